"""The dead band of a real cell and a real part (docs/conventions.md §7, §8).

* **Stall threshold s** (part units per radian). A squeeze with grip force F turns the
  part with the couple F·d′(θ); the support surface resists with at most m_max = μ_s m g r̄
  (the uniform-pressure Coulomb limit surface the simulation uses, r̄ the mean distance of
  the region from the centre of mass). So the part stalls where |d′| ≤ s_d = m_max / F.
  Likewise s_r for a push (the lower jaw presses with the same servo force). Over the
  physics ranges s is a range [s_lo, s_hi]: least support friction and mass and most
  force, and the opposite; r̄ moves by at most the centre-of-mass tolerance ε_c.
* **Jaw friction** μ_j adds the couple of two contacts d apart: a squeezed part can rest
  where |d′| ≤ μ_j·d + s_d. A push keeps its sense of rotation (the pusher decides it).
* **Slope error σ** of the drawing against the real part (:mod:`algrasp.geometry.recognise`),
  never below the manufacturing profile tolerance: the diameter has two contacts (2σ), the
  radius one (σ) plus ε_c (moving c by δ moves r and r′ by at most |δ|).

Pure: no I/O.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.polynomial import legendre  # at import, not on first use inside the first analysis

from algrasp.compiled import GEOMETRY
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.part import Part
from algrasp.geometry.recognise import DrawingError, drawing_error
from algrasp.geometry.segments import Line, Segment, loop_polyline
from algrasp.geometry.tolerances import Tolerances
from algrasp.geometry.units import meters_per_unit
from algrasp.planning.physics import COM_TOLERANCE_REL, DEFAULT_PHYSICS, Physics, iso_2768_f_mm

__all__ = ["DEFAULT_PHYSICS", "DeadBand", "PartTerms", "Physics", "dead_band", "mean_radius", "part_terms"]

_MEAN_RADIUS_TURN_RAD = 0.02
"""Polyline turn for r̄ (only r̄ uses it: ~1e-4 relative)."""


@dataclass(frozen=True)
class DeadBand:
    """Thresholds on the slope of d and r (part units per radian) for one part.

    Attributes:
        stall_lo, stall_hi: s over the ranges (the same for d and r).
        jaw_friction: μ_j,max: the squeeze may rest where |d′| ≤ μ_j·d + s_hi + σ_d.
        sigma_d, sigma_r: σ for d (two contacts) and r (one, plus the centre-of-mass disk).
        value_tol: how far values may differ and still be equal (symmetry), part units.
        value_tol_r: the same for r.
        value_err: how far the real d or r may be from the drawn one (part units): the
            drawing's error or the profile tolerance, the larger (r adds ε_c).
        mean_radius: r̄ (part units); com_tolerance: ε_c (part units).
        profile_floor: the manufacturing floor of σ (part units per radian).
        sources: what the drawing error was derived from.
    """

    stall_lo: float
    stall_hi: float
    jaw_friction: float
    sigma_d: float
    sigma_r: float
    value_tol: float
    value_tol_r: float
    mean_radius: float
    com_tolerance: float
    profile_floor: float
    value_err: float
    sources: tuple[str, ...] = ()

    @property
    def kappa_d(self) -> float:
        """Widest slope that may stall a squeeze, without the jaw term μ_j·d."""
        return self.stall_hi + self.sigma_d

    @property
    def kappa_r(self) -> float:
        return self.stall_hi + self.sigma_r

    def to_dict(self) -> dict[str, object]:
        return {"stall_per_rad": [self.stall_lo, self.stall_hi], "jaw_friction_max": self.jaw_friction,
                "sigma_d_per_rad": self.sigma_d, "sigma_r_per_rad": self.sigma_r,
                "kappa_d_per_rad": self.kappa_d, "kappa_r_per_rad": self.kappa_r,
                "mean_radius": self.mean_radius, "com_tolerance": self.com_tolerance,
                "profile_floor_per_rad": self.profile_floor, "value_tolerance": self.value_tol,
                "shape_sources": list(self.sources)}


def mean_radius(part: Part) -> float:
    """r̄: mean distance of the region's points from the centre of mass (part units).

    Green's theorem with F = (p − c)·|p − c| / 3, whose divergence is |p − c|:
    ∬ |p − c| dA = ⅓ ∮ |p − c| ⟨p − c, n⟩ ds, on the loops' polylines (turn ≤ 0.02 rad,
    6-point Gauss per edge; holes run clockwise and subtract). O(n)."""
    loops = (part.boundary, *part.holes)
    if GEOMETRY is not None and all(isinstance(s, Line) for loop in loops for s in loop):  # compiled: the same sums
        t, w = _GAUSS6_LISTS
        return float(sum(GEOMETRY.distance_integral([s.start for s in loop], part.center_of_mass, t, w)
                         for loop in loops) / part.area)
    c = np.asarray(part.center_of_mass)
    total = sum(_distance_integral(_loop_points(loop) - c) for loop in loops)
    return float(total / part.area)


def _loop_points(loop: tuple[Segment, ...]) -> FloatArray:
    """The loop's polyline points (N, 2): a polygon's vertices as they are (what
    :func:`~algrasp.geometry.segments.loop_polyline` gives, without a part per segment)."""
    if all(isinstance(s, Line) for s in loop):
        return np.array([s.start for s in loop], dtype=float)
    return loop_polyline(loop, _MEAN_RADIUS_TURN_RAD)[0]


def _gauss_nodes(k: int) -> tuple[FloatArray, FloatArray]:
    """k-point Gauss-Legendre nodes and weights on [0, 1] (read-only)."""
    t, w = legendre.leggauss(k)
    t, w = 0.5 * (t + 1.0), 0.5 * w
    t.setflags(write=False)
    w.setflags(write=False)
    return t, w


_GAUSS6 = _gauss_nodes(6)
"""6-point nodes and weights, built at import (leggauss solves an eigenproblem: a third
of :func:`mean_radius`'s time per call, and the first call's in a fresh process)."""
_GAUSS6_LISTS = (_GAUSS6[0].tolist(), _GAUSS6[1].tolist())


def _distance_integral(pts: FloatArray) -> float:
    """⅓ ∮ |p| (x dy − y dx) over the closed polyline ``pts`` (N, 2)."""
    d = np.concatenate([pts[1:], pts[:1]]) - pts
    t, w = _GAUSS6
    p = pts[:, None, :] + d[:, None, :] * t[None, :, None]
    rho = np.hypot(p[..., 0], p[..., 1])
    cross = p[..., 0] * d[:, None, 1] - p[..., 1] * d[:, None, 0]
    return float((rho * cross * w).sum() / 3.0)


def profile_floor(part: Part, physics: Physics, size: float | None = None) -> float:
    """The manufacturing floor of σ (part units per radian): the given profile tolerance,
    or ISO 2768-1 class f for the part's size (its :func:`nominal_size`, when known)."""
    if physics.profile_tolerance is not None:
        return physics.profile_tolerance
    mm_per_unit = 1e3 * meters_per_unit(part.units)
    return iso_2768_f_mm((nominal_size(part) if size is None else size) * mm_per_unit) / mm_per_unit


