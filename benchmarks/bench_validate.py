"""Drake validation figures: agreement, sim time ÷ wall time, and the 36-sample target.

Targets: a 36-sample validation of a 3-step plan ≤ 30 s on the 2-core machine (issue 4);
the pie's 36 samples ≤ 10 s and the 160 mm frame plate's (a real drawing,
``benchmarks/data/landrs-battery-plate.json``) ≤ 60 s, agreement unchanged (issue 21).
Prints agreement for the paper's pie part, a rectangle, an equilateral triangle, a random
polygon and a Bezier cam (centred placement), random placement, and push-grasp plans.

    python benchmarks/bench_validate.py                       # 36 samples, seed 1, all cases
    python benchmarks/bench_validate.py --samples 100 --seed 2 --only pie,cam

36 samples resolve agreement only to 3 %: one miss is 97 %. The ≥ 98 % target needs the
larger runs (100 samples resolve 1 %).

Plans are made on the robust model in the ideal cell (``IDEAL``: support μ 0.3, frictionless
jaws, 20 g, centred jaws), the cell these targets were set in: the default (real) cell
refuses most of these parts (conventions §8), and its plans are checked corner by corner
in ``bench_real_cell.py``. A refused case prints its reason instead of a row.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from algrasp.errors import NotOrientableError
from algrasp.geometry.arcforms import document, fig11_outline
from algrasp.planning.analysis import EXACT, IDEAL, analyse_document
from algrasp.planning.plans import make_plan
from algrasp.sim.validate import validate_plan
from algrasp.testing import shapes

FRAME = json.loads((Path(__file__).parent / "data" / "landrs-battery-plate.json").read_text())

CASES = [
    ("pie (paper)", shapes.pie(), "squeeze", "centred"),
    ("rectangle 10x4 mm", shapes.rectangle(10, 4), "squeeze", "centred"),
    ("equilateral triangle", shapes.regular_polygon(3, 6), "squeeze", "centred"),
    ("random polygon", {**shapes.random_polygon(7, 4), "polygon": [[6 * x, 6 * y] for x, y in shapes.random_polygon(7, 4)["polygon"]]},
     "squeeze", "centred"),
    ("Bezier cam", shapes.bezier_cam(), "squeeze", "centred"),
    ("pie (paper)", shapes.pie(), "squeeze", "random"),
    ("rectangle 10x4 mm", shapes.rectangle(10, 4), "squeeze", "random"),
    ("pie, com (0, 2.5)", shapes.pie(com=(0.0, 2.5)), "push_grasp", "centred"),
    ("Bezier cam", shapes.bezier_cam(), "push_grasp", "centred"),
    ("Fig. 11, cubic arcs", document(fig11_outline(), "cubic"), "squeeze", "centred"),
    ("Fig. 11, exact arcs", document(fig11_outline(), "arc"), "squeeze", "centred"),
    ("frame plate 160 mm", FRAME, "squeeze", "centred"),
]


def main(samples: int = 36, seed: int = 1, only: tuple[str, ...] = (), exact: bool = False) -> None:
    """Agreement = simulated final within 1° + the plan's final uncertainty of a claimed one.
    The worker pool is started first (pydrake imports, ~2–3 s once per process), so each
    row's wall time is the validation's own, as in a warm service."""
    t = time.perf_counter()
    warm = analyse_document(shapes.pie(), IDEAL)
    validate_plan(warm, make_plan(warm, "squeeze"), samples=2, seed=0)
    print(f"worker pool start-up and a 2-sample warm-up: {time.perf_counter() - t:.1f} s")
    print(f"{'part':24s} {'action':10s} {'placement':9s} {'N':>3s} {'±deg':>6s} {'agree':>7s} {'clear':>7s} {'wall s':>7s} "
          f"{'sim/wall':>8s}  ({'exact' if exact else 'robust'} model, ideal cell)")
    for name, doc, action, placement in CASES:
        if only and not any(key in name.lower() for key in only):
            continue
        analysis = analyse_document(doc, EXACT if exact else IDEAL)
        try:
            plan = make_plan(analysis, action, limits="none")  # type: ignore[arg-type]
        except NotOrientableError as e:
            print(f"{name:24s} {action:10s} {placement:9s} refused: {e.reason}", flush=True)
            continue
        t = time.perf_counter()
        v = validate_plan(analysis, plan, samples=samples, seed=seed, placement=placement)  # type: ignore[arg-type]
        wall = time.perf_counter() - t
        print(f"{name:24s} {action:10s} {placement:9s} {len(plan.steps):3d} {plan.to_dict()['final_uncertainty_deg']:6.2f} "
              f"{100 * v.agreement:6.1f}% {100 * v.agreement_clear:6.1f}% {wall:7.1f} {v.sim_seconds / v.wall_seconds:8.2f}",
              flush=True)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=36)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--only", default="", help="comma-separated part-name fragments, e.g. pie,cam")
    parser.add_argument("--exact", action="store_true", help="the paper's exact model (for comparison)")
    args = parser.parse_args()
    main(args.samples, args.seed, tuple(k.strip().lower() for k in args.only.split(",") if k.strip()), args.exact)
