"""Batch fixture design of a generated catalogue (random polygons, rectangles, regular
polygons, pies, Bezier blobs, disks with flats, and disks and Reuleaux triangles that
cannot be oriented) with ``algrasp batch`` on the local pool. Prints wall time,
throughput in parts per minute, CPU per part (the batch process's and the workers': on a
shared machine the figures that other load does not inflate) and peak memory (resident
set of the batch process and of its largest worker), without validation and with Drake
samples.

Targets: 10,000 parts without validation ≤ 5 min on 2 cores (issue 21), ≤ 1 min on the
robust model, optimised (issue 34: measured with ``--limits none``, the catalogue screen,
and with the default ``headline`` limits); with 4 Drake samples per part the parts/min is
printed (on the first ``--drake-parts`` parts).

    python benchmarks/bench_batch.py [--parts 10000] [--samples 0 4] [--drake-parts 40] [--workers 2]
                                     [--limits none headline]
"""

from __future__ import annotations

import argparse
import json
import resource
import tempfile
import time
from pathlib import Path
from typing import Any

from algrasp.cli import main as algrasp
from algrasp.testing.shapes import bezier_blob, disk, disk_with_flats, pie, random_polygon, rectangle, regular_polygon, reuleaux


def _scaled(doc: dict[str, Any], k: float) -> dict[str, Any]:
    """A Bezier-loop document scaled by ``k`` (control points only)."""
    return {**doc, "boundary": [{**s, "points": [[k * x, k * y] for x, y in s["points"]]} for s in doc["boundary"]]}


def catalogue(n: int) -> list[dict[str, Any]]:
    """``n`` generated parts, in millimetres, each with a unique name."""
    makers = [
        lambda i: random_polygon(6 + i % 10, seed=i),
        lambda i: rectangle(10.0 + i % 17, 3.0 + i % 5),
        lambda i: regular_polygon(3 + i % 6, 5.0 + i % 7),
        lambda i: pie(5.0 + i % 3, 10.0 + i % 40),
        lambda i: _scaled(bezier_blob(4 + i % 4, seed=i), 10.0),  # ~20 mm across, like the other parts
        lambda i: disk_with_flats(5.0, 5.0 + i % 30),
        lambda i: disk(3.0 + i % 4) if i % 2 else reuleaux(4.0),
    ]
    return [dict(makers[i % len(makers)](i), name=f"part-{i:03d}", units="mm") for i in range(n)]


def _cpu() -> tuple[float, float]:
    """CPU seconds (user + system) of this process and of its reaped children (the pool's
    workers, reaped when the batch shuts its pool down)."""
    me, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime, kids.ru_utime + kids.ru_stime


def run(parts: list[dict[str, Any]], samples: int, workers: int, limits: str = "headline") -> None:
    with tempfile.TemporaryDirectory() as tmp:
        cat = Path(tmp) / "catalogue"
        cat.mkdir()
        for p in parts:
            (cat / f"{p['name']}.json").write_text(json.dumps(p))
        out = Path(tmp) / "out"
        cpu0 = _cpu()
        t0 = time.perf_counter()
        code = algrasp(["batch", str(cat), "--out", str(out), "--workers", str(workers), "--validate-samples", str(samples),
                        "--record-dir", str(Path(tmp) / "logs"), "--limits", limits])
        wall = time.perf_counter() - t0
        own, workers_cpu = (b - a for a, b in zip(cpu0, _cpu()))
        spec = json.loads((out / "gripper_spec.json").read_text())
        agreements = [json.loads(x)["result"]["validation"]["agreement"] for x in (out / "results.jsonl").read_text().splitlines()
                      if samples and json.loads(x)["status"] == "done" and json.loads(x)["result"].get("validation")]
        extra = f", mean agreement {sum(agreements) / len(agreements):.3f}" if agreements else ""
        peak_self = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
        peak_worker = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
        print(f"== {len(parts)} parts, {samples} Drake samples each, {workers} workers, limits {limits}: exit {code}, {wall:.1f} s "
              f"({wall / 60:.2f} min), {60 * len(parts) / wall:.1f} parts/min; oriented {spec['oriented']}, "
              f"not oriented {len(spec['not_oriented'])}{extra}; peak RSS {peak_self:.0f} MiB (batch process), "
              f"{peak_worker:.0f} MiB (largest worker)")
        print(f"   CPU per part: {1000 * own / len(parts):.2f} ms in the batch process (reading, dispatch, store, "
              f"reports), {1000 * workers_cpu / len(parts):.2f} ms in the workers (the machine's other load does "
              "not count here, unlike in the wall time)")
        print("   report.md head:")
        print("   " + "\n   ".join((out / "report.md").read_text().splitlines()[:16]))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--parts", type=int, default=10_000)
    ap.add_argument("--samples", type=int, nargs="+", default=[0, 4])
    ap.add_argument("--drake-parts", type=int, default=40, help="parts of the catalogue validated in Drake")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--limits", nargs="+", default=["none", "headline"], choices=("none", "headline", "all"),
                    help="physics limits per part, one run each without validation (none: the fastest screen)")
    args = ap.parse_args()
    parts = catalogue(args.parts)
    for s in args.samples:
        for limits in args.limits if s == 0 else ["headline"]:
            run(parts if s == 0 else parts[:args.drake_parts], s, args.workers, limits)


if __name__ == "__main__":
    main()
