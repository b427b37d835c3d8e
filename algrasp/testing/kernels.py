"""Both paths of the compiled kernels, for tests that compare them bit for bit.

The compiled kernels (:mod:`algrasp.compiled`: ``KERNELS`` for planning, ``GEOMETRY``
for geometry) are read by module-level hooks; the Python/numpy path they reproduce is the
reference. :func:`reference_path` switches every loaded algrasp module's hooks off at
once, so a test cannot forget a module (each test file used to keep its own list, and
two of them missed the symmetry screen and verification).

>>> from algrasp.planning.analysis import analyse_document
>>> from algrasp.testing import shapes
>>> compiled, reference = both(lambda: analyse_document(shapes.regular_polygon(5)).robust.band.kappa_d)
>>> bits(compiled) == bits(reference)
True
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np

from algrasp.errors import NotOrientableError
from algrasp.geometry import functions

HOOKS = ("KERNELS", "GEOMETRY")
"""The module attributes that hold a compiled module (None: the reference path)."""


@contextmanager
def reference_path() -> Iterator[None]:
    """The Python/numpy reference: no loaded ``algrasp.*`` module sees a kernel (and no
    contact cells cached by the other path are reused)."""
    saved = [(m, name, getattr(m, name)) for key, m in list(sys.modules.items())
             if key.startswith("algrasp.") and key != "algrasp.compiled" for name in HOOKS if hasattr(m, name)]
    for m, name, _ in saved:
        setattr(m, name, None)
    functions._cells.cache_clear()
    try:
        yield
    finally:
        for m, name, value in saved:
            setattr(m, name, value)
        functions._cells.cache_clear()


@contextmanager
def compiled_path() -> Iterator[None]:
    """The kernels as built (none with ``ALGRASP_PURE``), with no cached cells."""
    functions._cells.cache_clear()
    yield


def bits(value: Any) -> Any:
    """A comparable form that tells apart every bit pattern (−0.0, NaN payloads, dtypes)
    of arrays, floats and nested lists/tuples of them; anything else by its repr."""
    if isinstance(value, np.ndarray):
        return ("array", value.dtype.str, value.shape, value.tobytes())
    if isinstance(value, (list, tuple)):
        return tuple(bits(v) for v in value)
    if isinstance(value, float):
        return ("float", value.hex())
    return repr(value)


ERRORS = (IndexError, ValueError, StopIteration)
"""Errors both paths must raise alike (hypothesis pairs inputs no caller pairs, e.g.
bounds where A′'s lookups run past the last piece: numpy's IndexError, and the kernels')."""


def both(make: Callable[[], Any]) -> tuple[Any, Any]:
    """(compiled, reference) results of ``make``, or the refusal's message, or the error
    it raised (type and message): both paths must answer, refuse and fail alike."""
    out: list[Any] = []
    for path in (compiled_path, reference_path):
        with path():
            try:
                out.append(make())
            except NotOrientableError as e:
                out.append(("refused", str(e)))
            except ERRORS as e:
                out.append(("raised", type(e).__name__, str(e)))
    return out[0], out[1]
