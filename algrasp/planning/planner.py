"""Algorithm A′ (paper §4): the shortest sensorless plan on a step/ramp function.

Works on any lifted transfer function F (squeeze Γ or push-grasp Γ∘p). Θ₁ is the
widest step; Θ_{i+1} is the widest interval whose image fits in Θ_i, until an interval
of width T (the symmetry period) is reached. For a fixed left end a the widest fit
[a, b) is found by one search on the monotone sequence of piece values; the widest
interval starts at a piece start (bottom-left placement) or is where the box's top
meets a step value or ramp start inside a ramp (top-right placement), so only those
candidates are tried: O(n log n + K) per iteration for n pieces, O(N(n log n + K)) in all.

Fixed and variable intervals both arise: a variable interval ends inside a ramp.
The image of [a, b) is [F(a), F(b⁻)], attained at the top when b⁻ lies on a step and
open (the ramp's values approach b) when it lies on a ramp, so a step value must fit
strictly and a ramp end may touch the box's top (paper Fig. 11).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from algrasp.compiled import KERNELS, LOOKUPS
from algrasp.errors import NotOrientableError
from algrasp.geometry.angles import shortest_turn, to_deg, to_rad
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.tolerances import PLANNING_RAD, ROUNDING, SYMMETRY_TOL_RAD
from algrasp.planning.transfer import TransferFunction

STRICT_RAD = 1e-9
"""How far below the box's top a step value must stay (a step value on the top edge
would belong to the next interval: intervals are half-open)."""

GUARD_RAD = 1e-12
"""Room kept on each side of every image even for zero-margin plans. In exact arithmetic
the paper's variable intervals fit with no room at all (Fig. 11); in floating point the
gripper angles carry ~1e-14 rad of rounding, which would push an image end over an
interval boundary. Costs at most one extra action when the ideal plan fits exactly."""


class _Pieces(NamedTuple):
    """Pieces of one step/ramp function over several periods as arrays (sorted by start;
    a named tuple: two are made per planning attempt)."""

    starts: FloatArray
    ends: FloatArray
    values: FloatArray  # step image, or the start for a ramp
    ramp: np.ndarray  # bool
    keys: FloatArray  # value a piece must stay below to fit (monotone)

    @staticmethod
    def of(F: TransferFunction) -> _Pieces:
        s, e, v, r = F.lifted
        if KERNELS is not None:  # typed loops, the same keys (algrasp.compiled)
            return _Pieces(s, e, v, r, KERNELS.keys(s, v, r, STRICT_RAD))
        keys = np.maximum.accumulate(np.where(r, s, v + STRICT_RAD))
        return _Pieces(s, e, v, r, keys)


@dataclass(frozen=True, eq=False)
class Lifted:
    """A (set-valued) transfer function lifted: the image of [a, b) is
    [lower(a), upper(b⁻)]. For an exact function lower and upper are the same."""

    lower: _Pieces
    upper: _Pieces
    fixed: dict[int, _Fixed] = field(default_factory=dict)
    """What :func:`_widest` reads that no box height changes, by the function's id."""
    tables: dict[int, Any] = field(default_factory=dict)
    """The compiled :func:`_widest` of each function (``_lookups.Widest``: its arrays held
    typed), by the function's id."""

    @staticmethod
    def of(F: TransferFunction, upper: TransferFunction | None = None) -> Lifted:
        lo = _Pieces.of(F)
        return Lifted(lo, lo if upper is None else _Pieces.of(upper))

    @property
    def starts(self) -> FloatArray:
        return self.lower.starts

    def value_at(self, a: FloatArray) -> FloatArray:
        """lower(a) (a may lie anywhere inside a piece)."""
        lo = self.lower
        i = lo.starts.searchsorted(a, side="right") - 1
        return np.where(lo.ramp[i], a, lo.values[i])

    def top(self, b: FloatArray) -> tuple[FloatArray, np.ndarray]:
        """sup upper([·, b)) = upper(b⁻), and whether it is attained (b⁻ on a step)."""
        up = self.upper
        j = up.starts.searchsorted(b, side="left") - 1
        on_ramp = up.ramp[j]
        return np.where(on_ramp, b, up.values[j]), ~on_ramp

    def right_end(self, y: FloatArray) -> FloatArray:
        """The largest b with upper([·, b)) inside a box whose top is at ``y``."""
        up = self.upper
        j = up.keys.searchsorted(y, side="left")  # first piece that cannot fit
        prev = j - 1
        partial = up.ramp[prev] & (up.ends[prev] > y)
        return np.where(partial, y, up.starts[j])


