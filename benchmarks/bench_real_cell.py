"""Plans that hold in a real cell (conventions §8), checked in Drake.

For seven kinds of part (pie-20, the Fig. 11 part, the bracket — a generalized polygon —,
a lens, a 40° pie, two random polygons) and both actions: plan in the default cell; if
refused, print the limits and plan again at the first limit found (placement centred, or
the profile tolerance, or the jaw friction); then simulate the plan at every corner of
its ranges (the centre of mass on its disk's rim, random placement when the plan allows
any) and report how many samples end within the claim + 0.25°.

Then, for the Fig. 11 part, pie-20 and a random polygon: the largest jaw friction for a
squeeze plan in the ideal cell with jaw friction, and a Drake run at that friction.

Usage: ``python benchmarks/bench_real_cell.py [--samples N] [--workers W] [--quick]``.
Prints a Markdown table (the README's) and takes about 20 minutes on 2 cores.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path
from typing import Any

import numpy as np

from algrasp.errors import NotOrientableError
from algrasp.geometry.arcforms import document, fig11_outline, pie_outline
from algrasp.planning.analysis import Model, analyse_document
from algrasp.planning.cells import Cell, sim_cells
from algrasp.planning.physics import DEFAULT_PHYSICS, IDEAL_CELL, Physics
from algrasp.planning.plans import make_plan
from algrasp.sim.config import DEFAULT_SIM
from algrasp.sim.validate import validate_cells

ROOT = Path(__file__).resolve().parents[1]
SLACK_DEG = 0.25


def _lens() -> dict[str, Any]:
    def centre(R: float, above: bool) -> float:
        return math.sqrt(R * R - 16.0) * (-1 if above else 1)
    cy1, cy2 = centre(5.0, True), centre(9.0, False)
    a1 = math.degrees(math.atan2(-cy1, 4.0))
    lo0, lo1 = math.degrees(math.atan2(-cy2, -4.0)), math.degrees(math.atan2(-cy2, 4.0))
    return {"name": "lens", "units": "mm", "boundary": [
        {"type": "arc", "center": [0.0, cy1], "radius": 5.0, "start_deg": a1, "end_deg": 180.0 - a1},
        {"type": "arc", "center": [0.0, cy2], "radius": 9.0, "start_deg": lo0, "end_deg": lo1}]}


def _random_polygon(seed: int, n: int = 7, size_mm: float = 20.0) -> dict[str, Any]:
    """A star-shaped polygon: n sorted random angles, radii in [0.5, 1]·size/2."""
    rng = np.random.default_rng(seed)
    a = np.sort(rng.uniform(0.0, 2 * math.pi, n))
    r = rng.uniform(0.5, 1.0, n) * size_mm / 2
    return {"name": f"random-{seed}", "units": "mm", "polygon": np.column_stack([r * np.cos(a), r * np.sin(a)]).round(4).tolist()}


def parts() -> list[dict[str, Any]]:
    pie20 = json.loads((ROOT / "algrasp" / "examples" / "pie-20.json").read_text())
    bracket = json.loads((ROOT / "algrasp" / "examples" / "bracket.json").read_text())
    fig11 = {**document(fig11_outline(), "arc"), "name": "fig11", "units": "mm"}
    pie40 = {**document(pie_outline(half_deg=40.0), "arc"), "name": "pie40", "units": "mm"}
    return [pie20, fig11, bracket, _lens(), pie40, _random_polygon(3), _random_polygon(8)]


def _relaxed(limits: dict[str, Any], physics: Physics) -> Physics | None:
    """The cell a refusal's limits point to, nearest first."""
    if limits.get("placement_centred"):
        return physics.with_values(placement="centred")
    prof = limits.get("profile_tolerance_max") or {}
    if prof.get("value"):
        return physics.with_values(profile_tolerance=0.9 * prof["value"])
    jaw = limits.get("jaw_friction_max") or {}
    if jaw.get("value") is not None:
        return physics.with_values(jaw_friction=(0.0, 0.9 * jaw["value"]))
    ideal = limits.get("ideal_cell") or {}
    if ideal.get("orientable"):
        mid = {k: (0.5 * sum(getattr(physics, k)),) * 2 for k in ("support_friction", "part_mass_kg", "grip_force_n")}
        return physics.with_values(**mid, jaw_friction=(0.0, 0.0), profile_tolerance=0.0, com_tolerance=0.0,
                                   placement="centred")
    return None


