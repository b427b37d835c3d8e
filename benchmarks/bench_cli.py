"""CLI start-up: wall time of ``algrasp --help`` and of a whole ``algrasp plan`` of the
bundled bracket's push-grasp (new process each time, as a cell script or a shell user
runs it). The bracket is the part ``make run`` plans: orientable in the default (real)
cell, which the paper's 5 mm pie is not (``algrasp plan`` refuses it there, exit 2).

Target (issue 21): ``algrasp --help`` ≤ 0.4 s (it was 0.9 s, half of it importing
scipy.spatial): the commands import their layers only when run.
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

EXE = Path(sys.executable).with_name("algrasp")
PART = Path(__file__).parents[1] / "algrasp" / "examples" / "bracket.json"
PLAN = ["plan", str(PART), "--action", "push_grasp"]


def p50_s(args: list[str], runs: int = 7) -> float:
    times = []
    for _ in range(runs):
        t = time.perf_counter()
        subprocess.run([str(EXE), *args], check=True, capture_output=True)
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def main() -> None:
    print(f"algrasp --help: {p50_s(['--help']):.3f} s p50 (target ≤ 0.4 s)")
    with tempfile.TemporaryDirectory() as tmp:
        plan = p50_s([*PLAN, "--record-dir", tmp], runs=5)
        optimised = p50_s([*PLAN, "--optimise", "--record-dir", tmp], runs=5)
    print(f"algrasp plan bracket.json --action push_grasp: {plan:.3f} s p50; with --optimise: {optimised:.3f} s p50 "
          "(whole process)")


if __name__ == "__main__":
    main()
