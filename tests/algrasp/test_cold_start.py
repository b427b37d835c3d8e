"""Cold start (issue 34): a fresh process's first plan pays no first-use imports, and a
pool worker is warmed before its first request. Checked by what gets imported, not by
timing (CI machines are loaded)."""

from __future__ import annotations

import json
import subprocess
import sys

from algrasp.pipeline import WARM_UP_PART

PROBE = """
import json, sys
from algrasp.errors import NotOrientableError
from algrasp.planning.analysis import analyse_document
from algrasp.planning.plans import make_plan
before = set(sys.modules)
analysis = analyse_document(json.loads(sys.argv[1]))
for action in ("push_grasp", "squeeze"):
    try:
        make_plan(analysis, action)
    except NotOrientableError:
        pass
print(json.dumps(sorted(set(sys.modules) - before)))
"""

# numpy.fft (1 ms) and the limit searches of a refusal may load on first use; numpy.ma
# (~30 ms, pulled in by a plain np.unique) and numpy.polynomial (~6 ms) must not.
ALLOWED_PREFIXES = ("numpy.fft", "algrasp.planning.limits")


def test_the_first_plan_in_a_fresh_process_imports_nothing_heavy() -> None:
    out = subprocess.run([sys.executable, "-c", PROBE, json.dumps(WARM_UP_PART)], capture_output=True, text=True,
                         check=True)
    loaded = json.loads(out.stdout)
    assert [m for m in loaded if not m.startswith(ALLOWED_PREFIXES)] == []


def test_warm_up_loads_what_a_request_needs() -> None:
    probe = ("import sys\nfrom algrasp.pipeline import warm_up\nwarm_up()\n"
             "print(all(m in sys.modules for m in ('algrasp.planning.limits', 'algrasp.planning.setvalued')))")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "True"
