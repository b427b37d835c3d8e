"""Cold start (issue 34): the first analysis + plans in a fresh process against the same
work warm, for the default model (robust, default ranges).

Targets: first call within 3× of a warm one, and ≥ 100× part-feeder's first call (633–
1,369 ms in the issue's side-by-side run; the ratio printed is against its fastest,
633 ms). Each row is the median over fresh processes (imports are timed apart: they are
paid once per process, before any part arrives); once with the refusal's limit search
read (what the CLI answers) and once with ``limits="none"`` (a catalogue screen; a
refusal's pending search that is never read costs the same).
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys

from algrasp.pipeline import WARM_UP_PART
from algrasp.testing import shapes

PROBE = """
import json, sys, time
t = time.perf_counter()
from algrasp.errors import NotOrientableError
from algrasp.planning.analysis import analyse_document
from algrasp.planning.plans import make_plan
imported = time.perf_counter() - t
doc = json.loads(sys.argv[1])
def once():
    a = analyse_document(doc)
    for action in ("push_grasp", "squeeze"):
        try:
            make_plan(a, action, limits=sys.argv[2])
        except NotOrientableError as e:
            e.limits  # with "refusal" the limit search runs here, as the CLI shows it
times = []
for _ in range(8):
    t = time.perf_counter(); once(); times.append(time.perf_counter() - t)
print(json.dumps([imported, times[0], sorted(times[1:])[3]]))
"""


PART_FEEDER_FIRST_MS = 633.0


def main() -> None:
    cases = [("triangle (3 lines)", WARM_UP_PART), ("rectangle", shapes.rectangle(3.0, 1.0)),
             ("random 7-gon", shapes.random_polygon(7, 4)), ("50 cubic Bezier segments", shapes.bezier_blob(50, 2))]
    for limits in ("refusal", "none"):
        print(f"limits {limits!r}")
        print(f"{'part':28s} {'imports ms':>11s} {'first ms':>9s} {'warm ms':>8s} {'first/warm':>11s} "
              f"{'part-feeder/first':>18s}  (median of 5 processes)")
        for name, doc in cases:
            rows = [json.loads(subprocess.run([sys.executable, "-c", PROBE, json.dumps(doc), limits], capture_output=True,
                                              text=True, check=True).stdout) for _ in range(5)]
            imp, first, warm = (1000 * statistics.median(r[i] for r in rows) for i in range(3))
            print(f"{name:28s} {imp:11.0f} {first:9.1f} {warm:8.1f} {first / warm:10.2f}× "
                  f"{PART_FEEDER_FIRST_MS / first:17.0f}×")


if __name__ == "__main__":
    main()
