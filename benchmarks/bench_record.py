"""Recording overhead: plan + validate through the CLI with and without the MCAP record.

Target (issue 6): recording adds < 10 % to the time of a plan + validation. Both runs use
the same warm worker pool (the first, unrecorded warm-up run builds it). In the ideal cell
(``--cell ideal``), where the paper's pie is orientable by squeeze; the default (real) cell
refuses it (exit 2), and its one orientable example, the bracket's push-grasp, pushes
~150 mm per action: minutes of simulation per sample, which would measure Drake."""

from __future__ import annotations

import contextlib
import io
import tempfile
import time
from pathlib import Path

from algrasp.cli import main

EXAMPLE = Path(__file__).parents[1] / "algrasp" / "examples" / "pie-20.json"


def timed(args: list[str]) -> float:
    t = time.perf_counter()
    with contextlib.redirect_stdout(io.StringIO()):
        assert main(args) == 0
    return time.perf_counter() - t


def run() -> None:
    with tempfile.TemporaryDirectory() as d:
        base = ["validate", str(EXAMPLE), "--cell", "ideal", "--samples", "12", "--json", "--record-dir", d]
        timed([*base, "--no-record"])  # warm the worker pool
        off = [timed([*base, "--no-record"]) for _ in range(2)]
        on = [timed(base) for _ in range(2)]
        size = sum(p.stat().st_size for p in Path(d).glob("*.mcap")) / len(on)
    print(f"plan + validate (12 samples, pie squeeze, ideal cell): without record {min(off):.2f} s, with record {min(on):.2f} s "
          f"({100 * (min(on) / min(off) - 1):+.1f} %), record {size / 1024:.0f} KiB")


if __name__ == "__main__":
    run()
