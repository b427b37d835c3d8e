"""The fence model (conventions §9): the push a fence applies, which fence angles are
admissible, and a fence design with its margins. Pure: no I/O; angles in radians.

The belt moves along world +x. Fence i is a wall at world angle α_i that acts on the part
as the gripper's lower jaw L at α_i, so passing it maps the world orientation φ to
``p(φ − α_i) + α_i`` (p the push function: exact, or the set-valued push of §7 on a belt,
:func:`on_belt`), tilted by the fence's friction on its rail
(:mod:`~algrasp.planning.fence_friction`; :meth:`Push.image` with the fence's angle).
A part slides along a fence only when the fence's steepness β (its angle to the belt
direction) satisfies ``β_min ≤ β < 90° − atan μ_f`` for the largest part–fence
friction μ_f; a fence on the right rail (y = 0) has α = β, one on the left rail (y = W)
α = 180° − β.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from algrasp.errors import ConfigError, NotOrientableError
from algrasp.geometry.angles import to_deg, to_rad
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.functions import SupportPairFunction
from algrasp.geometry.tolerances import ROUNDING, SYMMETRY_TOL_RAD
from algrasp.planning.analysis import Analysis, robust_analysis
from algrasp.planning.fence_friction import NO_TILT, Tilt, fence_tilt
from algrasp.planning.transfer import TransferFunction

EXIT_STEEPNESS_RAD = to_rad(2.0)
"""β_e: the exit guide's default angle to the belt (:mod:`algrasp.planning.fence_exit`)."""
DEFAULT_FENCE_FRICTION = (0.1, 0.3)
"""μ_f: UHMW-PE guide rail (the usual fence facing) on dry metal or plastic parts:
handbook 0.1–0.2, up to 0.3 worn or dusty (conventions §9)."""
MIN_STEEPNESS_RAD = to_rad(10.0)
"""β_min: a fence flatter than 10° to the belt is over 5.8 belt widths long."""
GRID_RAD = to_rad(0.5)
"""Fence angles tried: every 0.5° of each side's admissible set."""
MARGIN_STEPS_RAD = to_rad(np.arange(0.25, 10.01, 0.25))
"""Margins tried per fence (each must hold on both sides)."""


