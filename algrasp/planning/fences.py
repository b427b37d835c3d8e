"""Conveyor fences (conventions §9): the fewest fences that orient a part on a belt.

The model — the push a fence applies, admissible angles, designs and margins — is
:mod:`algrasp.planning.fence_model`. Fences alternate rails, so consecutive angles differ
by δ = α_{i+1} − α_i in ``(2 atan μ_f, 180° − 2β_min]`` (right → left) or its negative
(left → right), and the angles themselves stay in the admissible set; with
``rules.same_rail`` the next fence may stand on either rail (twice the branching).

The search is breadth-first over designs: fence angles on a grid of each side's
admissible set; a state is the arc of orientations (relative to its last fence) the part
may be in and the last fence's angle; for each fence angle the ``BEAM`` narrowest arcs
are kept. The first level with an arc that collapses to one orientation (up to p's
symmetry T) with every fence angle holding ``min_margin`` wins; among its designs the
shortest (an injected length, the fence layout's) then the widest margin is taken, and
the winner is turned as a whole for the shortest layout. Pure: no I/O; angles in radians.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from algrasp.errors import ConfigError, NotOrientableError
from algrasp.geometry.angles import to_deg, to_rad
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.tolerances import MAX_UNCERTAINTY_RAD, ROUNDING, SYMMETRY_TOL_RAD, UNCERTAINTY_FLOOR_RAD
from algrasp.planning.analysis import Analysis
from algrasp.planning.fence_model import (
    DEFAULT_FENCE_FRICTION,
    DEFAULT_RULES,
    FenceDesign,
    FenceRules,
    Push,
    centred,
    collapse_width,
    fence_rules,
    leave,
    margins,
    on_belt,
    push_of,
)
from algrasp.planning.planner import GUARD_RAD, PRECISE_RAD
from algrasp.planning.plans import _edge_tilt

__all__ = ["DEFAULT_FENCE_FRICTION", "DEFAULT_MIN_MARGIN_DEG", "DEFAULT_RULES", "FenceDesign", "FenceRules", "Push",
           "check_min_margin", "design_fences", "fence_rules", "friction_limit", "on_belt", "push_of", "turned"]

BEAM = 4
"""Arcs kept per fence angle and level (the narrowest)."""
MAX_FENCES = 12
DEFAULT_MIN_MARGIN_DEG = 1.0
"""How far (°) every fence angle may be off by default: a fence is set by hand to about a degree."""
CANDIDATES = 64
"""Designs of the winning level compared (spread evenly over the fence angles that reach it)."""
MAX_HITS = 1024
"""States of a level tried before it is given up when none of the first ``CANDIDATES`` holds."""
EXACT_GOAL_RAD = 1e-9
LIMIT_PROBES = 6
"""Bisection steps of the friction limit named in a refusal."""


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
    lo, hi = push.circle_at(alpha)
    return _Level(np.asarray(lo, dtype=float), np.asarray(hi, dtype=float), alpha, side, np.full(n, -1))


def _next_level(push: Push, rules: FenceRules, level: _Level) -> _Level:
    """Every state followed by every admissible angle of the other side (of either side
    with ``rules.same_rail``), pruned to the ``BEAM`` narrowest distinct arcs per angle."""
    parts = []
    for s, nxt in ((0, 1), (1, 0), (0, 0), (1, 1))[:4 if rules.same_rail else 2]:
        idx = np.nonzero(level.side == s)[0]
        grid = rules.grid(nxt)
        shift = level.alpha[idx, None] - grid[None, :]
        lo0, hi0 = leave(level.lo[idx], level.hi[idx], level.alpha[idx], rules.exit_turns)
        lo, hi = push.image(lo0[:, None] + shift, hi0[:, None] + shift, grid[None, :])
        cols = np.broadcast_to(grid[None, :], lo.shape)
        parts.append((lo.ravel(), hi.ravel(), cols.ravel(), np.full(lo.size, nxt), np.repeat(idx, len(grid))))
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


LengthOf = Callable[[FenceDesign], float]
"""The total fence length of a design (part units): the layout's, injected by the caller."""


