"""Run records of the tests go to a temporary directory, never to the checkout's logs/."""

from __future__ import annotations

import os
import tempfile

os.environ.setdefault("ALGRASP_LOG_DIR", tempfile.mkdtemp(prefix="algrasp-test-logs-"))
