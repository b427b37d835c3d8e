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

from dataclasses import dataclass

import numpy as np

from algrasp.curves import FloatArray
from algrasp.errors import NotOrientableError
from algrasp.transfer import TransferFunction

STRICT_RAD = 1e-9
"""How far below the box's top a step value must stay (a step value on the top edge
would belong to the next interval: intervals are half-open)."""

GUARD_RAD = 1e-12
"""Room kept on each side of every image even for zero-margin plans. In exact arithmetic
the paper's variable intervals fit with no room at all (Fig. 11); in floating point the
gripper angles carry ~1e-14 rad of rounding, which would push an image end over an
interval boundary. Costs at most one extra action when the ideal plan fits exactly."""


@dataclass(frozen=True, eq=False)
class _Lifted:
    """Pieces of F over several periods as arrays (sorted by start)."""

    starts: FloatArray
    ends: FloatArray
    values: FloatArray  # step image, or the start for a ramp
    ramp: np.ndarray  # bool
    keys: FloatArray  # value a piece must stay below to fit (monotone)

    @staticmethod
    def of(F: TransferFunction, periods: range) -> _Lifted:
        starts, ends, values, ramp = [], [], [], []
        for k in periods:
            for p in F.pieces:
                starts.append(p.start + k * F.period)
                ends.append(p.end + k * F.period)
                values.append(p.start + k * F.period if p.value is None else p.value + k * F.period)
                ramp.append(p.value is None)
        s, v, r = np.array(starts), np.array(values), np.array(ramp)
        keys = np.maximum.accumulate(np.where(r, s, v + STRICT_RAD))
        return _Lifted(s, np.array(ends), v, r, keys)

    def value_at(self, a: FloatArray) -> FloatArray:
        """F(a) (a may lie anywhere inside a piece)."""
        i = np.searchsorted(self.starts, a, side="right") - 1
        return np.where(self.ramp[i], a, self.values[i])

    def top(self, b: FloatArray) -> tuple[FloatArray, np.ndarray]:
        """sup F([·, b)) = F(b⁻), and whether it is attained (b⁻ on a step)."""
        j = np.searchsorted(self.starts, b, side="left") - 1
        on_ramp = self.ramp[j]
        return np.where(on_ramp, b, self.values[j]), ~on_ramp

    def widest_right_end(self, a: FloatArray, room: float) -> FloatArray:
        """For each left end a, the largest b with F([a, b)) inside [F(a), F(a) + room]."""
        y = self.value_at(a) + room
        j = np.searchsorted(self.keys, y, side="left")  # first piece that cannot fit
        prev = j - 1
        partial = self.ramp[prev] & (self.ends[prev] > y)
        return np.where(partial, y, self.starts[j])


def _candidates(F: TransferFunction, lifted: _Lifted, room: float) -> FloatArray:
    """Left ends to try: piece starts of one period, and points of ramps whose box top
    meets a step value or a ramp start (top-right placements)."""
    base = F.pieces[0].start
    one = (lifted.starts >= base - 1e-12) & (lifted.starts < base + F.period - 1e-12)
    out = [lifted.starts[one]]
    tops = np.unique(lifted.values)
    for s, e in zip(lifted.starts[one & lifted.ramp], lifted.ends[one & lifted.ramp]):
        lo, hi = np.searchsorted(tops, [s + room, e + room])
        out.append(tops[lo:hi] - room)
    return np.concatenate(out)


def widest_step(F: TransferFunction) -> tuple[float, float]:
    """Θ₁: the widest step [start, end) (radians, lifted)."""
    step = max(F.steps, key=lambda p: p.end - p.start)
    return step.start, step.end


def algorithm_a_prime(F: TransferFunction, T: float, min_margin: float = 0.0,
                      tol: float = 1e-13) -> list[tuple[float, float]]:
    """Θ₁ … Θ_N (radians, lifted, [a, b)); the last has width T.

    With ``min_margin`` > 0 every image must fit with that much to spare on both
    sides. Raises NotOrientableError when F has no step or the margin is too large.
    """
    if not F.steps:
        raise NotOrientableError("no_step", "the transfer function has no step (constant width or "
                                 "constant radius): no plan of this action can orient the part")
    lifted = _Lifted.of(F, range(-1, 4))
    intervals = [widest_step(F)]
    while intervals[-1][1] - intervals[-1][0] < T - tol:
        room = intervals[-1][1] - intervals[-1][0] - 2.0 * max(min_margin, GUARD_RAD)
        if room <= 0.0:
            raise _margin_error(min_margin, intervals)
        a = _candidates(F, lifted, room)
        b = lifted.widest_right_end(a, room)
        k = int(np.argmax(b - a))
        if b[k] - a[k] <= intervals[-1][1] - intervals[-1][0] + tol:
            raise _margin_error(min_margin, intervals)
        intervals.append((float(a[k]), float(min(b[k], a[k] + T))))
    last = intervals[-1]
    intervals[-1] = (last[0], last[0] + T)
    return intervals


def _margin_error(margin: float, intervals: list[tuple[float, float]]) -> NotOrientableError:
    width = np.degrees(intervals[-1][1] - intervals[-1][0])
    return NotOrientableError("margin_too_large",
                              f"no plan tolerates a gripper error of {np.degrees(margin):g}°: with that margin "
                              f"the widest interval that can be collapsed is {width:.6g}°")


def images(F: TransferFunction, intervals: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """[F(a), F(b⁻)] of each [a, b) (radians, lifted); one lifting for all. O((n + m) log n)."""
    lifted = _Lifted.of(F, range(-1, 4))
    lo = lifted.value_at(np.array([a for a, _ in intervals]))
    hi, _ = lifted.top(np.array([b for _, b in intervals]))
    return [(float(x), float(y)) for x, y in zip(lo, hi)]
