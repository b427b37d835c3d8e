"""Angle constants and conversions: the one place for them.

Radians inside the package; degrees only at boundaries (documents, drawings, figures,
records; conventions §1), through :func:`to_deg` and :func:`to_rad`. Both take a float or
a NumPy array and return the same kind. :func:`to_deg` is the product CPython's
``math.degrees`` computes; :func:`to_rad` is ``math.radians``'s product, or a neighbour of
it one unit in the last place away when that is what :func:`to_deg` writes as the given
degrees (for 5 % of angles the product misses). So degrees read back give the radians
they were written from, and a document read back writes out unchanged.

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
FloatLike = NDArray[np.float64]


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
    """Degrees → radians: a float for a number, an array for an array or a sequence; the
    radians :func:`to_deg` writes as these degrees when one lies within an ulp."""
    if isinstance(angle_deg, (int, float, np.number)):
        d = float(angle_deg)
        r = d * _RAD_PER_DEG
        if r * _DEG_PER_RAD != d:
            for c in (math.nextafter(r, math.inf), math.nextafter(r, -math.inf)):
                if c * _DEG_PER_RAD == d:
                    return c
        return r
    deg = np.asarray(angle_deg, dtype=float)
    out: NDArray[np.float64] = deg * _RAD_PER_DEG
    for toward in (np.inf, -np.inf):
        miss = out * _DEG_PER_RAD != deg
        if not miss.any():
            break
        near = np.nextafter(out, toward)
        out = np.where(miss & (near * _DEG_PER_RAD == deg), near, out)
    return out


def _scaled(x: float | Angles, k: float) -> float | NDArray[np.float64]:
    if isinstance(x, (int, float, np.number)):
        return float(x) * k
    return np.asarray(x, dtype=float) * k


def shortest_turn(angle_rad: float, period_rad: float = TWO_PI) -> float:
    """The signed turn in [−period/2, period/2) equivalent to ``angle_rad`` modulo
    ``period_rad`` (a gripper turning to an action that maps to itself under that period).

    >>> round(to_deg(shortest_turn(to_rad(170.0), math.pi)), 9)
    -10.0
    """
    return (angle_rad + period_rad / 2) % period_rad - period_rad / 2


@overload
def signed_diff(a_rad: float, b_rad: float) -> float: ...
@overload
def signed_diff(a_rad: FloatLike, b_rad: float | FloatLike) -> NDArray[np.float64]: ...
@overload
def signed_diff(a_rad: float, b_rad: FloatLike) -> NDArray[np.float64]: ...
def signed_diff(a_rad: float | FloatLike, b_rad: float | FloatLike) -> float | NDArray[np.float64]:
    """``a − b`` wrapped into [−π, π): how far ``a`` lies ahead of ``b`` on the circle
    (floats or broadcasting arrays; elementwise, O(n)).

    >>> round(to_deg(signed_diff(to_rad(350.0), to_rad(10.0))), 9)
    -20.0
    >>> to_deg(signed_diff(np.array([0.0, math.pi / 2]), 0.0)).round(9).tolist()
    [0.0, 90.0]
    """
    if isinstance(a_rad, (int, float)) and isinstance(b_rad, (int, float)):
        return (a_rad - b_rad + math.pi) % TWO_PI - math.pi
    return (np.asarray(a_rad, dtype=float) - b_rad + np.pi) % TWO_PI - np.pi


@overload
def wrap_from(angle_rad: float, base_rad: float) -> float: ...
@overload
def wrap_from(angle_rad: FloatLike, base_rad: float | FloatLike) -> NDArray[np.float64]: ...
@overload
def wrap_from(angle_rad: float, base_rad: FloatLike) -> NDArray[np.float64]: ...
def wrap_from(angle_rad: float | FloatLike, base_rad: float | FloatLike) -> float | NDArray[np.float64]:
    """``angle`` moved by whole turns into [base, base + 2π) (floats or broadcasting arrays).

    >>> round(to_deg(wrap_from(to_rad(-30.0), to_rad(90.0))), 9)
    330.0
    """
    if isinstance(angle_rad, (int, float)) and isinstance(base_rad, (int, float)):
        return base_rad + (angle_rad - base_rad) % TWO_PI
    return base_rad + (np.asarray(angle_rad, dtype=float) - base_rad) % TWO_PI


def wrap_deg(angle_deg: float) -> float:
    """An angle in degrees wrapped into [0, 360)."""
    return float(angle_deg) % 360.0