def _ramp_candidates(ramp_starts: FloatArray, ramp_ends: FloatArray, tops: FloatArray, room: float) -> FloatArray:
    """Left ends inside ramps whose box top meets a step value or a ramp start (top-right
    placements), from :func:`_fixed`'s ramps and tops; the piece starts of one period are
    the other candidates (:func:`_widest`)."""
    if not len(ramp_starts):
        return ramp_starts
    lo, hi = tops.searchsorted(ramp_starts + room), tops.searchsorted(ramp_ends + room)
    # tops[lo_k:hi_k] for every ramp k, in order: the ramps are sorted and disjoint, so
    # are these ranges, and top t lies in one where more ranges start than end by it.
    t = np.arange(len(tops))
    out: FloatArray = tops[lo.searchsorted(t, side="right") > hi.searchsorted(t, side="right")] - room
    return out


_Fixed = tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]


def _fixed(F: TransferFunction, lifted: Lifted) -> _Fixed:
    """The piece starts of one period, the starts and ends of its ramps, the distinct
    values of the upper bound and the lower bound at the piece starts; once per function
    and lifting."""
    got = lifted.fixed.get(id(F))
    if got is None and KERNELS is not None:  # typed loops, the same arrays (algrasp.compiled)
        got = lifted.fixed[id(F)] = KERNELS.fixed(F.pieces[0].start, F.period, lifted.lower, lifted.upper, ROUNDING)
    if got is None:
        base = F.pieces[0].start
        low = lifted.lower
        one = (low.starts >= base - ROUNDING) & (low.starts < base + F.period - ROUNDING)
        starts = low.starts[one]
        got = lifted.fixed[id(F)] = (starts, low.starts[one & low.ramp], low.ends[one & low.ramp],
                                     _unique(lifted.upper.values), lifted.value_at(starts))
    return got


def widest_step(F: TransferFunction) -> tuple[float, float]:
    """Θ₁: the widest step [start, end) (radians, lifted)."""
    step = max(F.steps, key=lambda p: p.end - p.start)
    return step.start, step.end


def algorithm_a_prime(F: TransferFunction, T: float, min_margin: float = 0.0,
                      tol: float = PLANNING_RAD) -> list[tuple[float, float]]:
    """Θ₁ … Θ_N (radians, lifted, [a, b)); the last has width T.

    With ``min_margin`` > 0 every image must fit with that much to spare on both
    sides. Raises NotOrientableError when F has no step or the margin is too large.
    """
    if not F.steps:
        raise NotOrientableError("no_step", "the transfer function has no step (constant width or "
                                 "constant radius): no plan of this action can orient the part")
    return _grow(F, None, T, widest_step(F), min_margin, tol)


def _grow(F: TransferFunction, lifted: Lifted | None, T: float, first: tuple[float, float], min_margin: float,
          tol: float, circle: float | None = None) -> list[tuple[float, float]]:
    """Θ₂, Θ₃, … after ``first``: each the widest interval whose image fits the last.
    ``circle``: the width of the image of the whole circle (set-valued functions), which
    ends the plan as soon as it fits. ``lifted`` (F's, made here when None) is only
    searched when Θ₁ is narrower than T."""
    intervals = [first]
    while intervals[-1][1] - intervals[-1][0] < T - tol:
        room = intervals[-1][1] - intervals[-1][0] - 2.0 * max(min_margin, GUARD_RAD)
        if room <= 0.0:
            raise _margin_error(min_margin, intervals)
        if circle is not None and circle <= room:
            intervals.append((intervals[-1][0], intervals[-1][0] + T))
            break
        lifted = lifted or Lifted.of(F)
        a, b = _widest(F, lifted, room)
        if b - a <= intervals[-1][1] - intervals[-1][0] + tol:
            raise _margin_error(min_margin, intervals)
        intervals.append((a, min(b, a + T)))
    last = intervals[-1]
    intervals[-1] = (last[0], last[0] + T)
    return intervals


