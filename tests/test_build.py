"""The install builds the compiled kernels wherever it can: a machine with a C compiler and
the Python headers must not fall back to the numpy path silently (setup.py marks the
extension optional, so a failed build would otherwise only show as a slower robust model
and as kernel tests skipped)."""

from __future__ import annotations

import os
import shlex
import shutil
import sysconfig
from pathlib import Path

import pytest


def _can_compile() -> bool:
    cc = shlex.split(sysconfig.get_config_var("CC") or "cc")
    headers = Path(sysconfig.get_paths()["include"]) / "Python.h"
    return bool(cc) and shutil.which(cc[0]) is not None and headers.is_file()


@pytest.mark.skipif(not _can_compile(), reason="no C compiler or Python headers: the numpy path is expected")
@pytest.mark.skipif(os.environ.get("ALGRASP_PURE", "") not in ("", "0"), reason="ALGRASP_PURE chooses the numpy path")
def test_kernels_built_where_a_compiler_is() -> None:
    from algrasp.compiled import GEOMETRY, KERNELS

    for name, module in (("algrasp.planning._kernels", KERNELS), ("algrasp.geometry._geometry", GEOMETRY)):
        assert module is not None, f"a C compiler and Python.h are here, but {name} was not built"
        # A compiled module, not a .py of the same name shadowing it.
        assert module.__file__ is not None and Path(module.__file__).suffix in (".so", ".pyd")
