"""Robust documents of a fixed corpus, for comparing answers before and after a speed
change (issue 34): every analysis document and both plans (or refusals) with every
physics limit, written as one JSON file; ``--diff A B`` lists every field that differs.

The corpus: the bundled examples, 13 generated parts (algrasp.testing.shapes) and each
part of the real drawings in tests/data/real and of every tenth shop drawing in
tests/data/shops (and the CAMotics and Crickit sheets): the first part of each sheet.

    python benchmarks/corpus_documents.py OUT.json [--only NAME ...]
    python benchmarks/corpus_documents.py --diff BEFORE.json AFTER.json
"""

from __future__ import annotations

import argparse
import json
import math
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from algrasp.errors import AlgraspError, NotOrientableError
from algrasp.planning.analysis import ROBUST, analyse_document
from algrasp.planning.plans import make_plan
from algrasp.testing import shapes

ROOT = Path(__file__).resolve().parents[1]


def corpus() -> Iterator[tuple[str, dict[str, Any]]]:
    """(name, part document) of every corpus part."""
    for path in sorted((ROOT / "algrasp" / "examples").rglob("*.json")):
        yield f"example/{path.stem}", json.loads(path.read_text())
    generated = {"triangle": shapes.regular_polygon(3), "rectangle-3x1": shapes.rectangle(3.0, 1.0),
                 "square": shapes.rectangle(1.0, 1.0), "hexagon": shapes.regular_polygon(6),
                 "pie-20": shapes.pie(5.0, 20.0), "pie-40": shapes.pie(1.0, 40.0),
                 "fig11-z1": shapes.disk_with_flats(1.0, 1.0), "fig11-z10": shapes.disk_with_flats(1.0, 10.0),
                 "random-3": shapes.random_polygon(3, 1), "random-7": shapes.random_polygon(7, 3),
                 "random-8": shapes.random_polygon(8, 5), "blob-6": shapes.bezier_blob(6, 1),
                 "cam": shapes.bezier_cam()}
    yield from ((f"generated/{k}", v) for k, v in generated.items())
    from algrasp.io.cad import import_bytes
    for path in sorted((ROOT / "tests" / "data" / "real").glob("*.dxf")):
        try:
            yield f"real/{path.stem}", import_bytes(path.name, path.read_bytes())
        except AlgraspError:
            continue
    shops = sorted(p for p in (ROOT / "tests" / "data" / "shops").rglob("*") if p.suffix in (".dxf", ".svg"))
    for path in dict.fromkeys([p for p in shops if "camotics" in p.name.lower() or "crickit" in p.name.lower()] + shops[::10]):
        try:
            yield f"shop/{path.parent.name}/{path.name}", import_bytes(path.name, path.read_bytes())
        except AlgraspError:
            continue


def documents(doc: dict[str, Any]) -> dict[str, Any]:
    """The robust analysis document and, per action, the plan document (every limit) or
    the refusal's error document (with its limits)."""
    a = analyse_document(doc, ROBUST)
    out: dict[str, Any] = {"analysis": a.to_dict()}
    for action in ("squeeze", "push_grasp"):
        try:
            p = make_plan(a, action, limits="all")
            d = dict(p.to_dict())
            d.pop("timings_s", None)
            out[action] = d
        except NotOrientableError as e:
            out[action] = e.to_dict()
    return out


def _diff(a: Any, b: Any, path: str, out: list[str]) -> None:
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k in ("timings_s", "timings", "run_id"):
                continue
            _diff(a.get(k, "<missing>"), b.get(k, "<missing>"), f"{path}.{k}", out)
    elif isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        for i, (x, y) in enumerate(zip(a, b)):
            _diff(x, y, f"{path}[{i}]", out)
    elif isinstance(a, float) and isinstance(b, float) and (a == b or (math.isnan(a) and math.isnan(b))):
        return
    elif a != b:
        out.append(f"{path}: {str(a)[:160]} → {str(b)[:160]}")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("out", nargs="?")
    ap.add_argument("--only", nargs="*")
    ap.add_argument("--diff", nargs=2)
    args = ap.parse_args()
    if args.diff:
        before, after = (json.loads(Path(p).read_text()) for p in args.diff)
        lines: list[str] = []
        _diff(before, after, "", lines)
        print("\n".join(lines) if lines else f"identical: {len(before)} parts")
        return
    result: dict[str, Any] = {}
    for name, doc in corpus():
        if args.only and name not in args.only:
            continue
        t = time.perf_counter()
        result[name] = documents(doc)
        print(f"{name:48s} {time.perf_counter() - t:6.2f} s", flush=True)
    Path(args.out).write_text(json.dumps(result, indent=1, sort_keys=True))


if __name__ == "__main__":
    main()