def _widest(F: TransferFunction, lifted: Lifted, room: float) -> tuple[float, float]:
    """The widest [a, b) whose image fits in a box of height ``room``, of the left ends
    worth trying: the piece starts of one period (bottom-left placements; their lower
    values are fixed), then the points of ramps :func:`_ramp_candidates` gives (the first
    widest wins)."""
    if LOOKUPS is not None:  # typed loops, the same interval (algrasp.compiled)
        table = lifted.tables.get(id(F))
        if table is None:
            table = lifted.tables[id(F)] = LOOKUPS.Widest.of(F.pieces[0].start, F.period, lifted.lower, lifted.upper,
                                                             ROUNDING)
        return table.at(room)  # type: ignore[no-any-return]
    starts, ramp_starts, ramp_ends, tops, at_starts = _fixed(F, lifted)
    inner = _ramp_candidates(ramp_starts, ramp_ends, tops, room)
    if len(inner):  # one search for both kinds; argmax's first maximum keeps the starts' priority
        starts, at_starts = np.concatenate((starts, inner)), np.concatenate((at_starts, lifted.value_at(inner)))
    b = lifted.right_end(at_starts + room)
    k = int((b - starts).argmax())
    return float(starts[k]), float(b[k])


def set_a_prime(lower: TransferFunction, upper: TransferFunction, T: float, circle: float | Callable[[], float],
                min_margin: float = 0.0, max_final_rad: float = np.pi, tol: float = PLANNING_RAD,
                lifted: Lifted | None = None) -> list[tuple[float, float]]:
    """Algorithm A′ on a set-valued function (conventions §7): the image of [a, b) is
    [lower(a), upper(b⁻)]; the whole circle's image is ``circle`` wide (or what computes
    that width: it is only read once some Θ₁ exists, so a refusal does not pay for it).
    ``lifted``: the bounds' :class:`Lifted`, when the caller has it.

    Θ₁ is the widest interval whose image is at most w₀ wide, w₀ one of the image widths
    a single orientation can have (the sinks, ``MAX_SINKS`` smallest). Every later
    interval depends on Θ₁ only through its width and the widest-fit width is monotone, so
    the plan is shortest for the widest Θ₁: among precise finals (w₀ ≤ ``PRECISE_RAD``) the
    widest Θ₁ (then the narrower image) is grown, else the widest of all. O(s·n log n + A′).
    """
    lifted = Lifted.of(lower, upper) if lifted is None else lifted
    firsts = [(w0, *_widest(lower, lifted, w0 + 2.0 * STRICT_RAD)) for w0 in _sink_widths(lower, upper, lifted, max_final_rad)]
    firsts = [(w0, a, b) for w0, a, b in firsts if b - a > tol]
    if not firsts:
        raise NotOrientableError("no_step", "no interval of orientations collapses to a small set: with this dead "
                                 "band the part cannot be oriented by this action")
    precise = [f for f in firsts if f[0] <= PRECISE_RAD]
    order = [max(precise, key=lambda f: (f[2] - f[1], -f[0]))] if precise else []
    widest = max(firsts, key=lambda f: (f[2] - f[1], -f[0]))
    if not order or widest[2] - widest[1] != order[0][2] - order[0][1]:
        order.append(widest)  # an equally wide Θ₁ grows the same later intervals: it would fail alike
    width = circle() if callable(circle) else circle
    for i, (_, a, b) in enumerate(order):
        try:
            return _grow(lower, lifted, T, (a, b), min_margin, tol, width)
        except NotOrientableError:
            if i == len(order) - 1:
                raise
    raise AssertionError("unreachable")


PRECISE_RAD = to_rad(1.0)
"""Final images at most this wide count as precise: among them the shortest plan wins
(then the narrower image); wider ones only when no precise plan exists."""
MAX_SINKS = 8
"""How many candidate final-image widths Θ₁ is tried with."""


