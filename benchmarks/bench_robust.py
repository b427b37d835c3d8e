"""Analysis + planning time with the dead band on (robust model, conventions §7) against
the exact model, for the issue-2 benchmark parts.

Target (issue 16): within 2× of the exact model's analysis times (1,000-vertex polygon
12–14 ms, 50 cubic Bezier segments 42–45 ms), planning included.
"""

from __future__ import annotations

import contextlib
import statistics
import time
from typing import Any

from algrasp.errors import NotOrientableError
from algrasp.geometry.arcforms import document, fig11_outline
from algrasp.pipeline import WARM_UP_PART
from algrasp.planning.analysis import EXACT, ROBUST, Model, analyse_document
from algrasp.planning.plans import make_plan
from algrasp.testing import shapes


def median_ms(doc: dict[str, Any], model: Model, plan: bool, repeats: int = 15) -> float:
    def once() -> None:
        a = analyse_document(doc, model)
        if plan:
            with contextlib.suppress(NotOrientableError):  # timed all the same
                make_plan(a, "squeeze")

    once()  # warm caches and imports
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        once()
        times.append(time.perf_counter() - t)
    return 1000 * statistics.median(times)


def main() -> None:
    cases = [("1,000-vertex random polygon", shapes.random_polygon(1000, 1)),
             ("50 cubic Bezier segments", shapes.bezier_blob(50, 2)),
             ("Fig. 11 part, cubic arcs", document(fig11_outline(), "cubic")),
             ("Fig. 11 part, 360-gon", document(fig11_outline(), "360gon"))]
    print(f"{'part':30s} {'exact analysis':>15s} {'robust analysis':>16s} {'exact + plan':>13s} {'robust + plan':>14s}  (ms)")
    for name, doc in cases:
        row = [median_ms(doc, m, p) for p in (False, True) for m in (EXACT, ROBUST)]
        print(f"{name:30s} {row[0]:15.2f} {row[1]:16.2f} {row[2]:13.2f} {row[3]:14.2f}   {_steps(doc)}")
    _refusals()


def _refusals() -> None:
    """A refusal under the default ranges carries every limit (the advice): one limit
    search per range, each probe one robust analysis and plan."""
    print(f"\n{'refused plan (with its limits)':30s} {'median ms':>10s}")
    for name, doc, action in (("triangle, squeeze", WARM_UP_PART, "squeeze"),
                              ("random 5-gon, squeeze", shapes.random_polygon(5, 3), "squeeze"),
                              ("random 5-gon, push-grasp", shapes.random_polygon(5, 3), "push_grasp")):
        a = analyse_document(doc, ROBUST)
        times = []
        for _ in range(5):
            t = time.perf_counter()
            try:
                make_plan(a, action)  # type: ignore[arg-type]
            except NotOrientableError as e:
                _ = e.limits  # the search runs when the limits are first read
            times.append(time.perf_counter() - t)
        print(f"{name:30s} {1000 * statistics.median(times):10.1f}")


def _steps(doc: dict[str, Any]) -> str:
    out = []
    for label, model in (("exact", EXACT), ("robust", ROBUST)):
        try:
            out.append(f"{label} {len(make_plan(analyse_document(doc, model), 'squeeze').steps)} steps")
        except NotOrientableError as e:
            out.append(f"{label}: {e.reason}")
    return ", ".join(out)


if __name__ == "__main__":
    main()
