"""The default (robust) model at speed, issue 34: the figures of its "What it must show".

Warm medians, one process: analysis + squeeze plan + push-grasp plan (a refusal is timed
all the same: it is the answer, and under the default ranges it carries its limit search) for a triangle and random
5–10-gons; a 1,000-vertex polygon (analysis + squeeze plan); a 50-cubic part against its
exact-model time; the Fig. 11 part at z = 1°. part-feeder (BerkeleyAutomation, the same
polygons) is not installable offline; its times are the ones measured side by side in the
issue (triangle 562 ms, random 5-gon 1,138 ms, warm) and are quoted, not re-run.
"""

from __future__ import annotations

import contextlib
import statistics
import time
from typing import Any

from algrasp.errors import NotOrientableError
from algrasp.pipeline import WARM_UP_PART
from algrasp.planning.analysis import EXACT, ROBUST, Model, analyse_document
from algrasp.planning.plans import make_plan
from algrasp.testing import shapes

PART_FEEDER_MS = {"triangle": 562.0, "random 5-gon": 1138.0}
TRIANGLE = WARM_UP_PART  # the warm-up triangle every worker plans first


def _work(doc: dict[str, Any], model: Model, actions: tuple[str, ...]) -> None:
    a = analyse_document(doc, model)
    for action in actions:
        with contextlib.suppress(NotOrientableError):
            make_plan(a, action)  # type: ignore[arg-type]


def median_ms(doc: dict[str, Any], model: Model = ROBUST, actions: tuple[str, ...] = ("squeeze", "push_grasp"),
              repeats: int = 30) -> float:
    _work(doc, model, actions)
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        _work(doc, model, actions)
        times.append(time.perf_counter() - t)
    return 1000 * statistics.median(times)


def main() -> None:
    print("default model (robust, default ranges), warm medians")
    print(f"  triangle, analysis only              {median_ms(TRIANGLE, actions=()):8.2f} ms")
    tri = median_ms(TRIANGLE)
    pf = PART_FEEDER_MS["triangle"]
    print(f"  triangle, analysis + both plans     {tri:8.2f} ms  (target ≤ 1 ms; part-feeder {pf:.0f} ms: {pf / tri:,.0f}×)")
    ratios = []
    for n in range(5, 11):
        ms = median_ms(shapes.random_polygon(n, 3))
        ratios.append(PART_FEEDER_MS["random 5-gon"] / ms)
        alone = median_ms(shapes.random_polygon(n, 3), actions=())
        print(f"  random {n:2d}-gon, analysis + both plans {ms:6.2f} ms  ({ratios[-1]:,.0f}× part-feeder's 5-gon); "
              f"analysis only {alone:.2f} ms")
    print(f"  median speed-up on 5–10-gons: {statistics.median(ratios):,.0f}× (target ≥ 1,000×)")
    big = median_ms(shapes.random_polygon(1000, 1), actions=("squeeze",), repeats=10)
    print(f"  1,000-vertex polygon, analysis + squeeze plan {big:7.2f} ms (target ≤ 20 ms)")
    blob = shapes.bezier_blob(50, 2)
    robust, exact = median_ms(blob, ROBUST, ("squeeze",), 10), median_ms(blob, EXACT, ("squeeze",), 10)
    print(f"  50-cubic part, analysis + squeeze plan: robust {robust:.2f} ms, exact {exact:.2f} ms "
          f"= {robust / exact:.2f}× (target ≤ 2×)")
    fig11 = shapes.disk_with_flats(1.0, 1.0)
    ms = median_ms(fig11, actions=("squeeze",), repeats=10)
    print(f"  Fig. 11 part, z = 1°, analysis + squeeze plan {ms:7.2f} ms (target ≤ 30 ms)")


if __name__ == "__main__":
    main()
