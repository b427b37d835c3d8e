"""The record of a hull's Gauss map: one feature over a range of outward normals.

Kept apart from :mod:`algrasp.geometry.hull`, which builds these features, so that
:mod:`algrasp.geometry.bank` (which stacks them into arrays) and the hull can both import
it without importing each other.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from algrasp.geometry.curves import Piece

_new = object.__new__


@dataclass(frozen=True, eq=False)
class HullFeature:
    """One feature of the hull over the normal range ``[psi0, psi1]`` (radians).

    ``kind`` is "point" (a vertex: ``center``), "circle" (an arc: ``center``,
    ``radius``, ``piece`` between ``s0`` and ``s1``) or "curve" (``piece`` between
    ``s0`` and ``s1``).
    """

    kind: Literal["point", "circle", "curve"]
    psi0: float
    psi1: float
    center: tuple[float, float] = (0.0, 0.0)
    radius: float = 0.0
    piece: Piece | None = None
    s0: float = 0.0
    s1: float = 1.0

    @classmethod
    def point(cls, psi0: float, psi1: float, center: tuple[float, float]) -> HullFeature:
        """``HullFeature("point", psi0, psi1, center)``, at half the cost: the fields set in
        one dictionary update instead of a frozen ``__init__``'s setattr each (a polygon's
        hull makes one per corner)."""
        f = _new(cls)
        f.__dict__.update(kind="point", psi0=psi0, psi1=psi1, center=center, radius=0.0, piece=None, s0=0.0, s1=1.0)
        return f

    @property
    def point_like(self) -> bool:
        """Whether the support point is ``center + radius·u(ψ)`` (closed forms apply)."""
        return self.kind != "curve"