MAX_MIN_MARGIN_DEG = 45.0
"""A fence margin must be below 45° (a fence's whole admissible range is under 80°)."""


def check_min_margin(min_margin_deg: float, name: str = "min_margin_deg") -> None:
    """ConfigError (``name``) unless 0 ≤ ``min_margin_deg`` < 45 (degrees)."""
    if not (np.isfinite(min_margin_deg) and 0.0 <= min_margin_deg < MAX_MIN_MARGIN_DEG):
        raise ConfigError(name, f"must be in [0, {MAX_MIN_MARGIN_DEG:g}), got {min_margin_deg!r}")


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
    check_min_margin(min_margin_deg)
    push = push_of(analysis, rules.friction)
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
    push = push.with_friction(rules.friction)
    levels = [_first_level(push, rules)]
    while True:
        last = levels[-1]
        hits = np.nonzero(last.hi - last.lo <= goal)[0]
        designs = _candidates(analysis, push, rules, levels, hits, goal, margin)
        if designs:
            return turned(analysis, push, rules, _best(designs, length), goal, margin, length)
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
        held = collapse_width(push, A, rules.exit_steepness, rules.exit_turns) <= goal
        keep = np.nonzero((m.min(axis=1) >= margin - ROUNDING) & held)[0]
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


def turned(analysis: Analysis, push: Push, rules: FenceRules, design: FenceDesign, goal: float, margin: float,
           length: LengthOf | None) -> FenceDesign:
    """The design turned as a whole by the γ of ``TURNS_RAD`` giving the least ``length``
    (then the widest margins): every α_i + γ makes the same relative turns, but the exit
    turns between fences follow the steepness, so each turned design is checked again: it
    must collapse, and every angle must stay admissible on its rail with its margin ≥
    ``margin``. Vectorised over the K turns: O(K · N · M) pushes of arcs."""
    if length is None:
        return design
    base = np.array(design.angles)
    A = base[None, :] + TURNS_RAD[:, None]
    right = np.array(design.sides) == 0
    sides_ok = np.all(np.less(A, 0.5 * np.pi) == right[None, :], axis=1)
    sides_ok &= np.all(rules.slacks(A) > 0.0, axis=1)
    A = A[sides_ok]
    ok = collapse_width(push, A, rules.exit_steepness, rules.exit_turns) <= goal
    A = A[ok]
    if len(A) == 0:
        return design
    m = margins(push, rules, A, goal)
    best, best_key = design, (round(length(design), 6), -min(design.margins))
    for angles, ms in zip(A.tolist(), m.tolist()):
        if min(ms) < margin - ROUNDING or min(ms) <= 0.0:
            continue
        cand = _design(analysis, push, rules, angles, ms)
        if cand.final_uncertainty > MAX_UNCERTAINTY_RAD:
            continue
        key = (round(length(cand), 6), -min(ms))
        if key < best_key:
            best, best_key = cand, key
    return best


def _design(analysis: Analysis, push: Push, rules: FenceRules, angles: list[float], held: list[float]) -> FenceDesign:
    """The design of a fence sequence with its margins ``held``: inputs, final orientations, uncertainty."""
    inputs = [(0.0, 2.0 * np.pi)]
    lo, hi = (np.atleast_1d(x) for x in push.circle_at(angles[0]))
    for a0, a1 in zip(angles[:-1], angles[1:]):
        lo, hi = leave(lo, hi, a0, rules.exit_turns)
        lo, hi = lo + a0 - a1, hi + a0 - a1
        inputs.append((float(lo[0]), float(hi[0])))
        lo, hi = push.image(lo, hi, a1)
    T = push.symmetry
    mid = 0.5 * float(lo[0] + hi[0]) + angles[-1]
    finals = tuple(sorted(float(np.mod(mid + i * T, 2 * np.pi)) for i in range(int(round(2 * np.pi / T)))))
    unc = 0.0 if push.exact else max(0.5 * float(hi[0] - lo[0]) + GUARD_RAD + _edge_tilt(analysis, float(lo[0]),
                                                                                        float(hi[0])),
                                     UNCERTAINTY_FLOOR_RAD)
    sides = tuple(0 if a < 0.5 * np.pi else 1 for a in angles)
    return FenceDesign(tuple(angles), sides, tuple(held), tuple(inputs), finals,
                       unc, T, rules, push.exact)


