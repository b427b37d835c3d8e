"""Optimisation of whole plans: wall time, cycle time against the naive constant-speed
profile, push distances against Peshkin's covering-disk bound.

Targets: optimising a whole plan ≤ 1 s for the paper's parts (issue 5); the pie's
optimised push-grasp plan ≤ 100 ms p50 with a cycle time no worse than 6.87 s (issue 21).
"cold" is the first plan of a process; "p50" the median of 21 further runs. The last
row limits the jaws' jerk (CasADi's S-curves).
"""

from __future__ import annotations

import statistics
import time
from typing import Any

from algrasp.geometry.part import load_part
from algrasp.planning.analysis import analyse_part
from algrasp.planning.plans import make_plan
from algrasp.testing import shapes
from optimisation.execution import optimise_execution

PARTS: list[tuple[str, dict[str, Any], str]] = [
    ("pie (paper)", shapes.pie(5.0, 20.0, com=(0.0, 2.5)), "squeeze"),
    ("pie (paper)", shapes.pie(5.0, 20.0, com=(0.0, 2.5)), "push_grasp"),
    ("Fig. 11 disk, z=10°", shapes.disk_with_flats(5.0, 10.0), "squeeze"),
    ("rectangle 10x4", shapes.rectangle(10.0, 4.0), "push_grasp"),
    ("triangle r=5", shapes.regular_polygon(3, 5.0), "push_grasp"),
    ("Bezier cam", shapes.bezier_cam(), "push_grasp"),
]


def main() -> None:
    print(f"{'part':22} {'action':10} {'steps':>5} {'cold ms':>8} {'p50 ms':>8} {'cycle s':>8} {'naive s':>8}"
          "  push / bound (part unit)")
    for name, doc, action in PARTS:
        analysis = analyse_part(load_part(doc))
        plan = make_plan(analysis, action)  # type: ignore[arg-type]
        t = time.perf_counter()
        ex = optimise_execution(analysis, plan)
        cold = time.perf_counter() - t
        warm = []
        for _ in range(21):
            t = time.perf_counter()
            optimise_execution(analysis, plan)
            warm.append(time.perf_counter() - t)
        pushes = ", ".join(f"{s.push.distance:.2f}/{s.push.bound:.2f}" for s in ex.steps if s.push is not None) or "—"
        print(f"{name:22} {action:10} {len(plan.steps):5d} {1000 * cold:8.0f} {1000 * statistics.median(warm):8.0f} "
              f"{ex.cycle_time_s:8.3f} {ex.naive_cycle_time_s:8.3f}  {pushes}")


def jerk_limited() -> None:
    from optimisation.profile import profile_from_dict

    doc = shapes.pie(5.0, 20.0, com=(0.0, 2.5))
    analysis = analyse_part(load_part(doc))
    plan = make_plan(analysis, "push_grasp")
    free = optimise_execution(analysis, plan).cycle_time_s
    profile = profile_from_dict({"jaw_max_jerk_m_s3": 20.0})
    t = time.perf_counter()
    ex = optimise_execution(analysis, plan, profile)
    cold = time.perf_counter() - t
    t = time.perf_counter()
    optimise_execution(analysis, plan, profile)
    print(f"pie push_grasp, jaw jerk ≤ 20 m/s³: cold {1000 * cold:.0f} ms, warm {1000 * (time.perf_counter() - t):.0f} ms, "
          f"cycle {ex.cycle_time_s:.3f} s (no jerk limit: {free:.3f} s)")


if __name__ == "__main__":
    main()
    jerk_limited()