@dataclass(frozen=True, eq=False)
class Push:
    """The push function as a fence sees it: bounds of its images, the symmetry period T,
    the arc (relative, lifted) every orientation lands in after one frictionless fence,
    and the fence friction's :class:`~algrasp.planning.fence_friction.Tilt` per rail
    (right, left) for the friction range ``friction`` (radius function ``radius``)."""

    lower: TransferFunction
    upper: TransferFunction
    symmetry: float
    circle: tuple[float, float]
    exact: bool
    radius: SupportPairFunction | None = None
    friction: tuple[float, float] = (0.0, 0.0)
    tilt: tuple[Tilt, Tilt] = NO_TILT

    def with_friction(self, friction: tuple[float, float]) -> Push:
        """This push with the tilt of the fence friction range ``friction`` (itself when unchanged)."""
        if friction == self.friction or self.radius is None:
            return self
        return replace(self, friction=friction, tilt=fence_tilt(self.radius, friction))

    def circle_at(self, alpha: FloatArray | float) -> tuple[FloatArray, FloatArray]:
        """The arc (relative to a fence at world angle α, lifted) every orientation lands in
        after it: ``circle`` widened by the rests' shifts on its rail (radians, arrays like α)."""
        lo, hi = np.broadcast_arrays(np.full(np.shape(alpha), self.circle[0]), np.full(np.shape(alpha), self.circle[1]))
        return self._moved(lo, hi, alpha)

    def _moved(self, a: FloatArray, b: FloatArray, alpha: FloatArray | float) -> tuple[FloatArray, FloatArray]:
        """Image arcs [a, b] with their ends moved by the rests' shifts on α's rail."""
        if self.tilt is NO_TILT or not (self.tilt[0].moves_rests or self.tilt[1].moves_rests):
            return a, b
        return self._per_rail(alpha, lambda t: t.rest_shift(a, b), a, b, add=True)

    def _per_rail(self, alpha: FloatArray | float, f: Callable[[Tilt], tuple[FloatArray, FloatArray]],
                  lo: FloatArray, hi: FloatArray, add: bool = False) -> tuple[FloatArray, FloatArray]:
        """``f`` of the rail of each α (one rail's only when all α share it), added to
        (lo, hi) with ``add``."""
        right = np.asarray(alpha, dtype=float) < 0.5 * np.pi
        if right.all() or not right.any():
            x, y = f(self.tilt[0] if right.all() else self.tilt[1])
        else:
            (rx, ry), (lx, ly) = f(self.tilt[0]), f(self.tilt[1])
            x, y = np.where(right, rx, lx), np.where(right, ry, ly)
        return (lo + x, hi + y) if add else (x, y)

    def image(self, lo: FloatArray, hi: FloatArray,
              alpha: FloatArray | float | None = None) -> tuple[FloatArray, FloatArray]:
        """Hull of the images of the closed arcs [lo, hi] (radians, lifted, relative to a
        fence at world angle α, which sets the rail and so the friction's tilt:
        ``lower(m_lo(lo)) + o_lo``, ``upper(m_hi(hi)) + o_hi``; None: no tilt), lo moved to [0, T)."""
        lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
        tilted = alpha is not None and self.tilt is not NO_TILT
        if tilted:
            lo, hi = self._per_rail(alpha, lambda t: (t.map_lo(lo), t.map_hi(hi)), lo, hi)  # type: ignore[arg-type]
        k = np.floor(lo / self.symmetry) * self.symmetry
        a, b = self.lower.apply(lo - k) + k, self.upper.apply(hi - k) + k
        if tilted:
            a, b = self._moved(a, b, alpha)  # type: ignore[arg-type]
        k2 = np.floor(a / self.symmetry) * self.symmetry
        return a - k2, b - k2


def on_belt(analysis: Analysis) -> Analysis:
    """The analysis as a fence sees the part: a part pushed by a fence slides on the belt
    (in the belt's frame a fence pushes it across a still support), so it turns whichever
    way the contact normal passes its centre of mass, at any support friction (Mason's
    voting theorem): the set-valued push has no stall band; the shape, profile and
    centre-of-mass bands of §7–§8 stay. The exact model is returned as it is."""
    if analysis.robust is None or analysis.robust.physics.support_friction == (0.0, 0.0):
        return analysis
    physics = analysis.robust.physics.merged({"support_friction": [0.0, 0.0]})
    robust = robust_analysis(analysis.part, analysis.diameter, analysis.radius, physics, analysis.tol,
                             analysis.robust.terms)
    return replace(analysis, robust=robust)


def push_of(analysis: Analysis, friction: tuple[float, float] | None = None) -> Push:
    """The exact push (``--exact``) or the set-valued one of the robust model (§7) on the
    belt (:func:`on_belt`), tilted by the fence friction range ``friction`` (None: the
    default, ``DEFAULT_FENCE_FRICTION``; :mod:`~algrasp.planning.fence_friction`).

    Raises NotOrientableError (``no_step``, ``dead_band``) when no fence can orient the part."""
    analysis = on_belt(analysis)
    p = analysis.push
    if not p.steps:
        raise NotOrientableError("no_step", "the push function has no step (constant radius about the centre of "
                                 "mass, e.g. a disk): no fence can orient the part")
    mu = DEFAULT_FENCE_FRICTION if friction is None else (float(friction[0]), float(friction[1]))
    if analysis.robust is None:
        T = p.symmetry_period(SYMMETRY_TOL_RAD)
        return Push(p, p, T, p.circle_images(T)[0], True, analysis.radius).with_friction(mu)
    S = analysis.robust.push
    if S is None or not S.orientable:
        raise NotOrientableError("dead_band", analysis.robust.reasons.get("push") or "with the dead band every "
                                 "orientation may stay where it is: no fence can orient the part")
    return Push(S.lower, S.upper, S.symmetry, S.circle_images()[0], False, analysis.radius).with_friction(mu)