SAME_RAIL_HINT = "; a design exists with consecutive fences on one rail (same_rail true, --same-rail)"
"""Added to a refusal with alternating fences when one rail would do (never with ``same_rail``)."""


def _refusal(analysis: Analysis, push: Push, rules: FenceRules, margin: float) -> NotOrientableError:
    """Why no design exists, and the largest fence friction under which one would. When
    fences alternate and the exit turns are modelled, one more search tells whether
    consecutive fences on one rail would orient the part (``limits["same_rail_design"]``)."""
    if rules.exit_turns and _search(analysis, push, replace(rules, exit_turns=False), margin, None) is not None:
        same = not rules.same_rail and _search(analysis, push, replace(rules, same_rail=True), margin, None) is not None
        return NotOrientableError("no_fence_design", _turns_message(rules) + (SAME_RAIL_HINT if same else ""),
                                  {"fence_friction_max": None, "berretty_design": True, "same_rail_design": same})
    mu = friction_limit(analysis, push, rules, margin)
    base = (f"no sequence of at most {MAX_FENCES} {_kind(rules)}fences with steepness in "
            f"[{to_deg(rules.min_steepness):g}°, {to_deg(rules.max_steepness):.3g}°) (fence friction ≤ "
            f"{rules.friction[1]:g}) and margins ≥ {to_deg(margin):g}° orients the part")
    if mu is None:
        why = "" if push.exact else (" (the shape, profile and centre-of-mass tolerances leave orientations that "
                                     "may turn either way; --exact gives the drawing's design)")
        return NotOrientableError("no_fence_design", base + ", even with frictionless fences" + why,
                                  {"fence_friction_max": None})
    return NotOrientableError("no_fence_design", f"{base}; a design exists with fence friction ≤ {mu:.3g}",
                              {"fence_friction_max": mu})


def _turns_message(rules: FenceRules) -> str:
    """The refusal when only the tips' turns stand in the way (Berretty's model has a
    design): what the next fence sees, on the other rail or, with ``same_rail``, on either."""
    if rules.same_rail:
        shift = ("so the next fence sees its outcomes shifted by 180° − β only on the other rail, and by its own "
                 "steepness β only on the same rail")
    else:
        shift = "so the next fence, on the other rail, sees its outcomes shifted by 180° − β only"
    return (f"no sequence of at most {MAX_FENCES} {_kind(rules)}fences orients the part once the turn it takes over "
            "each fence's tip is modelled (up to the fence's angle to the belt): past each tip it lies where a fence "
            f"parallel to the belt would leave it, {shift} (conventions §9); in Berretty et al.'s model, where it "
            "keeps its orientation between fences, a design exists (exit_turns false, --no-exit-turns), which Drake "
            "does not bear out")


def _kind(rules: FenceRules) -> str:
    """How the refusal names the fences: "alternating", or "" (either rail) with ``same_rail``."""
    return "" if rules.same_rail else "alternating "


def friction_limit(analysis: Analysis, push: Push, rules: FenceRules, margin: float) -> float | None:
    """The largest μ_f,hi (bisection, ``LIMIT_PROBES`` steps) with a design; None: none even at 0."""
    def exists(mu: float) -> bool:
        return _search(analysis, push, replace(rules, friction=(0.0, mu)), margin, None) is not None

    if not exists(0.0):
        return None
    lo, hi = 0.0, rules.friction[1]
    for _ in range(LIMIT_PROBES):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if exists(mid) else (lo, mid)
    return lo
