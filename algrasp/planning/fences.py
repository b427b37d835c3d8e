"""Conveyor fences (conventions §9): the fewest fences that orient a part on a belt.

The belt moves along world +x. Fence i is a wall at world angle α_i that acts on the part
as the gripper's lower jaw L at α_i, so passing it maps the world orientation φ to
``p(φ − α_i) + α_i`` (p the push function: exact, or the set-valued push of §7). A part
slides along a fence only when the fence's steepness β (its angle to the belt direction)
satisfies ``β_min ≤ β < 90° − atan μ_f`` for the largest part–fence friction μ_f; a fence on
the right side (y = 0) has α = β, one on the left side (y = W) α = 180° − β, and fences
alternate sides. So consecutive angles differ by δ = α_{i+1} − α_i in
``(2 atan μ_f, 180° − 2β_min]`` (right → left) or its negative (left → right), and the
angles themselves stay in the admissible set.

The search is breadth-first over designs: fence angles on a grid of each side's
admissible set; a state is the arc of orientations (relative to its last fence) the part
may be in and the last fence's angle; for each fence angle the ``BEAM`` narrowest arcs
are kept. The first level with an arc that collapses to one orientation (up to p's
symmetry T) with every fence angle holding ``min_margin`` wins; among its designs the
shortest (an injected length, the fence layout's) then the widest margin is taken.
Pure: no I/O; angles in radians.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from algrasp.errors import ConfigError, NotOrientableError
from algrasp.geometry.angles import to_deg, to_rad
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.tolerances import MAX_UNCERTAINTY_RAD, ROUNDING, SYMMETRY_TOL_RAD, UNCERTAINTY_FLOOR_RAD
from algrasp.planning.analysis import Analysis, robust_analysis
from algrasp.planning.planner import GUARD_RAD, PRECISE_RAD
from algrasp.planning.plans import _edge_tilt
from algrasp.planning.transfer import TransferFunction

DEFAULT_FENCE_FRICTION = (0.1, 0.3)
"""μ_f: UHMW-PE guide rail (the usual fence facing) on dry metal or plastic parts:
handbook 0.1–0.2, up to 0.3 worn or dusty (conventions §9)."""
MIN_STEEPNESS_RAD = to_rad(10.0)
"""β_min: a fence flatter than 10° to the belt is over 5.8 belt widths long."""
GRID_RAD = to_rad(0.5)
"""Fence angles tried: every 0.5° of each side's admissible set."""
BEAM = 4
"""Arcs kept per fence angle and level (the narrowest)."""
MAX_FENCES = 12
DEFAULT_MIN_MARGIN_DEG = 1.0
"""How far (°) every fence angle may be off by default: a fence is set by hand to about a degree."""
MARGIN_STEPS_RAD = to_rad(np.arange(0.25, 10.01, 0.25))
"""Margins tried per fence (each must hold on both sides)."""
CANDIDATES = 64
"""Designs of the winning level compared (spread evenly over the fence angles that reach it)."""
MAX_HITS = 1024
"""States of a level tried before it is given up when none of the first ``CANDIDATES`` holds."""
EXACT_GOAL_RAD = 1e-9
LIMIT_PROBES = 6
"""Bisection steps of the friction limit named in a refusal."""


