"""Angle constants and conversions: the one place for them.

Radians inside the package; degrees only at boundaries (documents, drawings, figures,
records; conventions §1), through :func:`to_deg` and :func:`to_rad`. Both take a float or
a NumPy array and return the same kind; they are the exact products CPython's
``math.degrees``/``math.radians`` compute, so documents are byte-identical.

>>> round(to_deg(TWO_PI), 9), to_rad(180.0) == math.pi
(360.0, True)
>>> to_deg(np.array([0.0, math.pi])).tolist()
[0.0, 180.0]
>>> wrap_deg(-90.0), wrap_deg(720.5)
(270.0, 0.5)
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import overload

import numpy as np
from numpy.typing import NDArray

TWO_PI = 2.0 * math.pi
"""One full turn (radians)."""

_DEG_PER_RAD = 180.0 / math.pi
_RAD_PER_DEG = math.pi / 180.0

Angles = NDArray[np.float64] | Sequence[float]


@overload
def to_deg(angle_rad: float) -> float: ...
@overload
def to_deg(angle_rad: Angles) -> NDArray[np.float64]: ...
def to_deg(angle_rad: float | Angles) -> float | NDArray[np.float64]:
    """Radians → degrees: a float for a number, an array for an array or a sequence."""
    return _scaled(angle_rad, _DEG_PER_RAD)


@overload
def to_rad(angle_deg: float) -> float: ...
@overload
def to_rad(angle_deg: Angles) -> NDArray[np.float64]: ...
def to_rad(angle_deg: float | Angles) -> float | NDArray[np.float64]:
    """Degrees → radians: a float for a number, an array for an array or a sequence."""
    return _scaled(angle_deg, _RAD_PER_DEG)


def _scaled(x: float | Angles, k: float) -> float | NDArray[np.float64]:
    if isinstance(x, (int, float, np.number)):
        return float(x) * k
    return np.asarray(x, dtype=float) * k


def wrap_deg(angle_deg: float) -> float:
    """An angle in degrees wrapped into [0, 360)."""
    return float(angle_deg) % 360.0
