"""Which implementation of the hot array passes runs: the compiled kernels
(:mod:`algrasp.planning._kernels`, typed loops built from a .pyx at install when a C
compiler is there) or the numpy reference they reproduce bit for bit.

``KERNELS`` is the compiled module, or None: when it was not built, or when the
environment sets ``ALGRASP_PURE=1`` (read once, at import). The numpy path is the
reference: ``tests/test_kernels.py`` compares the two on random and corpus parts.
"""

from __future__ import annotations

import os
from types import ModuleType


def _load() -> ModuleType | None:
    if os.environ.get("ALGRASP_PURE", "") not in ("", "0"):
        return None
    try:
        import algrasp.planning._kernels as _kernels
    except ImportError:  # no compiler at install: the numpy path
        return None
    return _kernels


KERNELS = _load()
"""The compiled kernels module, or None (the numpy path)."""
