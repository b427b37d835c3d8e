"""``algrasp replay`` and ``algrasp runs``: review recorded runs from the command line."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from algrasp.io.record.recorder import default_directory
from algrasp.io.record.replay import list_runs, replay


def cmd_replay(args: argparse.Namespace) -> int:
    result = replay(Path(args.run))
    if args.figure:
        _figure(Path(args.run), args.figure)
    if args.json:
        print(json.dumps({k: result[k] for k in ("run_id", "action", "steps", "differences")}, indent=2))
        return 0
    s, req = result["summary"], result["request"]
    print(f"run {result['run_id']}: {s.get('command')} of part {req['part'].get('name')!r}, action {result['action']}, "
          f"status {s.get('status')}")
    for i, st in enumerate(result["steps"]):
        push = "" if st.get("push_distance") is None else f", push {st['push_distance']:.4f}"
        print(f"  step {i + 1}: gripper {st['gripper_angle_deg']:.4f}°{push}")
    if result["validation"]:
        v = result["validation"]
        print(f"  validation: {len(v['samples'])} samples, agreement {100 * v['agreement']:.1f}%")
    print("  timings: " + ", ".join(f"{k} {v:.3f} s" for k, v in s.get("timings_s", {}).items()))
    print("  versions: " + ", ".join(f"{k} {v}" for k, v in s.get("versions", {}).items()))
    diffs = result["differences"]
    print("reproducible: recomputed analysis and plan match the record" if not diffs else f"{len(diffs)} differences:")
    for d in diffs[:50]:
        print(f"  {d['what']} {d['path']}: recorded {d['recorded']!r}, recomputed {d['recomputed']!r}")
    if args.figure:
        print(f"figure written to {args.figure}")
    return 0


def _figure(path: Path, out: str) -> None:
    from algrasp.io.record.replay import recorded_plan
    from algrasp.plots import plan_figure

    analysis, plan = recorded_plan(path)
    plan_figure(analysis, plan, out)


def cmd_runs(args: argparse.Namespace) -> int:
    runs = list_runs(Path(args.dir) if args.dir else default_directory())
    if args.json:
        print(json.dumps(runs, indent=2))
        return 0
    from rich.console import Console
    from rich.table import Table

    table = Table(title=f"{len(runs)} recorded runs")
    for col in ("run id", "command", "part", "action", "steps", "agreement", "cycle (s)", "status"):
        table.add_column(col)
    for r in runs:
        agree = "" if r.get("agreement") is None else f"{100 * r['agreement']:.1f}%"
        cycle = "" if r.get("cycle_time_s") is None else f"{r['cycle_time_s']:.3f}"
        table.add_row(r["run_id"], r.get("command", ""), str(r.get("part_name") or ""), str(r.get("action") or ""),
                      "" if r.get("steps") is None else str(r["steps"]), agree, cycle, r.get("status", ""))
    Console(width=160).print(table)
    for r in runs:
        if r.get("status") == "damaged":
            print(f"algrasp: damaged record: {r['error']}", file=sys.stderr)
    return 0


def add_commands(sub: Any) -> None:
    p = sub.add_parser("replay", help="summarise a run record and recompute it from its request")
    p.add_argument("run", metavar="RUN.mcap")
    p.add_argument("--json", action="store_true")
    p.add_argument("--figure", metavar="OUT.svg|png", help="render the plan figure from the record")
    p.set_defaults(func=cmd_replay)
    p = sub.add_parser("runs", help="list recorded runs with their main figures")
    p.add_argument("--dir", metavar="DIR", help="record directory (default $ALGRASP_LOG_DIR or logs/)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_runs)
