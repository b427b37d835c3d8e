"""Run records of the tests go to a temporary directory, never to the checkout's logs/."""

from __future__ import annotations

import os
import tempfile

os.environ.setdefault("ALGRASP_LOG_DIR", tempfile.mkdtemp(prefix="algrasp-test-logs-"))
# The suite's cell is the ideal one of conventions §7 (frictionless jaws, support μ 0.3,
# 20 g, 2 N, centred, exact parts) unless a test says otherwise: most tests check the
# machinery against the paper and brute force in one known cell. Tests of the real-cell
# defaults (conventions §8) set ALGRASP_CELL=default or pass their physics explicitly.
os.environ.setdefault("ALGRASP_CELL", "ideal")