@dataclass(frozen=True)
class FenceRules:
    """Which fence angles are admissible: friction range μ_f and the least steepness."""

    friction: tuple[float, float] = DEFAULT_FENCE_FRICTION
    min_steepness: float = MIN_STEEPNESS_RAD
    exit_steepness: float | None = EXIT_STEEPNESS_RAD
    """β_e of the exit guide the design must also collapse through (None: no guide)."""
    exit_turns: bool = True
    """Model the turn a part takes over each fence's tip (:func:`exit_turn`); False is
    Berretty et al.'s model, in which the part keeps its orientation between fences."""
    same_rail: bool = False
    """Let consecutive fences stand on one rail (the layout then makes the later reach
    further across the belt); False: they alternate rails (conventions §9)."""

    @property
    def max_steepness(self) -> float:
        """β < 90° − atan μ_f,hi: steeper fences hold the part (radians)."""
        return 0.5 * np.pi - math.atan(self.friction[1])

    def grid(self, side: int) -> FloatArray:
        """Admissible world angles α (radians) of side 0 (right, α = β) or 1 (left, α = π − β)."""
        beta = np.arange(self.min_steepness, self.max_steepness - ROUNDING, GRID_RAD)
        return beta if side == 0 else np.pi - beta

    def slacks(self, alpha: FloatArray) -> FloatArray:
        """:meth:`slack` of every angle of an array (radians)."""
        beta = np.where(alpha < 0.5 * np.pi, alpha, np.pi - alpha)
        return np.asarray(np.minimum(beta - self.min_steepness, self.max_steepness - beta))

    def slack(self, alpha: float) -> float:
        """How far α may move and stay admissible (radians; ≤ 0: not admissible)."""
        beta = alpha if alpha < 0.5 * np.pi else np.pi - alpha
        return min(beta - self.min_steepness, self.max_steepness - beta)


DEFAULT_RULES = FenceRules()


def fence_rules(friction: tuple[float, float] | list[float] | float | None = None) -> FenceRules:
    """Rules for a friction range (a number or [lo, hi]; None: the default).

    Raises ConfigError (``fence_friction``) unless 0 ≤ lo ≤ hi < tan(90° − β_min)."""
    if friction is None:
        return DEFAULT_RULES
    values = [friction] if isinstance(friction, (int, float)) else list(friction)
    top = math.tan(0.5 * np.pi - MIN_STEEPNESS_RAD)
    if len(values) not in (1, 2) or not all(isinstance(v, (int, float)) and math.isfinite(v) for v in values):
        raise ConfigError("fence_friction", f"expected a number or [lo, hi], got {friction!r}")
    lo, hi = float(values[0]), float(values[-1])
    if not (0.0 <= lo <= hi < top):
        raise ConfigError("fence_friction", f"expected 0 ≤ lo ≤ hi < {top:.3g} (μ_f ≥ tan "
                          f"{90 - to_deg(MIN_STEEPNESS_RAD):g}° leaves no admissible fence), got [{lo:g}, {hi:g}]")
    return FenceRules((lo, hi))


