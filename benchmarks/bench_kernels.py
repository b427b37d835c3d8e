"""The compiled kernels (algrasp.compiled: ``KERNELS`` for planning, ``GEOMETRY`` for
geometry) against the Python/numpy path they reproduce bit for bit (issue 34: the
default robust model's work unit, analysis + squeeze plan + push-grasp plan).

Each stage of the work unit is timed on fresh inputs (a new part, so no cached property
of the last run is read), compiled and then with every hook switched off in-process
(:func:`algrasp.testing.kernels.reference_path`, one interpreter for both); CPU medians.
The kernels fuse whole passes (the cells to the bounds in one call, compositions in one
call each), so the stages, not the kernels one by one, are what can be compared.

    python benchmarks/bench_kernels.py [--part triangle|7-gon|10-gon]
"""

from __future__ import annotations

import argparse
import contextlib
import statistics
import time
from collections.abc import Callable
from typing import Any

from algrasp.compiled import GEOMETRY, KERNELS
from algrasp.errors import NotOrientableError
from algrasp.geometry.functions import analyse
from algrasp.geometry.part import load_part
from algrasp.pipeline import WARM_UP_PART
from algrasp.planning.analysis import ROBUST, analyse_document, robust_analysis
from algrasp.planning.deadband import part_terms
from algrasp.planning.plans import make_plan
from algrasp.testing import shapes
from algrasp.testing.kernels import reference_path

PARTS: dict[str, dict[str, Any]] = {"triangle": WARM_UP_PART, "7-gon": shapes.random_polygon(7, 3),
                                    "10-gon": shapes.random_polygon(10, 3)}


def median_ms(fn: Callable[[], object], reps: int = 300) -> float:
    for _ in range(reps // 10):
        fn()
    times = []
    for _ in range(reps):
        t = time.process_time()
        fn()
        times.append(time.process_time() - t)
    return 1e3 * statistics.median(times)


def stages(doc: dict[str, Any]) -> dict[str, Callable[[], object]]:
    """Each stage of one work unit, on a freshly loaded part each call."""
    tol, physics = analyse_document(doc).tol, ROBUST.physics

    def fresh() -> Any:
        return load_part(doc, tol, snap=True)

    def functions() -> Any:
        p = fresh()
        return p, analyse("diameter", p.hull, p.center_of_mass, p.size, tol), analyse("radius", p.hull,
                                                                                      p.center_of_mass, p.size, tol)

    def plan(action: str) -> Callable[[], None]:
        a = analyse_document(doc)  # fresh per run would time the analysis too: one analysis, its plan made again

        def run() -> None:
            with contextlib.suppress(NotOrientableError):
                make_plan(a, action, limits="none")
        return run

    def unit() -> None:
        a = analyse_document(doc)
        for action in ("squeeze", "push_grasp"):
            with contextlib.suppress(NotOrientableError):
                make_plan(a, action, limits="none")

    return {"load part": lambda: fresh().size, "+ d and r": functions, "+ part terms": lambda: part_terms(fresh(), tol),
            "+ robust analysis": lambda: robust_analysis(*functions(), physics, tol),
            "squeeze plan": plan("squeeze"), "push-grasp plan": plan("push_grasp"), "work unit": unit}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--part", choices=sorted(PARTS), default="triangle")
    args = parser.parse_args()
    if KERNELS is None and GEOMETRY is None:
        print("compiled kernels not built (or ALGRASP_PURE set): nothing to compare")
        return
    print(f"{args.part}: ms per call (CPU medians)")
    print(f"{'stage':<20}{'compiled':>10}{'reference':>11}{'saved':>8}")
    for name, fn in stages(PARTS[args.part]).items():
        fast = median_ms(fn)
        with reference_path():
            slow = median_ms(fn)
        print(f"{name:<20}{fast:>10.4f}{slow:>11.4f}{1 - fast / slow:>8.0%}")


if __name__ == "__main__":
    main()
