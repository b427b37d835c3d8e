"""Which implementation of the hot array passes runs: the compiled kernels (typed loops
built from a .pyx at install when a C compiler is there) or the numpy/Python reference
they reproduce bit for bit.

``KERNELS`` is :mod:`algrasp.planning._kernels` (with ``LOOKUPS``, :mod:`algrasp.planning._lookups`) and ``GEOMETRY`` is
:mod:`algrasp.geometry._geometry` (the diameter/radius analysis of point-like hulls), or
None: when it was not built, or when the environment sets ``ALGRASP_PURE=1`` (read once,
at import). The numpy path is the reference: ``tests/algrasp/planning/test_kernels.py``
and ``tests/algrasp/geometry/test_geometry_kernels.py`` compare the two.
"""

from __future__ import annotations

import importlib
import os
from types import ModuleType


def _load(name: str) -> ModuleType | None:
    if os.environ.get("ALGRASP_PURE", "") not in ("", "0"):
        return None
    try:
        return importlib.import_module(name)
    except ImportError:  # no compiler at install: the numpy path
        return None


KERNELS = _load("algrasp.planning._kernels")
"""The compiled set-valued kernels module, or None (the numpy path)."""
LOOKUPS = None if KERNELS is None else _load("algrasp.planning._lookups")
"""The compiled lookups and plan loops (:mod:`algrasp.planning._lookups`; the part
:data:`KERNELS` does not re-export), present exactly when KERNELS is."""
GEOMETRY = _load("algrasp.geometry._geometry")
"""The compiled geometry kernels module, or None (the Python path)."""
