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
from typing import TYPE_CHECKING, Any

import numpy as np

from algrasp.errors import NotOrientableError
from algrasp.geometry import functions
from algrasp.geometry.part import load_part
from algrasp.geometry.tolerances import DEFAULT_TOLERANCES
from algrasp.testing import shapes

if TYPE_CHECKING:
    from algrasp.geometry.functions import SupportPairFunction

HOOKS = ("KERNELS", "LOOKUPS", "GEOMETRY")
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


FAMILIES: dict[str, Callable[[int, int], dict[str, Any]]] = {
    "polygon": lambda seed, n: shapes.random_polygon(n, seed),
    "regular": lambda seed, n: shapes.regular_polygon(n, 1.0 + seed % 7, phase_deg=seed % 90),
    "reuleaux": lambda seed, n: shapes.reuleaux(1.0 + seed % 5),
    "flats": lambda seed, n: shapes.disk_with_flats(1.0, 5.0 + seed % 30),
    "pie": lambda seed, n: shapes.pie(5.0, 10.0 + seed % 40),
    "blob": lambda seed, n: shapes.bezier_blob(max(n, 4), seed),
    "disk": lambda seed, n: shapes.disk(1.0 + seed % 3),
    "rectangle": lambda seed, n: shapes.rectangle(1.0 + seed % 5, 1.0 + n % 3),
}
"""Part documents by family, (seed, n) → document: what the kernel tests draw from (each
test file its own subset: the fused set-valued call, for one, takes point-like contacts only)."""


def families(*names: str) -> dict[str, Callable[[int, int], dict[str, Any]]]:
    """The named :data:`FAMILIES`."""
    return {n: FAMILIES[n] for n in names}


def support_function(doc: dict[str, Any], kind: str) -> SupportPairFunction:
    """d (``kind`` "diameter") or r ("radius") of the part ``doc``, default tolerances."""
    part = load_part(doc)
    return functions.analyse(kind, part.hull, part.center_of_mass, part.size, DEFAULT_TOLERANCES)  # type: ignore[arg-type]


def set_args(f: SupportPairFunction, s: tuple[float, ...]) -> dict[str, Any]:
    """set_transfer's arguments after f for a dead band scaled to f: ``s`` = (stall low,
    stall extra, σ, value tolerance, value error, jaw μ, shallow depth) as fractions of
    f's largest value."""
    scale = float(np.max(f.values(np.linspace(0.0, np.pi, 64))))
    s_lo, s_extra, sigma, tol, err, mu, depth = (scale * v for v in s)
    return {"stall": (s_lo, s_lo + s_extra), "sigma": sigma, "value_tol": tol, "tol_rad": DEFAULT_TOLERANCES.angle_rad,
            "jaw_friction": mu / scale if f.kind == "diameter" else 0.0, "value_err": err, "shallow": depth}
