"""Push distances: how far the lower jaw must push so that the part reaches its
push-function fixed point, from every orientation of a plan step's input interval.

Mechanics (the model of the Drake validation, ``algrasp.sim.config``): a frictionless
straight pusher moving along the closing axis n touches the part at its lowest hull
point q (relative to the centre of mass, gripper frame). Support friction follows the
ellipsoidal limit surface with m_max / f_max = c (``c`` = the mean distance r̄ of the
region's points from the centre of mass). The contact force λn has moment λ q_x; the
quasi-static twist is normal to the ellipsoid, (v, ω) ∝ (λn / f², λ q_x / (f c)²), and
the contact point must move with the pusher, so per unit of push distance s

    dθ/ds = q_x(θ) / (c² + q_x(θ)²),            q_x(θ) = −r′(θ),

which drives θ monotonically to the local minimum of r that the push function p
predicts. Peshkin's bound [paper, ref. 29] takes the slowest rotation any pressure
distribution inside the disk of radius a (the smallest disk centred on the centre of
mass that covers the part) allows: the same law with c = a. Since the rate falls with
c and r̄ ≤ a, the optimised distance never exceeds the bound.

The dynamics are integrated in θ rather than in s: integrating dθ/ds in s is stiff at an
edge-aligned fixed point (q_x jumps sign; fixed-step RK4 chatters across it by more than
the tolerance), while its inverse ds/dθ is smooth up to the tolerance band where the
push is complete. The worst case over the initial orientation is exact (see
``_worst_case``): the far end of each monotone basin.

Starting exactly at an unstable equilibrium (a local maximum of r, a step boundary of
p), the part never turns; the needed distance grows without bound near it. As in the
validation, orientations within ``band_rad`` of an unstable equilibrium are excluded
from the worst case (stated in every result).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from algrasp.errors import AlgraspError
from algrasp.geometry.angles import TWO_PI, to_deg, wrap_deg
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.hull import unit
from algrasp.planning.analysis import Analysis

TABLE_POINTS = 7200
"""Samples of q_x(θ) per turn (0.05°): exact support points, linearly interpolated."""
PATH_STEPS = 400
"""Simpson steps along the orientation path."""
MIN_LEVER_REL = 1e-9
"""|q_x| floor (relative to the covering radius) where the push law is inverted."""


@dataclass(frozen=True)
class PushResult:
    """Push distance of one push-grasp step (part units) with its evidence.

    ``distance`` the worst case over the step's starts of the push law's distance; ``bound`` Peshkin's covering-disk bound;
    ``worst_start_deg`` the relative orientation that needs it, turning to
    ``fixed_point_deg``; ``candidates`` number of basins (monotone start ranges) considered."""

    distance: float
    bound: float
    worst_start_deg: float
    fixed_point_deg: float
    candidates: int
    tolerance_deg: float
    band_deg: float


@dataclass(frozen=True, eq=False)
class PushModel:
    """q_x(θ) of a part (exact support points on a grid) and its friction radii."""

    theta: FloatArray  # (TABLE_POINTS + 1,) radians over [0, 2π]
    lever: FloatArray  # q_x at theta, part units
    mean_radius: float  # c = r̄
    cover_radius: float  # a: largest distance from the centre of mass to the hull
    height: FloatArray | None = None
    """r(θ) at theta (part units) when the jaw has friction (None: frictionless)."""
    jaw_friction: float = 0.0

    def rate(self, q: FloatArray, r: FloatArray, c: FloatArray) -> FloatArray:
        """|dθ/ds| with jaw friction μ (conventions §8; frictionless: |q|/(c² + q²)).

        The contact sticks to the jaw while the force the sticking twist needs stays in
        the friction cone, |q| r ≤ μ (c² + r²); then the contact moves with the jaw and
        ω (c² + q² + r²) = |q|. Otherwise it slides and friction takes μ·r off the lever:
        ω = (|q| − μ r) / (c² + |q| (|q| − μ r))."""
        a = np.abs(q)
        mu = self.jaw_friction
        stick = a * r <= mu * (c * c + r * r)
        lever = np.maximum(a - mu * r, 0.0)
        slide = lever / (c * c + a * lever)
        return np.where(stick, a / (c * c + a * a + r * r), slide)  # type: ignore[no-any-return]

    def path_distances(self, start: FloatArray, end: FloatArray, c: FloatArray) -> FloatArray:
        """Push distance to turn from each ``start`` to ``end`` (radians, lifted; shape
        (B,)) for friction radii ``c`` (B,): the push law inverted along the path,
        s = ∫ (c² + q_x²)/|q_x| dθ, by composite Simpson with PATH_STEPS steps through a
        linear interpolant of q_x. O(B·PATH_STEPS), vectorised."""
        u = np.linspace(0.0, 1.0, 2 * PATH_STEPS + 1)
        theta = start[:, None] + (end - start)[:, None] * u[None, :]
        wrapped = np.mod(theta, TWO_PI)
        q = np.interp(wrapped, self.theta, self.lever)
        floor = MIN_LEVER_REL * self.cover_radius
        if self.height is None:
            g = (c[:, None] ** 2 + q * q) / np.maximum(np.abs(q), floor)
        else:
            r = np.interp(wrapped, self.theta, self.height)
            g = 1.0 / np.maximum(self.rate(q, r, np.broadcast_to(c[:, None], q.shape)), floor / self.cover_radius ** 2)
        w = np.ones(2 * PATH_STEPS + 1)
        w[1:-1:2], w[2:-1:2] = 4.0, 2.0
        return np.abs((end - start) / (6 * PATH_STEPS) * (g @ w))  # type: ignore[no-any-return]


def push_model(analysis: Analysis, mean_radius: float, jaw_friction: float = 0.0) -> PushModel:
    """Tabulate q_x(θ) from the exact hull: the lowest point in the gripper frame of the
    part at relative orientation θ is its support point in direction R(−θ)(0, −1). With
    jaw friction (the largest of the ranges) r(θ) too: pushes are long enough for a
    contact that sticks."""
    part = analysis.part
    theta = np.linspace(0.0, TWO_PI, TABLE_POINTS + 1)
    pts = part.hull.support_points(-np.pi / 2 - theta) - np.asarray(part.center_of_mass)
    lever = np.sum(pts * unit(-theta), axis=-1)
    psi = np.linspace(0.0, TWO_PI, 4096, endpoint=False)
    cover = float(np.max(np.hypot(*(part.hull.support_points(psi) - np.asarray(part.center_of_mass)).T)))
    height = None if jaw_friction <= 0.0 else np.abs(np.sum(pts * unit(np.pi / 2 - theta), axis=-1))
    return PushModel(theta, lever, mean_radius, cover, height, jaw_friction)


@dataclass(frozen=True)
class Basin:
    """Starts [lo, hi] (radians, lifted) that all flow to ``target`` = f ∓ tol; ``far``
    is the end of [lo, hi] farther from the target."""

    lo: float
    hi: float
    target: float
    fixed_point: float

    @property
    def far(self) -> float:
        return self.lo if self.target >= self.hi else self.hi


def basins(analysis: Analysis, interval: tuple[float, float], band_rad: float, tol_rad: float) -> list[Basin]:
    """The parts of ``interval`` in each step of p, minus ``band_rad`` around its ends
    (unstable equilibria), split at the fixed point, minus starts already within tol."""
    p = analysis.push
    a, b = interval
    k0 = int(np.floor((a - p.pieces[0].start) / p.period)) - 1
    out = []
    for k in range(k0, k0 + 4):
        for piece in p.steps:
            s = piece.shifted(k * p.period)
            assert s.value is not None
            lo, hi = max(a, s.start + band_rad), min(b, s.end - band_rad)
            f = s.value
            for x, y, t in ((lo, min(hi, f - tol_rad), f - tol_rad), (max(lo, f + tol_rad), hi, f + tol_rad)):
                if x < y:
                    out.append(Basin(x, y, t, f))
    return out


def _worst_case(model: PushModel, groups: list[list[Basin]]) -> list[tuple[float, float, float]]:
    """Worst-case push distance per step, for c = r̄ and (Peshkin's bound) c = a.

    The flow is one-dimensional and monotone: a start farther from the fixed point passes
    through every nearer start on its way, so over a basin the needed distance is
    maximised at its far end — the maximiser is known exactly and only the path
    integrals are computed (one vectorised quadrature over all basins and both c).
    Returns (distance, bound, worst start) per step."""
    flat = [b for g in groups for b in g]
    K = len(flat)
    far = np.array([b.far for b in flat] * 2)
    target = np.array([b.target for b in flat] * 2)
    cs = np.array([model.mean_radius] * K + [model.cover_radius] * K)
    ss = model.path_distances(far, target, cs)
    if not np.all(np.isfinite(ss)):
        raise AlgraspError("push distance: the push law could not be integrated (degenerate part?)")
    out, i = [], 0
    for g in groups:
        own, cover = ss[i:i + len(g)], ss[K + i:K + i + len(g)]
        w = int(np.argmax(own))
        out.append((float(own[w]), float(np.max(cover)), float(far[i + w])))
        i += len(g)
    return out


def push_distances(model: PushModel, analysis: Analysis, intervals: list[tuple[float, float]],
                   tol_rad: float, band_rad: float) -> list[PushResult]:
    """Optimised push distances of push-grasp steps whose relative orientations lie in
    ``intervals`` (radians, lifted). Cost: 2·PATH_STEPS·3 table lookups per basin (tens
    of milliseconds for the paper's parts)."""
    groups = [basins(analysis, interval, band_rad, tol_rad) for interval in intervals]
    live = [g for g in groups if g]
    solved = iter(_worst_case(model, live) if live else [])
    tol_deg, band_deg = float(to_deg(tol_rad)), float(to_deg(band_rad))
    out = []
    for interval, g in zip(intervals, groups):
        if not g:
            start = wrap_deg(to_deg(interval[0]))
            out.append(PushResult(0.0, 0.0, start, start, 0, tol_deg, band_deg))
            continue
        d, bound, worst = next(solved)
        f = min(g, key=lambda b: abs(b.far - worst)).fixed_point
        out.append(PushResult(d, bound, wrap_deg(to_deg(worst)), wrap_deg(to_deg(f)), len(g),
                              tol_deg, band_deg))
    return out
