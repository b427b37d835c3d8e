"""Drawings as shops send them (issue 32): every file of tests/data/shops/{dxf,svg}
imported as delivered (no options) and compared with its truth (truth.json: decided by
rendering each file and looking, never by running the importer). Prints one row per file
with a miss, then the table per source program that the README shows.

    .venv/bin/python benchmarks/bench_shop_corpus.py
"""

from __future__ import annotations

import json
import sys
import time
from collections import defaultdict
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from algrasp.errors import AlgraspError  # noqa: E402
from algrasp.io.cad import list_parts  # noqa: E402

SHOPS = ROOT / "tests" / "data" / "shops"
BBOX_REL = 5e-3
"""A part's box agrees with the truth when both sides are within 0.5 %."""
MM = {"mm": 1.0, "in": 25.4, "cm": 10.0, "m": 1000.0, "um": 1e-3}


def corpus() -> list[tuple[Path, dict[str, Any]]]:
    """(file, truth) for every file with a truth entry."""
    out = []
    for folder in sorted(p for p in SHOPS.iterdir() if p.is_dir()):
        truth_file = folder / "truth.json"
        if truth_file.is_file():
            truth = json.loads(truth_file.read_text(encoding="utf-8"))
            out += [(folder / name, t) for name, t in sorted(truth.items()) if (folder / name).is_file()]
    return out


def judge(path: Path, truth: dict[str, Any]) -> tuple[str | None, float]:
    """None when the import matches the truth, else what differs; and the seconds taken."""
    t0 = time.perf_counter()
    try:
        out = list_parts(path.name, path.read_bytes())
    except AlgraspError as exc:
        seconds = time.perf_counter() - t0
        return (None if truth["kind"] == "none" else f"refused: {str(exc)[:160]}"), seconds
    seconds = time.perf_counter() - t0
    rows = out["parts"]
    if truth["kind"] == "none":
        return (f"{len(rows)} part(s) found in a drawing with none" if rows else None), seconds
    if len(rows) != truth["parts"]:
        return f"{len(rows)} parts, truth {truth['parts']}", seconds
    if truth["kind"] != "part":
        return None, seconds
    return _part_miss(rows[0], truth, path.suffix.lower()), seconds


def _part_miss(row: dict[str, Any], truth: dict[str, Any], suffix: str) -> str | None:
    if truth.get("holes") is not None and row["holes"] != truth["holes"]:
        return f"{row['holes']} holes, truth {truth['holes']}"
    if suffix == ".dxf" and truth.get("units") in MM and truth["units"] != row["units"]:  # SVG: always mm
        return f"units {row['units']}, truth {truth['units']}"
    if truth.get("bbox_mm"):
        k = MM.get(row["units"], 1.0)
        x0, y0, x1, y1 = row["bbox"]
        got = sorted([k * (x1 - x0), k * (y1 - y0)])
        want = sorted(float(v) for v in truth["bbox_mm"])
        if any(abs(g - w) > BBOX_REL * max(w, 1e-9) for g, w in zip(got, want)):
            return f"box {got[0]:.2f} × {got[1]:.2f} mm, truth {want[0]:.2f} × {want[1]:.2f}"
    return None


FAMILIES = ("SolidWorks", "Fusion 360", "Inventor", "AutoCAD", "LibreCAD", "QCAD", "FreeCAD", "OpenSCAD", "Inkscape",
            "Illustrator", "CorelDRAW", "KiCad", "SketchUp", "Onshape", "LightBurn", "maker.js", "dxfwrite", "ezdxf",
            "cairo", "matplotlib", "Eagle", "Rhino", "DraftSight", "BricsCAD", "Affinity", "svg.py")
"""Source programs as the README's table names them (the truth's ``program`` says more)."""


def family(program: str | None) -> str:
    """The program family a truth's ``program`` note names first (``other`` if none)."""
    text = (program or "").lower()
    hits = [(text.find(f.lower()), f) for f in FAMILIES if f.lower() in text]
    if "corel" in text and not hits:
        return "CorelDRAW"
    return min(hits)[1] if hits else ("unknown" if not text or text.startswith("unknown") else "other")


def main() -> None:
    rows = corpus()
    by_program: dict[str, list[bool]] = defaultdict(list)
    slowest = 0.0
    misses = 0
    for path, truth in rows:
        miss, seconds = judge(path, truth)
        slowest = max(slowest, seconds)
        by_program[f"{family(truth.get('program'))} ({path.suffix[1:]})"].append(miss is None)
        if miss is not None:
            misses += 1
            print(f"MISS {path.parent.name}/{path.name}: {miss}")
    sources = {line.split("|")[2].strip() for f in SHOPS.glob("*/SOURCES.md") for line in f.read_text().splitlines()
               if line.startswith("|") and not line.startswith(("| file", "|---", "| ---"))}
    print(f"\n{len(rows)} drawings from {len(sources)} repositories, {len(rows) - misses} right as delivered, "
          f"slowest {slowest:.2f} s\n")
    print("| source program | drawings | right as delivered |")
    print("|---|---|---|")
    for program, oks in sorted(by_program.items(), key=lambda kv: (-len(kv[1]), kv[0])):
        print(f"| {program} | {len(oks)} | {sum(oks)} |")


if __name__ == "__main__":
    main()