def _sink_widths(lower: TransferFunction, upper: TransferFunction, lifted: Lifted, max_rad: float) -> list[float]:
    """Distinct image widths upper(x) − lower(x) at piece starts, smallest first."""
    if KERNELS is not None:  # typed loops, the same widths (algrasp.compiled)
        return KERNELS.sink_widths(lower, upper, lifted.lower, max_rad, MAX_SINKS)  # type: ignore[no-any-return]
    xs = np.array(lower.starts + upper.starts)
    width = upper.apply(xs) - lifted.value_at(xs)
    sinks: list[float] = _unique(width[(width >= 0.0) & (width <= max_rad)].round(10))[:MAX_SINKS].tolist()
    return sinks


def _margin_error(margin: float, intervals: list[tuple[float, float]]) -> NotOrientableError:
    width = to_deg(intervals[-1][1] - intervals[-1][0])
    return NotOrientableError("margin_too_large",
                              f"no plan tolerates a gripper error of {to_deg(margin):g}°: with that margin "
                              f"the widest interval that can be collapsed is {width:.6g}°")


def images(F: TransferFunction, intervals: list[tuple[float, float]], upper: TransferFunction | None = None,
           lifted: Lifted | None = None) -> list[tuple[float, float]]:
    """[F(a), F(b⁻)] of each [a, b) (radians, lifted; with ``upper``, [F(a), upper(b⁻)]);
    one lifting for all (``lifted``, when the caller has it). O((n + m) log n)."""
    if not intervals:
        return []
    lifted = Lifted.of(F, upper) if lifted is None else lifted
    if KERNELS is not None:  # typed loops, the same floats (algrasp.compiled)
        return KERNELS.images(lifted.lower, lifted.upper, intervals)  # type: ignore[no-any-return]
    lo = lifted.value_at(np.array([a for a, _ in intervals]))
    hi, _ = lifted.top(np.array([b for _, b in intervals]))
    return [(float(x), float(y)) for x, y in zip(lo, hi)]


# ------------------------------------------------------ gripper angles (plans.gripper_steps)


def self_turn(period: float, T: float, margin: float) -> float:
    """The smallest turn that maps an action to itself: T (the part's symmetry, true to
    SYMMETRY_TOL_RAD) when the margin absorbs that on both image ends, else the period."""
    return T if margin > 2.0 * SYMMETRY_TOL_RAD else period


def nearest(angle: float, ref: float, turn: float) -> float:
    """``angle`` plus the multiple of ``turn`` that brings it nearest ``ref`` (radians)."""
    return angle - turn * round((angle - ref) / turn)


def first_choice(arcs: list[tuple[float, float]], fit: list[float], need: float, nxt: tuple[float, float],
                  alpha_next: float, period: float, T: float) -> tuple[int, float]:
    """The arc (its index) and first action's angle needing the least turning, of the arcs
    with room ``fit`` ≥ ``need`` and, for each, the angles that centre it in the second
    action's interval ``nxt`` (one per turn that maps the action to itself): the turns
    from the last action's angle (0, where the previous part left the gripper) and on to
    the second action's, each the shortest under the action's period (as the execution
    turns). The first least (turning, index) wins. O(arcs · turns)."""
    if LOOKUPS is not None:  # typed loops, the same keys and angle (algrasp.compiled)
        return LOOKUPS.first_choice(arcs, fit, need, nxt, alpha_next, period, T, 2.0 * SYMMETRY_TOL_RAD)  # type: ignore[no-any-return]
    best: tuple[float, int] | None = None
    out = (0, 0.0)
    for k, arc in enumerate(arcs):
        if not fit[k] >= need:
            continue
        turn = self_turn(period, T, fit[k])
        base = alpha_next + 0.5 * (nxt[0] + nxt[1]) - 0.5 * (arc[0] + arc[1])
        for i in range(max(1, round(2 * np.pi / turn))):
            alpha = base + i * turn
            key = (abs(shortest_turn(alpha, period)) + abs(shortest_turn(alpha_next - alpha, period)), k)
            if best is None or key < best:
                best, out = key, (k, alpha)
    if best is None:
        raise ValueError("min() arg is an empty sequence")
    return out


def _unique(a: FloatArray) -> FloatArray:
    """``np.unique(a)`` of finite values (the first of equal values kept, as np.unique's
    stable sort does: −0.0 or 0.0), in plain floats: the arrays are small. (The plain
    np.unique imports ``numpy.ma`` on first use, ~30 ms of a fresh process's first plan.)"""
    return np.array(sorted(set(a.tolist())), dtype=float)