@dataclass(frozen=True, eq=False)
class FenceDesign:
    """A verified fence sequence. Angles in radians.

    Attributes
    ----------
    angles : tuple of float
        α_i in the order the part meets them (world, (0, π)).
    sides : tuple of int
        0 right (y = 0, α = β), 1 left (y = W, α = π − β).
    margins : tuple of float
        How far each α_i may be off, the others as designed (radians).
    inputs : tuple of (float, float)
        The arc of orientations relative to each fence the part arrives in (lifted;
        the first is the whole circle, (0, 2π)).
    final_orientations : tuple of float
        World orientations the part leaves in, [0, 2π), one per symmetry period.
    final_uncertainty : float
        Half-width (radians) around each final orientation.
    symmetry : float
        T of the push function (radians).
    rules : FenceRules
        The friction range and steepness the angles were chosen under.
    """

    angles: tuple[float, ...]
    sides: tuple[int, ...]
    margins: tuple[float, ...]
    inputs: tuple[tuple[float, float], ...]
    final_orientations: tuple[float, ...]
    final_uncertainty: float
    symmetry: float
    rules: FenceRules
    exact: bool

    def run(self, push: Push, phi: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Hull of the world orientations on the last fence from each φ (radians): every
        fence's push, and between fences the way off its tip of :func:`leave`."""
        return self.run_each(push, phi)[-1]

    def run_each(self, push: Push, phi: FloatArray) -> list[tuple[FloatArray, FloatArray]]:
        """:meth:`run`'s hull on each fence in turn (world, radians), one (lo, hi) per fence."""
        lo = hi = np.asarray(phi, dtype=float)
        out = []
        for i, a in enumerate(self.angles):
            if i > 0:
                lo, hi = leave(lo, hi, self.angles[i - 1], self.rules.exit_turns)
            lo, hi = push.image(lo - a, hi - a, a)
            lo, hi = lo + a, hi + a
            out.append((lo, hi))
        return out


def exit_turn(lo: FloatArray | float, hi: FloatArray | float,
              alpha: FloatArray | float) -> tuple[FloatArray, FloatArray]:
    """The arcs [lo, hi] (orientations, radians; any frame) widened by the turn a part may
    take as it leaves a fence at world angle α over its tip: towards the belt direction,
    by at most the fence's steepness β (clockwise, lo − β, on the right rail α = β;
    counter-clockwise, hi + β, on the left α = π − β). The belt's drag presses the part
    against the tip only while its contact normal has a component against the belt; that
    normal turns with the part (and with the contact moving round a convex part) from
    steepness β to 0, so the part turns by some t ∈ [0, β] (conventions §9). O(n)."""
    a = np.asarray(alpha, dtype=float)
    right = a < 0.5 * np.pi
    lo_, hi_ = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    return np.where(right, lo_ - a, lo_), np.where(right, hi_, hi_ + (np.pi - a))


def guide_angle(alpha: FloatArray | float, steepness: float) -> FloatArray:
    """α_e of the exit guide on the rail of a last fence at α: β_e right, π − β_e left."""
    a = np.asarray(alpha, dtype=float)
    return np.where(a < 0.5 * np.pi, steepness, np.pi - steepness)


def to_guide(lo: FloatArray, hi: FloatArray, last: FloatArray | float,
             guide: FloatArray | float) -> tuple[FloatArray, FloatArray]:
    """The arcs [lo, hi] the part is in on the last fence at α_N = ``last`` (relative to
    it, radians) as it arrives at the exit guide at α_e = ``guide``: turned over the
    fence's tip (:func:`exit_turn`, always: the guide is there to take that turn back),
    relative to the guide. O(n)."""
    lo, hi = exit_turn(lo, hi, last)
    shift = np.asarray(last, dtype=float) - np.asarray(guide, dtype=float)
    return lo + shift, hi + shift


def guide_image(push: Push, lo: FloatArray, hi: FloatArray, last: FloatArray | float,
                guide: FloatArray | float) -> tuple[FloatArray, FloatArray]:
    """The exit guide's push (tilted at its angle, as every fence's) of the arcs [lo, hi]
    the part is in on the last fence at ``last`` (relative to it): :func:`to_guide`, then
    :meth:`Push.image`; the result relative to the guide at ``guide`` (radians)."""
    return push.image(*to_guide(lo, hi, last, guide), guide)


def leave(lo: FloatArray, hi: FloatArray, alpha: FloatArray | float, turns: bool) -> tuple[FloatArray, FloatArray]:
    """The arcs [lo, hi] (any frame, radians) the part may be in when it has left the fence
    at α over its tip: :func:`exit_turn` with ``turns`` (the default model), unchanged
    without (Berretty et al.'s model, in which a part keeps its orientation between fences)."""
    if not turns:
        return np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    return exit_turn(lo, hi, alpha)


def collapse_width(push: Push, angles: FloatArray, exit_steepness: float | None = None,
                   turns: bool = True) -> FloatArray:
    """Width of the final arc of each design (rows of ``angles``, (m, N), radians), from
    every start: the first fence leaves the part in ``push.circle``, and it leaves each
    fence over its tip (:func:`leave`, with ``turns``). With ``exit_steepness`` the wider
    of the arc on the last fence and the arc the exit guide pushes the part back into
    (the last fence's tip turns it by at most β_N first); without, the arc on the last fence."""
    lo, hi = push.circle_at(angles[:, 0])
    for i in range(1, angles.shape[1]):
        lo, hi = leave(lo, hi, angles[:, i - 1], turns)
        shift = angles[:, i - 1] - angles[:, i]
        lo, hi = push.image(lo + shift, hi + shift, angles[:, i])
    if exit_steepness is None:
        return np.asarray(hi - lo)
    last = angles[:, -1]
    guide = guide_angle(last, exit_steepness)
    glo, ghi = guide_image(push, lo, hi, last, guide)
    return np.asarray(np.maximum(hi - lo, ghi - glo))


def held_range(push: Push, rules: FenceRules, angles: FloatArray, i: int, goal: float,
          admissible_only: bool = True) -> tuple[FloatArray, FloatArray]:
    """For each design (rows of ``angles``, (K, N)), how far α_i may move up and down (the
    others as designed) with it still collapsing to ``goal`` and (``admissible_only``) α_i
    admissible and on its rail: two (K,) arrays in radians, from ``MARGIN_STEPS_RAD``. One vectorised pass."""
    K, N = angles.shape
    M = len(MARGIN_STEPS_RAD)
    trial = np.repeat(angles[:, None, :], 2 * M, axis=1)
    trial[:, :, i] += np.concatenate([MARGIN_STEPS_RAD, -MARGIN_STEPS_RAD])[None, :]
    ok = (collapse_width(push, trial.reshape(-1, N), rules.exit_steepness, rules.exit_turns) <= goal).reshape(K, 2, M)
    if admissible_only:  # admissible, and on its own rail (frictionless fences: no gap at 90° to stop it)
        moved = trial[:, :, i]
        ok &= ((rules.slacks(moved) > 0.0) & ((moved < 0.5 * np.pi) == (angles[:, None, i] < 0.5 * np.pi))).reshape(K, 2, M)
    n = np.where(ok.all(axis=2), M, np.argmin(ok, axis=2))  # leading steps that hold
    held = np.where(n > 0, MARGIN_STEPS_RAD[np.maximum(n - 1, 0)], 0.0)
    return held[:, 0], held[:, 1]


def margins(push: Push, rules: FenceRules, angles: FloatArray, goal: float) -> FloatArray:
    """(K, N): per design and fence, the largest tried margin m with α_i ± m (the others as
    designed) still collapsing to ``goal`` and admissible (radians; 0: not even the smallest)."""
    out = np.zeros(angles.shape)
    for i in range(angles.shape[1]):
        up, down = held_range(push, rules, angles, i, goal)
        out[:, i] = np.minimum(np.minimum(up, down), np.maximum(rules.slacks(angles[:, i]), 0.0))
    return out


def centred(push: Push, rules: FenceRules, angles: FloatArray, goal: float, sweeps: int = 3) -> FloatArray:
    """The designs (K, N) with each angle moved, in turn, to the middle of the range it may
    take with the others fixed (``sweeps`` passes): the search's grid angles sit at the edges."""
    out = np.array(angles, dtype=float)
    for _ in range(sweeps):
        for i in range(out.shape[1]):
            up, down = held_range(push, rules, out, i, goal)
            out[:, i] += 0.5 * (up - down)
    return out