@dataclass(frozen=True, eq=False)
class Push:
    """The push function as a fence sees it: bounds of its images, the symmetry period T
    and the arc (relative, lifted) every orientation lands in after one fence."""

    lower: TransferFunction
    upper: TransferFunction
    symmetry: float
    circle: tuple[float, float]
    exact: bool

    def image(self, lo: FloatArray, hi: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Hull of the images of the closed arcs [lo, hi] (radians, lifted), lo moved to [0, T)."""
        k = np.floor(lo / self.symmetry) * self.symmetry
        a, b = self.lower.apply(lo - k), self.upper.apply(hi - k)
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


def push_of(analysis: Analysis) -> Push:
    """The exact push (``--exact``) or the set-valued one of the robust model (§7) on the
    belt (:func:`on_belt`).

    Raises NotOrientableError (``no_step``, ``dead_band``) when no fence can orient the part."""
    analysis = on_belt(analysis)
    p = analysis.push
    if not p.steps:
        raise NotOrientableError("no_step", "the push function has no step (constant radius about the centre of "
                                 "mass, e.g. a disk): no fence can orient the part")
    if analysis.robust is None:
        T = p.symmetry_period(SYMMETRY_TOL_RAD)
        return Push(p, p, T, p.circle_images(T)[0], True)
    S = analysis.robust.push
    if S is None or not S.orientable:
        raise NotOrientableError("dead_band", analysis.robust.reasons.get("push") or "with the dead band every "
                                 "orientation may stay where it is: no fence can orient the part")
    return Push(S.lower, S.upper, S.symmetry, S.circle_images()[0], False)


@dataclass(frozen=True)
class FenceRules:
    """Which fence angles are admissible: friction range μ_f and the least steepness."""

    friction: tuple[float, float] = DEFAULT_FENCE_FRICTION
    min_steepness: float = MIN_STEEPNESS_RAD

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
    """Rules for a friction range (a number or [lo, hi]; None: the default)."""
    lo, hi = (DEFAULT_FENCE_FRICTION if friction is None else
              (friction, friction) if isinstance(friction, (int, float)) else tuple(friction) * (2 // len(friction)))
    if not (0.0 <= lo <= hi < math.tan(0.5 * np.pi - MIN_STEEPNESS_RAD)):
        raise ConfigError("fence_friction", f"expected 0 ≤ lo ≤ hi < {math.tan(0.5 * np.pi - MIN_STEEPNESS_RAD):.3g} "
                          f"(μ_f ≥ tan {90 - to_deg(MIN_STEEPNESS_RAD):g}° leaves no admissible fence), got [{lo:g}, {hi:g}]")
    return FenceRules((float(lo), float(hi)))


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
        """Hull of the world orientations after every fence from each φ (radians)."""
        lo = hi = np.asarray(phi, dtype=float)
        for a in self.angles:
            lo, hi = push.image(lo - a, hi - a)
            lo, hi = lo + a, hi + a
        return lo, hi


@dataclass(frozen=True)
class _Level:
    """States of one search level: arcs [lo, hi] relative to the last fence, its angle
    and side, and the index of the parent state in the level before."""

    lo: FloatArray
    hi: FloatArray
    alpha: FloatArray
    side: np.ndarray
    parent: np.ndarray


def _first_level(push: Push, rules: FenceRules) -> _Level:
    alpha = np.concatenate([rules.grid(0), rules.grid(1)])
    side = np.repeat([0, 1], [len(rules.grid(0)), len(rules.grid(1))])
    n = len(alpha)
    return _Level(np.full(n, push.circle[0]), np.full(n, push.circle[1]), alpha, side, np.full(n, -1))


def _next_level(push: Push, rules: FenceRules, level: _Level) -> _Level:
    """Every state followed by every admissible angle of the other side, pruned to the
    ``BEAM`` narrowest distinct arcs per angle."""
    parts = []
    for s in (0, 1):
        idx = np.nonzero(level.side == s)[0]
        grid = rules.grid(1 - s)
        shift = level.alpha[idx, None] - grid[None, :]
        lo, hi = push.image(level.lo[idx, None] + shift, level.hi[idx, None] + shift)
        cols = np.broadcast_to(grid[None, :], lo.shape)
        parts.append((lo.ravel(), hi.ravel(), cols.ravel(), np.full(lo.size, 1 - s), np.repeat(idx, len(grid))))
    lo, hi, alpha, side, parent = (np.concatenate(x) for x in zip(*parts))
    keep = _prune(lo, hi, alpha, push.symmetry)
    return _Level(lo[keep], hi[keep], alpha[keep], side[keep], parent[keep])


def _prune(lo: FloatArray, hi: FloatArray, alpha: FloatArray, T: float) -> np.ndarray:
    """Indices of the ``BEAM`` narrowest distinct arcs per angle (arcs of width ≥ T dropped)."""
    w = hi - lo
    key_a, key_lo, key_hi = np.round(alpha, 9), np.round(lo, 9), np.round(hi, 9)
    order = np.lexsort((key_hi, key_lo, w, key_a))
    order = order[w[order] < T - SYMMETRY_TOL_RAD]
    a, l_, h = key_a[order], key_lo[order], key_hi[order]
    new = np.ones(len(order), dtype=bool)
    new[1:] = (a[1:] != a[:-1]) | (l_[1:] != l_[:-1]) | (h[1:] != h[:-1])
    order, a = order[new], a[new]
    start = np.ones(len(order), dtype=bool)
    start[1:] = a[1:] != a[:-1]
    group_start = np.maximum.accumulate(np.where(start, np.arange(len(order)), 0))
    return order[np.arange(len(order)) - group_start < BEAM]


def _chain(levels: list[_Level], k: int) -> list[float]:
    """The fence angles leading to state k of the last level, in passing order."""
    out: list[float] = []
    for level in levels[::-1]:
        out.append(float(level.alpha[k]))
        k = int(level.parent[k])
    return out[::-1]


def collapse_width(push: Push, angles: FloatArray) -> FloatArray:
    """Width of the final arc of each design (rows of ``angles``, (m, N), radians), from
    every start: the first fence leaves the part in ``push.circle``."""
    lo = np.full(angles.shape[0], push.circle[0])
    hi = np.full(angles.shape[0], push.circle[1])
    for i in range(1, angles.shape[1]):
        shift = angles[:, i - 1] - angles[:, i]
        lo, hi = push.image(lo + shift, hi + shift)
    return np.asarray(hi - lo)


def _held(push: Push, rules: FenceRules, angles: FloatArray, i: int, goal: float,
          admissible_only: bool = True) -> tuple[FloatArray, FloatArray]:
    """For each design (rows of ``angles``, (K, N)), how far α_i may move up and down (the
    others as designed) with it still collapsing to ``goal`` and (``admissible_only``) α_i
    admissible: two (K,) arrays in radians, from ``MARGIN_STEPS_RAD``. One vectorised pass."""
    K, N = angles.shape
    M = len(MARGIN_STEPS_RAD)
    trial = np.repeat(angles[:, None, :], 2 * M, axis=1)
    trial[:, :, i] += np.concatenate([MARGIN_STEPS_RAD, -MARGIN_STEPS_RAD])[None, :]
    ok = (collapse_width(push, trial.reshape(-1, N)) <= goal).reshape(K, 2, M)
    if admissible_only:
        ok &= rules.slacks(trial[:, :, i]).reshape(K, 2, M) > 0.0
    n = np.where(ok.all(axis=2), M, np.argmin(ok, axis=2))  # leading steps that hold
    held = np.where(n > 0, MARGIN_STEPS_RAD[np.maximum(n - 1, 0)], 0.0)
    return held[:, 0], held[:, 1]


def margins(push: Push, rules: FenceRules, angles: FloatArray, goal: float) -> FloatArray:
    """(K, N): per design and fence, the largest tried margin m with α_i ± m (the others as
    designed) still collapsing to ``goal`` and admissible (radians; 0: not even the smallest)."""
    out = np.zeros(angles.shape)
    for i in range(angles.shape[1]):
        up, down = _held(push, rules, angles, i, goal)
        out[:, i] = np.minimum(np.minimum(up, down), np.maximum(rules.slacks(angles[:, i]), 0.0))
    return out


def centred(push: Push, rules: FenceRules, angles: FloatArray, goal: float, sweeps: int = 3) -> FloatArray:
    """The designs (K, N) with each angle moved, in turn, to the middle of the range it may
    take with the others fixed (``sweeps`` passes): the search's grid angles sit at the edges."""
    out = np.array(angles, dtype=float)
    for _ in range(sweeps):
        for i in range(out.shape[1]):
            up, down = _held(push, rules, out, i, goal)
            out[:, i] += 0.5 * (up - down)
    return out


LengthOf = Callable[[FenceDesign], float]
"""The total fence length of a design (part units): the layout's, injected by the caller."""


def design_fences(analysis: Analysis, rules: FenceRules = DEFAULT_RULES, min_margin_deg: float = DEFAULT_MIN_MARGIN_DEG,
                  length: LengthOf | None = None) -> FenceDesign:
    """The fewest fences orienting the part (see module docs), ties by ``length`` then margin.

    Raises
    ------
    NotOrientableError
        ``no_step``/``dead_band`` when the push cannot orient the part; ``no_fence_design``
        when no admissible sequence of at most ``MAX_FENCES`` does (with ``limits``:
        the largest fence friction under which one would, if any).
    """
    if not (np.isfinite(min_margin_deg) and 0.0 <= min_margin_deg < 45.0):
        raise ConfigError("min_margin_deg", f"must be in [0, 45), got {min_margin_deg}")
    push = push_of(analysis)
    found = _search(analysis, push, rules, to_rad(min_margin_deg), length)
    if found is not None:
        return found
    raise _refusal(analysis, push, rules, to_rad(min_margin_deg))


def _goal(push: Push) -> float:
    """The widest final arc accepted (radians): a point, or twice the uncertainty a design may claim."""
    return EXACT_GOAL_RAD if push.exact else 2.0 * (MAX_UNCERTAINTY_RAD - GUARD_RAD)


def _search(analysis: Analysis, push: Push, rules: FenceRules, margin: float,
            length: LengthOf | None) -> FenceDesign | None:
    """Breadth-first over levels; the first level holding a design with every margin ≥
    ``margin`` and an uncertainty a design may claim."""
    goal = _goal(push)
    levels = [_first_level(push, rules)]
    while True:
        last = levels[-1]
        hits = np.nonzero(last.hi - last.lo <= goal)[0]
        designs = _candidates(analysis, push, rules, levels, hits, goal, margin)
        if designs:
            return turned(push, rules, _best(designs, length), goal, margin, length)
        if len(last.lo) == 0 or len(levels) == MAX_FENCES:
            return None
        levels.append(_next_level(push, rules, last))


def _candidates(analysis: Analysis, push: Push, rules: FenceRules, levels: list[_Level], hits: np.ndarray,
                goal: float, margin: float) -> list[FenceDesign]:
    """Designs of the states ``hits`` of the last level, centred, that hold ``margin`` and
    a claimable uncertainty: ``CANDIDATES`` spread evenly over them, and when none holds, up
    to ``MAX_HITS`` (a level is only given up when those fail too). Vectorised over designs."""
    tried: set[int] = set()
    for n in (CANDIDATES, MAX_HITS):
        pick = [int(k) for k in hits[np.unique(np.linspace(0, len(hits) - 1, min(len(hits), n)).astype(int))]
                if int(k) not in tried]
        tried.update(pick)
        if not pick:
            continue
        A = centred(push, rules, np.array([_chain(levels, k) for k in pick]), goal)
        m = margins(push, rules, A, goal)
        keep = np.nonzero(m.min(axis=1) >= margin - ROUNDING)[0]
        designs = [d for d in (_design(analysis, push, rules, A[k].tolist(), m[k].tolist()) for k in keep)
                   if d.final_uncertainty <= MAX_UNCERTAINTY_RAD]
        if designs:
            return designs
    return []


def _best(designs: list[FenceDesign], length: LengthOf | None) -> FenceDesign:
    """Precise designs first (final arc ≤ 1°), then the shortest, then the widest margins."""

    def key(d: FenceDesign) -> tuple[bool, float, float, float]:
        size = 0.0 if length is None else round(length(d), 6)
        return d.final_uncertainty > PRECISE_RAD, size, -min(d.margins), -sum(d.margins)

    return min(designs, key=key)


TURNS_RAD = to_rad(np.arange(-60.0, 60.01, 0.25))
"""Whole-design turns γ tried for the shortest layout."""


def turned(push: Push, rules: FenceRules, design: FenceDesign, goal: float, margin: float,
           length: LengthOf | None) -> FenceDesign:
    """The design turned as a whole by the γ of ``TURNS_RAD`` giving the least ``length``
    (then the widest margins): every α_i + γ makes the same relative turns, so the part
    collapses from every start as before and only the final orientations turn by γ; every
    angle must stay admissible on its rail with its margin ≥ ``margin``."""
    if length is None:
        return design
    held = [_held(push, rules, np.array([design.angles]), i, goal, admissible_only=False)
            for i in range(len(design.angles))]
    best, best_key = design, (round(length(design), 6), -min(design.margins))
    for g in TURNS_RAD.tolist():
        angles = [a + g for a in design.angles]
        ms = [min(float(up[0]), float(down[0]), rules.slack(a)) for (up, down), a in zip(held, angles)]
        if min(ms) < margin - ROUNDING or min(ms) <= 0.0 or any((a < 0.5 * np.pi) != (s == 0)
                                                                  for a, s in zip(angles, design.sides)):
            continue
        finals = tuple(sorted(float(np.mod(f + g, 2 * np.pi)) for f in design.final_orientations))
        cand = replace(design, angles=tuple(angles), margins=tuple(ms), final_orientations=finals)
        key = (round(length(cand), 6), -min(ms))
        if key < best_key:
            best, best_key = cand, key
    return best


def _design(analysis: Analysis, push: Push, rules: FenceRules, angles: list[float], held: list[float]) -> FenceDesign:
    """The design of a fence sequence with its margins ``held``: inputs, final orientations, uncertainty."""
    inputs = [(0.0, 2.0 * np.pi)]
    lo, hi = np.array([push.circle[0]]), np.array([push.circle[1]])
    for a0, a1 in zip(angles[:-1], angles[1:]):
        lo, hi = lo + a0 - a1, hi + a0 - a1
        inputs.append((float(lo[0]), float(hi[0])))
        lo, hi = push.image(lo, hi)
    T = push.symmetry
    mid = 0.5 * float(lo[0] + hi[0]) + angles[-1]
    finals = tuple(sorted(float(np.mod(mid + i * T, 2 * np.pi)) for i in range(int(round(2 * np.pi / T)))))
    unc = 0.0 if push.exact else max(0.5 * float(hi[0] - lo[0]) + GUARD_RAD + _edge_tilt(analysis, float(lo[0]),
                                                                                        float(hi[0])),
                                     UNCERTAINTY_FLOOR_RAD)
    sides = tuple(0 if a < 0.5 * np.pi else 1 for a in angles)
    return FenceDesign(tuple(angles), sides, tuple(held), tuple(inputs), finals,
                       unc, T, rules, push.exact)


def _refusal(analysis: Analysis, push: Push, rules: FenceRules, margin: float) -> NotOrientableError:
    """Why no design exists, and the largest fence friction under which one would."""
    mu = friction_limit(analysis, push, rules, margin)
    base = (f"no sequence of at most {MAX_FENCES} alternating fences with steepness in "
            f"[{to_deg(rules.min_steepness):g}°, {to_deg(rules.max_steepness):.3g}°) (fence friction ≤ "
            f"{rules.friction[1]:g}) and margins ≥ {to_deg(margin):g}° orients the part")
    if mu is None:
        why = "" if push.exact else (" (the shape, profile and centre-of-mass tolerances leave orientations that "
                                     "may turn either way; --exact gives the drawing's design)")
        return NotOrientableError("no_fence_design", base + ", even with frictionless fences" + why,
                                  {"fence_friction_max": None})
    return NotOrientableError("no_fence_design", f"{base}; a design exists with fence friction ≤ {mu:.3g}",
                              {"fence_friction_max": mu})


def friction_limit(analysis: Analysis, push: Push, rules: FenceRules, margin: float) -> float | None:
    """The largest μ_f,hi (bisection, ``LIMIT_PROBES`` steps) with a design; None: none even at 0."""
    def exists(mu: float) -> bool:
        return _search(analysis, push, FenceRules((0.0, mu), rules.min_steepness), margin, None) is not None

    if not exists(0.0):
        return None
    lo, hi = 0.0, rules.friction[1]
    for _ in range(LIMIT_PROBES):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if exists(mid) else (lo, mid)
    return lo
