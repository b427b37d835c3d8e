"""The default (robust) model at speed, issue 34: the figures of its "What it must show".

Warm medians of this process's CPU time (the machine is shared: wall time also counts
the other jobs on its cores; part-feeder's single-threaded times are wall ≈ CPU), one
process: analysis + squeeze plan + push-grasp plan (a refusal is timed all the same: it
is the answer) for a triangle and random
5–10-gons; a 1,000-vertex polygon (analysis + squeeze plan); a 50-cubic part against its
exact-model time; the Fig. 11 part at z = 1°. part-feeder (BerkeleyAutomation, the same
polygons) is not installable offline; its times are the ones measured side by side in the
issue (triangle 562 ms, random 5-gon 1,138 ms, warm) and are quoted, not re-run.

Each line is timed twice. First as the answer alone: ``make_plan`` returns the plan or
raises the refusal, whose limit search is left pending (it runs when the refusal's
limits or message are first read; conventions §8); this is what a Python caller that
only catches the refusal pays, and what ``limits="none"`` costs. Then as the CLI and HTTP
answer: the refusal's limits read as well (every physics limit, ~5–25 more analyses).
The targets were set before the physics ranges and their limits existed; each is
printed beside both figures. The last table compares the default ranges with one value
per range (each range's midpoint): the cost of physics as ranges.
"""

from __future__ import annotations

import statistics
import time
from typing import Any

from algrasp.errors import NotOrientableError
from algrasp.pipeline import WARM_UP_PART
from algrasp.planning.analysis import EXACT, ROBUST, Model, analyse_document
from algrasp.planning.physics import DEFAULT_PHYSICS, PARAMETERS
from algrasp.planning.plans import LimitsWanted, make_plan
from algrasp.testing import shapes

PART_FEEDER_MS = {"triangle": 562.0, "random 5-gon": 1138.0}
TRIANGLE = WARM_UP_PART  # the warm-up triangle every worker plans first


def _work(doc: dict[str, Any], model: Model, actions: tuple[str, ...], limits: LimitsWanted, read: bool) -> None:
    a = analyse_document(doc, model)
    for action in actions:
        try:
            make_plan(a, action, limits=limits)  # type: ignore[arg-type]
        except NotOrientableError as e:
            if read:
                _ = e.limits  # the refusal's limit search, as the CLI and HTTP show it


def median_ms(doc: dict[str, Any], model: Model = ROBUST, actions: tuple[str, ...] = ("squeeze", "push_grasp"),
              repeats: int = 30, limits: LimitsWanted = "refusal", read: bool = False) -> float:
    _work(doc, model, actions, limits, read)
    times = []
    for _ in range(repeats):
        t = time.process_time()
        _work(doc, model, actions, limits, read)
        times.append(time.process_time() - t)
    return 1000 * statistics.median(times)


def both(doc: dict[str, Any], model: Model = ROBUST, actions: tuple[str, ...] = ("squeeze", "push_grasp"),
         repeats: int = 30) -> tuple[float, float]:
    """(the plan or refusal alone, with the refusal's limits read)."""
    return median_ms(doc, model, actions, repeats), median_ms(doc, model, actions, repeats, read=True)


ONE_VALUE = Model(False, DEFAULT_PHYSICS.with_values(**{n: (0.5 * sum(getattr(DEFAULT_PHYSICS, n)),) * 2
                                                       for n in PARAMETERS}))
"""The default ranges collapsed to their midpoints: one value each."""


def ranges_table() -> None:
    print("physics as ranges against one value per range (analysis + both plans, limits none; target ≤ 1.5×)")
    for name, doc in (("triangle", TRIANGLE), ("random 7-gon", shapes.random_polygon(7, 3)),
                      ("50-cubic part", shapes.bezier_blob(50, 2)), ("pie 40°", shapes.pie(1.0, 40.0))):
        ranged, one = median_ms(doc, limits="none", repeats=15), median_ms(doc, ONE_VALUE, limits="none", repeats=15)
        print(f"  {name:16s} ranges {ranged:7.2f} ms   one value {one:7.2f} ms   {ranged / one:5.2f}×")


def main() -> None:
    print("default model (robust, default ranges), warm CPU medians: plan or refusal alone | with the refusal's limits read")
    print(f"  triangle, analysis only              {median_ms(TRIANGLE, actions=()):8.2f} ms")
    tri, tri_l = both(TRIANGLE)
    pf = PART_FEEDER_MS["triangle"]
    print(f"  triangle, analysis + both plans     {tri:8.2f} | {tri_l:6.2f} ms  (target ≤ 1 ms; part-feeder {pf:.0f} ms: "
          f"{pf / tri:,.0f}× | {pf / tri_l:,.0f}×)")
    ratios, ratios_l = [], []
    for n in range(5, 11):
        ms, ms_l = both(shapes.random_polygon(n, 3))
        ratios.append(PART_FEEDER_MS["random 5-gon"] / ms)
        ratios_l.append(PART_FEEDER_MS["random 5-gon"] / ms_l)
        alone = median_ms(shapes.random_polygon(n, 3), actions=())
        print(f"  random {n:2d}-gon, analysis + both plans {ms:6.2f} | {ms_l:6.2f} ms  ({ratios[-1]:,.0f}× | "
              f"{ratios_l[-1]:,.0f}× part-feeder's 5-gon); analysis only {alone:.2f} ms")
    print(f"  median speed-up on 5–10-gons: {statistics.median(ratios):,.0f}× | {statistics.median(ratios_l):,.0f}× "
          "(target ≥ 1,000×)")
    big, big_l = both(shapes.random_polygon(1000, 1), actions=("squeeze",), repeats=10)
    print(f"  1,000-vertex polygon, analysis + squeeze plan {big:7.2f} | {big_l:6.2f} ms (target ≤ 20 ms)")
    blob = shapes.bezier_blob(50, 2)
    (robust, robust_l), exact = both(blob, ROBUST, ("squeeze",), 10), median_ms(blob, EXACT, ("squeeze",), 10)
    print(f"  50-cubic part, analysis + squeeze plan: robust {robust:.2f} | {robust_l:.2f} ms, exact {exact:.2f} ms "
          f"= {robust / exact:.2f}× | {robust_l / exact:.2f}× (target ≤ 2×)")
    ms, ms_l = both(shapes.disk_with_flats(1.0, 1.0), actions=("squeeze",), repeats=10)
    print(f"  Fig. 11 part, z = 1°, analysis + squeeze plan {ms:7.2f} | {ms_l:6.2f} ms (target ≤ 30 ms)")
    ranges_table()


if __name__ == "__main__":
    main()