_NOMINAL_DIRECTIONS = 90
"""Directions sampled for the largest width (2° apart: within 0.06 % of the true maximum)."""


def _nominal_directions() -> tuple[FloatArray, FloatArray, FloatArray]:
    """The sampled normals ψ and ψ + π (one array), cos ψ and sin ψ: fixed, so made once
    at import (read-only)."""
    psi = np.linspace(0.0, np.pi, _NOMINAL_DIRECTIONS, endpoint=False)
    out = (np.concatenate([psi, psi + np.pi]), np.cos(psi), np.sin(psi))
    for a in out:
        a.setflags(write=False)
    return out


_NOMINAL_PSI, _NOMINAL_COS, _NOMINAL_SIN = _nominal_directions()
_NOMINAL_LISTS = tuple(a.tolist() for a in _nominal_directions())
"""The same as float lists, for the compiled kernel."""


def nominal_size(part: Part) -> float:
    """The part's largest width (part units): the nominal size tolerance tables use.
    A hull of vertices only: compiled when built (:mod:`algrasp.compiled`), the same value."""
    table = part.hull.table
    if GEOMETRY is not None and table.vertices_only:
        return GEOMETRY.widest(table.breakpoint_list, [f.center for f in part.hull.features],  # type: ignore[no-any-return]
                               *_NOMINAL_LISTS)
    both = part.hull.support_points(_NOMINAL_PSI)
    chord = both[:_NOMINAL_DIRECTIONS] - both[_NOMINAL_DIRECTIONS:]
    return float((chord[:, 0] * _NOMINAL_COS + chord[:, 1] * _NOMINAL_SIN).max())


@dataclass(frozen=True)
class PartTerms:
    """What the dead band takes from the part alone (not from the physics): r̄ and the
    nominal size (part units) and the drawing's own error. Computed once per analysis and
    reused by the probes of a limit search, which vary only the physics."""

    mean_radius: float
    error: DrawingError
    nominal_size: float


def part_terms(part: Part, tol: Tolerances) -> PartTerms:
    """:class:`PartTerms` of the part. O(n)."""
    return PartTerms(mean_radius(part), drawing_error(part.boundary, tol), nominal_size(part))


def dead_band(part: Part, physics: Physics, tol: Tolerances, terms: PartTerms) -> DeadBand:
    """The part's dead band under the physics ranges, given its own terms. O(1)."""
    rbar, err = terms.mean_radius, terms.error
    floor = profile_floor(part, physics, terms.nominal_size)
    sigma = max(err.slope, floor) if physics.shape_tolerance is None else max(physics.shape_tolerance, floor)
    eps_c = COM_TOLERANCE_REL * part.size if physics.com_tolerance is None else physics.com_tolerance
    # Symmetry is judged on the drawing (its own error; a measured σ bounds position at ~3°
    # of turn); a profile tolerance t moves each contact point of the real part by at most
    # t, so d and r (and their slopes, per radian) by at most t: the barriers' value error.
    drawn = sigma if physics.shape_tolerance is not None else err.slope
    value = max(err.value, tol.symmetry_value_rel * part.size, 0.05 * drawn)
    lo, hi = physics.stall_ratio
    return DeadBand(lo * max(rbar - eps_c, 0.0), hi * (rbar + eps_c), physics.jaw_friction[1], 2.0 * sigma,
                    sigma + eps_c, value, value, rbar, eps_c, floor, max(value, floor), (*part.recognised, *err.sources))