def plan_in_cell(doc: dict[str, Any], action: str) -> tuple[Any, Any, Physics, str]:
    """(analysis, plan or None, physics used, note)."""
    physics = DEFAULT_PHYSICS
    try:
        a = analyse_document(doc, Model(physics=physics))
        return a, make_plan(a, action), physics, "default cell"  # type: ignore[arg-type]
    except NotOrientableError as e:
        relaxed = _relaxed(e.limits or {}, physics)
        note = f"refused: {(e.limits or {}).get('advice', e.message)[:120]}"
        if relaxed is None:
            return None, None, physics, note
        try:
            a = analyse_document(doc, Model(physics=relaxed))
            return a, make_plan(a, action), relaxed, note + " → planned at that limit"  # type: ignore[arg-type]
        except NotOrientableError as e2:
            return None, None, relaxed, note + f" → still refused ({e2.reason})"


def simulate(analysis: Any, plan: Any, physics: Physics, cells: list[Cell], samples: int, workers: int) -> Any:
    placement = "random" if physics.placement == "any" else "centred"
    return validate_cells(analysis, plan, cells, samples, 0, placement, SLACK_DEG, DEFAULT_SIM, workers)  # type: ignore[arg-type]


def corner_table(samples: int, workers: int, quick: bool) -> None:
    print("| part | action | cell | plan | corners | samples within claim + 0.25° | worst miss (°) | wall (s) |")
    print("|---|---|---|---|---|---|---|---|")
    for doc in parts()[: 3 if quick else None]:
        for action in ("squeeze", "push_grasp"):
            t0 = time.perf_counter()
            a, plan, physics, note = plan_in_cell(doc, action)
            if plan is None:
                print(f"| {doc['name']} | {action} | {note} | — | — | — | — | — |", flush=True)
                continue
            band = a.robust.band
            cells = sim_cells("corners", physics, band.com_tolerance, 1, 0)
            v = simulate(a, plan, physics, cells[:4] if quick else cells, samples, workers)
            worst = max(c["worst_error_deg"] for c in v.cells)
            ok = sum(s.agrees for s in v.samples)
            print(f"| {doc['name']} | {action} | {note} | {len(plan.steps)} steps, ±{math.degrees(plan.final_uncertainty):.2f}° "
                  f"| {len(cells)} | {ok}/{len(v.samples)} ({100 * ok / len(v.samples):.0f} %) | {worst:.2f} "
                  f"| {time.perf_counter() - t0:.0f} |", flush=True)


def jaw_limit_runs(samples: int, workers: int) -> None:
    print("\n| part | largest jaw μ for a squeeze (ideal cell otherwise) | Drake at that μ: within claim + 0.25° | worst miss (°) |")
    print("|---|---|---|---|")
    for doc in (parts()[1], parts()[0], parts()[5]):
        base = IDEAL_CELL
        a = analyse_document(doc, Model(physics=base))
        try:
            plan = make_plan(a, "squeeze", limits="headline")
        except NotOrientableError as e:
            print(f"| {doc['name']} | refused: {e.message[:80]} | — | — |")
            continue
        mu = plan.limits["jaw_friction_max"]["value"]  # type: ignore[index]
        at = base.with_values(jaw_friction=(0.0, mu))
        a2 = analyse_document(doc, Model(physics=at))
        plan2 = make_plan(a2, "squeeze")
        cell = Cell(at.with_values(jaw_friction=(mu, mu)), (0.0, 0.0), f"jaw_friction={mu:.3g}")
        v = simulate(a2, plan2, at, [cell], samples, workers)
        ok = sum(s.agrees for s in v.samples)
        print(f"| {doc['name']} | {mu:.3f} | {ok}/{len(v.samples)} | {v.cells[0]['worst_error_deg']:.2f} |", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=int, default=2, help="samples per corner")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--quick", action="store_true", help="three parts, four corners")
    args = ap.parse_args()
    corner_table(args.samples, args.workers, args.quick)
    jaw_limit_runs(max(args.samples, 6), args.workers)


if __name__ == "__main__":
    main()
