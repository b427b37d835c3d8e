"""The dead band of a real gripper and a real part (conventions §7): κ = s + σ.

* **Stall threshold s** (part units per radian). A squeeze with grip force F turns the
  part with the couple F·d′(θ); the support surface resists with at most m_max = μ m g r̄
  (the uniform-pressure Coulomb limit surface the simulation uses, r̄ the mean distance of
  the region from the centre of mass). So the part stalls where |d′| ≤ s_d = m_max / F.
  Likewise s_r = m_max / F for a push (the lower jaw presses with the same servo force).
* **Slope error σ** of the drawing against the real part (:mod:`algrasp.geometry.recognise`):
  0 for exact curves, measured for arc approximations and tessellations; the diameter has
  two contacts (2σ), the radius one (σ).

:class:`Physics` holds the gripper and part parameters; the simulation's defaults
(``algrasp.sim.config``) are taken from :data:`DEFAULT_PHYSICS`, so the planner and the
simulator model one gripper. Pure: no I/O.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from algrasp.errors import ConfigError
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.part import Part
from algrasp.geometry.recognise import drawing_error
from algrasp.geometry.segments import loop_polyline
from algrasp.geometry.tolerances import Tolerances

_MEAN_RADIUS_TURN_RAD = 0.02
"""Polyline turn for r̄ (only r̄ uses it: ~1e-4 relative)."""


@dataclass(frozen=True)
class Physics:
    """Gripper and part parameters of the dead band (SI units).

    ``shape_tolerance`` is σ per jaw in part units per radian; None derives it from the
    drawing (:func:`algrasp.geometry.recognise.drawing_error`).
    """

    support_friction: float = 0.3
    part_mass_kg: float = 0.02
    grip_force_n: float = 2.0
    gravity_m_s2: float = 9.81
    shape_tolerance: float | None = None

    def __post_init__(self) -> None:
        for f in fields(self):
            v = getattr(self, f.name)
            if v is None and f.name == "shape_tolerance":
                continue
            if not (isinstance(v, (int, float)) and math.isfinite(v) and 0.0 <= v <= 1e6):
                raise ConfigError(f"physics.{f.name}", f"must be a finite number in [0, 1e6], got {v!r}")
        if self.grip_force_n <= 0.0:
            raise ConfigError("physics.grip_force_n", "must be positive")

    @property
    def stall_ratio(self) -> float:
        """μ m g / F (dimensionless): s = ratio · r̄."""
        return self.support_friction * self.part_mass_kg * self.gravity_m_s2 / self.grip_force_n

    def to_dict(self) -> dict[str, float | None]:
        return {f.name: getattr(self, f.name) for f in fields(self)}


DEFAULT_PHYSICS = Physics()


@dataclass(frozen=True)
class DeadBand:
    """Thresholds on the slope of d and r (part units per radian) for one part.

    Attributes:
        stall: s, the same for d and r (m_max / F in part units).
        sigma_d, sigma_r: σ for d (two contacts) and r (one).
        value_tol: how far values may differ and still be equal (symmetry), part units.
        mean_radius: r̄ (part units).
        sources: what the drawing error was derived from.
    """

    stall: float
    sigma_d: float
    sigma_r: float
    value_tol: float
    mean_radius: float
    sources: tuple[str, ...] = ()

    @property
    def kappa_d(self) -> float:
        return self.stall + self.sigma_d

    @property
    def kappa_r(self) -> float:
        return self.stall + self.sigma_r

    def to_dict(self) -> dict[str, object]:
        return {"stall_per_rad": self.stall, "sigma_d_per_rad": self.sigma_d, "sigma_r_per_rad": self.sigma_r,
                "kappa_d_per_rad": self.kappa_d, "kappa_r_per_rad": self.kappa_r,
                "mean_radius": self.mean_radius, "value_tolerance": self.value_tol,
                "shape_sources": list(self.sources)}


def mean_radius(part: Part) -> float:
    """r̄: mean distance of the region's points from the centre of mass (part units).

    Green's theorem with F = (p − c)·|p − c| / 3, whose divergence is |p − c|:
    ∬ |p − c| dA = ⅓ ∮ |p − c| ⟨p − c, n⟩ ds, on the loops' polylines (turn ≤ 0.02 rad,
    6-point Gauss per edge; holes run clockwise and subtract). O(n)."""
    c = np.asarray(part.center_of_mass)
    total = sum(_distance_integral(loop_polyline(loop, _MEAN_RADIUS_TURN_RAD)[0] - c) for loop in (part.boundary, *part.holes))
    return float(total / part.area)


def _distance_integral(pts: FloatArray) -> float:
    """⅓ ∮ |p| (x dy − y dx) over the closed polyline ``pts`` (N, 2)."""
    d = np.roll(pts, -1, axis=0) - pts
    t, w = np.polynomial.legendre.leggauss(6)
    t, w = 0.5 * (t + 1.0), 0.5 * w
    p = pts[:, None, :] + d[:, None, :] * t[None, :, None]
    rho = np.hypot(p[..., 0], p[..., 1])
    cross = p[..., 0] * d[:, None, 1] - p[..., 1] * d[:, None, 0]
    return float(np.sum(rho * cross * w) / 3.0)


def dead_band(part: Part, physics: Physics, tol: Tolerances) -> DeadBand:
    """The part's dead band under ``physics``. O(n) plus a 120² grid for r̄."""
    rbar = mean_radius(part)
    err = drawing_error(part.boundary, tol)
    sigma = err.slope if physics.shape_tolerance is None else physics.shape_tolerance
    value = max(err.value, tol.symmetry_value_rel * part.size)
    if physics.shape_tolerance is not None:
        value = max(value, 0.05 * physics.shape_tolerance)  # ~3° of slope error as position
    return DeadBand(physics.stall_ratio * rbar, 2.0 * sigma, sigma, value, rbar, (*part.recognised, *err.sources))
