"""Planning time (Algorithm A′ + gripper angles) and verification time.

Targets (issue 3): a 1,000-vertex random polygon planned (analysis + plan) ≤ 50 ms;
the Fig. 11 part with z = 0.25° (N ≈ 720) planned ≤ 200 ms. Also how time grows
with the number of pieces n and the plan length N.

Issue 21: analysis + both plans (squeeze and push-grasp, exact model), warm, for a
triangle, a rectangle and random 6–10-gons: targets ≤ 0.5 ms for the triangle and ≤ 2 ms
for the 10-gons (BerkeleyAutomation part-feeder: 2.7–5.5 s each, measured here).
"""

from __future__ import annotations

import statistics
import time
from typing import Any

from algrasp.geometry.part import load_part
from algrasp.planning.analysis import analyse_part
from algrasp.planning.plans import make_plan
from algrasp.testing import shapes


def timed(doc: dict[str, Any], action: str = "squeeze", repeats: int = 5) -> tuple[float, float, float, int]:
    """Median ms of (analysis, planning, verification) and the plan length."""
    rows = []
    for _ in range(repeats + 1):
        t = time.perf_counter()
        analysis = analyse_part(load_part(doc))
        t_analysis = time.perf_counter() - t
        plan = make_plan(analysis, action)  # type: ignore[arg-type]
        rows.append((t_analysis, plan.timings_s["planning"], plan.timings_s["verification"], len(plan.steps)))
    rows = rows[1:]
    med = [1000 * statistics.median(r[i] for r in rows) for i in range(3)]
    return med[0], med[1], med[2], rows[0][3]


def both_plans_ms(doc: dict[str, Any], repeats: int = 200) -> float:
    """Median ms of load + analysis + squeeze plan + push-grasp plan, after a warm-up."""
    times = []
    for _ in range(repeats + 10):
        t = time.perf_counter()
        analysis = analyse_part(load_part(doc))
        make_plan(analysis, "squeeze")
        make_plan(analysis, "push_grasp")
        times.append(time.perf_counter() - t)
    return 1000 * statistics.median(times[10:])


def small_parts() -> None:
    cases = [("triangle", shapes.regular_polygon(3, 5.0), 0.5), ("rectangle 10x4", shapes.rectangle(10.0, 4.0), 2.0)]
    cases += [(f"random {n}-gon", shapes.random_polygon(n, n), 2.0) for n in range(6, 11)]
    print("analysis + both plans, warm (issue 21):")
    for name, doc, target in cases:
        ms = both_plans_ms(doc)
        print(f"  {name:16s} {ms:6.2f} ms (target ≤ {target:g} ms; part-feeder 2.7–5.5 s: {2700 / ms:,.0f}× faster)")


def main() -> None:
    small_parts()
    a, p, v, n = timed(shapes.random_polygon(1000, 1))
    print(f"1,000-vertex random polygon: analysis {a:.2f} ms + planning {p:.2f} ms = {a + p:.2f} ms "
          f"(target ≤ 50 ms); N = {n}; verification {v:.2f} ms")
    a, p, v, n = timed(shapes.disk_with_flats(1.0, 0.25), repeats=3)
    print(f"Fig. 11 part, z = 0.25°: planning {p:.2f} ms (target ≤ 200 ms), N = {n}; "
          f"analysis {a:.2f} ms, verification {v:.2f} ms")
    print("growth with n (random polygons, squeeze):")
    for size in (100, 300, 1000, 3000):
        a, p, v, n = timed(shapes.random_polygon(size, 2))
        print(f"  vertices {size:5d}: analysis {a:7.2f} ms, planning {p:6.2f} ms, N = {n}")
    print("growth with N (Fig. 11 part):")
    for z in (8.0, 4.0, 2.0, 1.0, 0.5, 0.25):
        a, p, v, n = timed(shapes.disk_with_flats(1.0, z), repeats=3)
        print(f"  z = {z:5.2f}°: N = {n:4d}, planning {p:7.2f} ms ({1000 * p / n:.0f} µs per action), "
              f"verification {v:7.2f} ms")


if __name__ == "__main__":
    main()
