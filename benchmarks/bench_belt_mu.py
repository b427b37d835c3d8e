"""Fence designs in Drake at a chosen part–fence friction (conventions §9, README "Conveyor fences").

The designs of ``bench_belt.py``'s parts (made for the default fence friction range
0.1–0.3) simulated with the part–wall μ fixed at each ``--mu`` (the bench uses the range's
middle), ``--samples`` seeded starts each: one row per part and μ with the fences,
agreement past the exit guide and on the last fence, the worst error, the claim, the belt
speed and the wall time. A part refused by the planner prints its refusal.

    python benchmarks/bench_belt_mu.py --mu 0.1 0.3 --samples 10 --only stadium-40x16
    python benchmarks/bench_belt_mu.py --mu 0.3 --samples 10 --only "battery plate (LANDRS)" --same-rail
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))


def main() -> None:
    from bench_belt import parts

    from algrasp import api
    from algrasp.errors import AlgraspError
    from algrasp.geometry.angles import to_deg
    from algrasp.sim.belt import validate_fences

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mu", type=float, nargs="+", default=[0.1, 0.3])
    ap.add_argument("--samples", type=int, default=10)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--only", nargs="+")
    ap.add_argument("--same-rail", action="store_true", help="consecutive fences may share a rail")
    args = ap.parse_args()
    print("| part | rails | fences (deg) | fence μ | agreement | on last fence | worst error | claim ± | belt speed | wall |")
    print("|---|---|---|---:|---:|---:|---:|---:|---:|---:|")
    for doc, options in parts():
        if args.only and doc["name"] not in args.only:
            continue
        options = {**options, **({"same_rail": True} if args.same_rail else {})}
        rails = "same" if options.get("same_rail") else "alternating"
        try:
            layout, analysis = api.fences(doc, **options), api.analyse(doc)
        except AlgraspError as exc:
            print(f"| {doc['name']} | {rails} | refused: {exc} |")
            continue
        angles = ", ".join(f"{float(to_deg(a)):.2f}" for a in layout.design.angles)
        assert analysis.robust is not None  # the bench's parts are planned in the robust model
        physics = analysis.robust.physics
        for mu in args.mu:
            v = validate_fences(analysis.part, layout, physics, args.samples, args.seed, wall_friction=mu)
            worst = max(s.error_deg for s in v.samples)
            agree = sum(s.agrees for s in v.samples)
            print(f"| {doc['name']} | {rails} | {angles} | {v.fence_friction:g} | {agree}/{len(v.samples)} | "
                  f"{v.agreement_on_last_fence:.0%} | {worst:.2f}° | {v.final_uncertainty_deg:.2f}° | "
                  f"{v.belt_speed_m_s:.3g} m/s | {v.wall_seconds:.0f} s |", flush=True)


if __name__ == "__main__":
    main()
