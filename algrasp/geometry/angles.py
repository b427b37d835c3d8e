"""Angle constants and conversions: the one place for them.

Radians inside the package; degrees only at the document boundary (conventions §1),
through :func:`to_deg` and :func:`to_rad`.

>>> round(to_deg(TWO_PI), 9), to_rad(180.0) == math.pi
(360.0, True)
"""

from __future__ import annotations

import math

TWO_PI = 2.0 * math.pi
"""One full turn (radians)."""


def to_deg(angle_rad: float) -> float:
    """Radians → degrees (for documents)."""
    return math.degrees(angle_rad)


def to_rad(angle_deg: float) -> float:
    """Degrees → radians (from documents)."""
    return math.radians(angle_deg)
