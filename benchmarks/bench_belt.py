"""Fence designs simulated on a belt in Drake (conventions §9, README "Conveyor fences").

For each part (the square, a rectangle, a hexagon and six curved parts of lines and arcs:
two rounded rectangles, a stadium, a rounded triangle, the battery plate and the bracket)
and its fences option (alternating rails, or ``same_rail``: the ``rails`` column): the
fence design with its exit guide (default 2°), then ``--samples``
seeded starts (random orientation and lateral position) on the belt; a sample agrees when
the part's orientation after it has left every fence and the exit guide is within the
document's claimed uncertainty + 0.25° of a claimed final orientation (modulo the
symmetry). Prints one row per part: rails, fences, samples, agreement, worst error, the
claim, belt speed, support and fence friction. Parts run in ``--workers`` processes;
``--only NAME ...`` runs the parts of those names.

    python benchmarks/bench_belt.py --samples 10 --workers 2 > belt.txt
    python benchmarks/bench_belt.py --samples 10 --only bracket rounded-triangle-30-r3
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def _rounded_rectangle(w: float, h: float, r: float) -> dict[str, Any]:
    """A w × h rectangle with corner arcs of radius r: a generalized polygon (lines and arcs)."""
    def arc(cx: float, cy: float, a0: float) -> dict[str, Any]:
        return {"type": "arc", "center": [cx, cy], "radius": r, "start_deg": a0, "end_deg": a0 + 90}

    def line(a: list[float], b: list[float]) -> dict[str, Any]:
        return {"type": "line", "start": a, "end": b}

    return {"name": f"rounded-{w:g}x{h:g}-r{r:g}", "units": "mm", "boundary": [
        line([r, 0], [w - r, 0]), arc(w - r, r, -90), line([w, r], [w, h - r]), arc(w - r, h - r, 0),
        line([w - r, h], [r, h]), arc(r, h - r, 90), line([0, h - r], [0, r]), arc(r, r, 180)]}


def _stadium(w: float, h: float) -> dict[str, Any]:
    """Two semicircles of diameter h joined by straight sides, w long."""
    r = h / 2
    return {"name": f"stadium-{w:g}x{h:g}", "units": "mm", "boundary": [
        {"type": "line", "start": [r, 0], "end": [w - r, 0]},
        {"type": "arc", "center": [w - r, r], "radius": r, "start_deg": -90, "end_deg": 90},
        {"type": "line", "start": [w - r, h], "end": [r, h]},
        {"type": "arc", "center": [r, r], "radius": r, "start_deg": 90, "end_deg": 270}]}


def _rounded_regular_polygon(n: int, side: float, r: float) -> dict[str, Any]:
    """A regular n-gon of the given side (centred at the origin, one side at the bottom)
    with every corner replaced by an arc of radius r tangent to its two sides: n arcs of
    sweep 360°/n (counter-clockwise) joined by n straight sides, each side − 2r·tan(π/n) long."""
    from algrasp.geometry.angles import to_deg

    circum = side / (2 * math.sin(math.pi / n))
    inset = circum - r / math.cos(math.pi / n)  # centroid to each arc's centre
    corners = [-math.pi / 2 + math.pi / n + 2 * math.pi * k / n for k in range(n)]
    centers = [(inset * math.cos(t), inset * math.sin(t)) for t in corners]

    def on_arc(k: int, a: float) -> list[float]:
        return [centers[k][0] + r * math.cos(a), centers[k][1] + r * math.sin(a)]

    boundary: list[dict[str, Any]] = []
    for k, t in enumerate(corners):  # the arc at corner k, then the side to corner k + 1 (outward normal t + π/n)
        a0, a1 = t - math.pi / n, t + math.pi / n
        boundary.append({"type": "arc", "center": list(centers[k]), "radius": r,
                         "start_deg": to_deg(a0), "end_deg": to_deg(a1)})
        boundary.append({"type": "line", "start": on_arc(k, a1), "end": on_arc((k + 1) % n, a1)})
    names = {3: "triangle", 4: "square", 6: "hexagon"}
    return {"name": f"rounded-{names.get(n, f'{n}-gon')}-{side:g}-r{r:g}", "units": "mm", "boundary": boundary}


def parts() -> list[tuple[dict[str, Any], dict[str, Any]]]:
    """(part document, fences options): the square, a rectangle, a regular hexagon and six
    curved parts (lines and arcs): two rounded rectangles, a stadium, a rounded triangle, the
    battery plate (a real drawing's part) and the bracket example, the last on one rail
    (``same_rail``: it has no alternating design). Random polygons, pie-20, the Fig. 11
    part, gear-12 and the half-disk have no design once the exit turns are modelled."""
    square = json.loads((ROOT / "tests" / "data" / "fences" / "square-30.json").read_text())
    hexagon = {"name": "hexagon-15", "units": "mm",  # unrounded: rounded to 1e-6 mm the robust model refuses it
               "polygon": [[15 * math.cos(k * math.pi / 3), 15 * math.sin(k * math.pi / 3)] for k in range(6)]}
    examples = ROOT / "algrasp" / "examples"
    battery = json.loads((examples / "real" / "battery-plate.json").read_text())
    bracket = json.loads((examples / "bracket.json").read_text())
    return [(square, {}), ({"name": "rect-40x20", "units": "mm", "boundary": [[0, 0], [40, 0], [40, 20], [0, 20]]}, {}),
            (hexagon, {}), (_rounded_rectangle(40, 20, 4), {}), (_stadium(40, 16), {}), (_rounded_rectangle(50, 20, 8), {}),
            (_rounded_regular_polygon(3, 30, 3), {}), (battery, {}), (bracket, {"same_rail": True})]


def run(item: tuple[dict[str, Any], dict[str, Any]], samples: int, seed: int) -> dict[str, Any]:
    """One part's row (or its refusal)."""
    from algrasp import api
    from algrasp.errors import AlgraspError

    doc, options = item
    try:
        v = api.validate_fences(doc, samples=samples, seed=seed, **options).to_dict()
        layout: dict[str, Any] = dict(api.fences(doc, **options).to_dict())
    except AlgraspError as exc:
        return {"part": doc.get("name"), "rails": "same" if options.get("same_rail") else "alternating",
                "error": str(exc)}
    errs = [s["error_deg"] for s in v["samples"]]
    return {"part": doc.get("name"), "rails": "same" if options.get("same_rail") else "alternating",
            "model": layout["model"], "fences": len(layout["fences"]),
            "samples": len(errs), "agree": sum(s["agrees"] for s in v["samples"]),
            "on_last_fence": v["agreement_on_last_fence"], "worst_deg": max(errs),
            "claim_deg": v["final_uncertainty_deg"], "exit_deg": (layout["exit"] or {}).get("steepness_deg"),
            "belt_m_s": v["belt_speed_m_s"], "support": v["support_friction"], "fence": v["fence_friction"],
            "wall_s": v["wall_seconds"]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=12)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--only", nargs="*", metavar="NAME", help="run only these parts (by name)")
    args = ap.parse_args()
    items = [p for p in parts() if not args.only or p[0].get("name") in args.only]
    print("| part | rails | model | fences | samples | agreement | worst error | claim ± | exit guide "
          "| on last fence | belt speed | support μ | fence μ | wall |")
    print("|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|", flush=True)
    with ProcessPoolExecutor(args.workers) as pool:  # a row as each part finishes
        futures = [pool.submit(run, item, args.samples, args.seed) for item in items]
        for f in as_completed(futures):
            r = f.result()
            print(json.dumps(r), file=sys.stderr, flush=True)
            if "error" in r:
                print(f"| {r['part']} | {r['rails']} | refused: {r['error'][:80]} |||||||||||", flush=True)
                continue
            print(f"| {r['part']} | {r['rails']} | {r['model']} | {r['fences']} | {r['samples']} | {r['agree']}/{r['samples']} "
                  f"({r['agree'] / r['samples']:.0%}) | {r['worst_deg']:.2f}° | {r['claim_deg']:.2f}° + 0.25° "
                  f"| {r['exit_deg']:g}° | {r['on_last_fence']:.0%} | {r['belt_m_s']:.3g} m/s | {r['support']:.3g} "
                  f"| {r['fence']:.3g} | {r['wall_s']:.0f} s |", flush=True)


if __name__ == "__main__":
    main()
