"""Transfer functions: steps and ramps (conventions §3, paper §2.1.2, Appendices B, C).

A transfer function F maps a relative orientation θ to the orientation after an
action. It is stored *lifted* to ℝ: monotone non-decreasing with
F(θ + P) = F(θ) + P for its natural period P (π for squeezing, 2π for pushing).
Pieces are left-closed, right-open: a step maps [start, end) to ``value``; a ramp
maps every θ in [start, end) to itself.
"""

from __future__ import annotations

import bisect
import math
import operator
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from algrasp.compiled import KERNELS, LOOKUPS
from algrasp.geometry.angles import TWO_PI
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.functions import Run
from algrasp.geometry.lazy import cached_property
from algrasp.geometry.tolerances import ROUNDING

BoolArray = NDArray[np.bool_]
LIFTS = range(-1, 4)
"""The periods :attr:`TransferFunction.lifted` covers: a plan's intervals and images
start in the first period and reach at most two periods beyond it."""


FEW_PROBES = 16
"""Up to this many θ :meth:`TransferFunction.values_at` reads in plain floats (a vectorised pass ~5 µs, a float ~0.4 µs)."""


class TransferPiece(NamedTuple):
    """[start, end) (radians, lifted); ``value`` is the step's image, None for a ramp.
    A named tuple: immutable, and cheap to make (a composition makes many)."""

    start: float
    end: float
    value: float | None

    @property
    def is_ramp(self) -> bool:
        return self.value is None

    def shifted(self, d: float) -> TransferPiece:
        return TransferPiece(self.start + d, self.end + d, None if self.value is None else self.value + d)


@dataclass(frozen=True, eq=False)
class TransferFunction:
    """A step/ramp transfer function over one natural ``period`` (radians).

    ``pieces`` are sorted; the first starts in [0, period); together they cover
    [pieces[0].start, pieces[0].start + period). O(log n) evaluation.
    """

    period: float
    pieces: tuple[TransferPiece, ...]

    @property
    def steps(self) -> tuple[TransferPiece, ...]:
        return tuple(p for p in self.pieces if p.value is not None)

    @property
    def ramps(self) -> tuple[TransferPiece, ...]:
        return tuple(p for p in self.pieces if p.value is None)

    @cached_property
    def starts(self) -> list[float]:
        return [p.start for p in self.pieces]

    @cached_property
    def _arrays(self) -> tuple[FloatArray, FloatArray]:
        """Starts and step values (NaN for ramps) as arrays for :meth:`apply`."""
        starts = np.array(self.starts)
        values = np.array([np.nan if p.value is None else p.value for p in self.pieces])
        starts.flags.writeable = values.flags.writeable = False
        return starts, values

    @cached_property
    def _search(self) -> tuple[float, FloatArray]:
        """The first start and the step values after the last's copy, indexed by the search's
        insertion point i (piece i − 1): i = 0 (θ rounded below the first start) reads the last."""
        starts, values = self._arrays
        return float(starts[0]), np.concatenate([values[-1:], values])

    @cached_property
    def _floats(self) -> tuple[float, list[float], list[float]]:
        """:attr:`_search` in plain floats with the piece starts (:meth:`steps_floats`), from the pieces."""
        starts = self.starts
        values = [math.nan if p.value is None else float(p.value) for p in self.pieces]
        return float(starts[0]), starts, [values[-1], *values]

    @property
    def starts_array(self) -> FloatArray:
        """Piece starts (n,) as a read-only array (radians)."""
        return self._arrays[0]

    @cached_property
    def lifted(self) -> tuple[FloatArray, FloatArray, FloatArray, BoolArray]:
        """The pieces lifted over the periods −1 … 3 (``LIFTS``), as read-only arrays
        (5n,) sorted by start: starts, ends, values (a ramp's is its start) and ramp
        flags. Algorithm A′ searches these; built once per function, O(n)."""
        if KERNELS is not None:  # typed loops, the same arrays (algrasp.compiled)
            return KERNELS.lifted(self)  # type: ignore[no-any-return]
        pieces = self.pieces
        rows = np.array([self.starts, [p.end for p in pieces], [p.start if p.value is None else p.value for p in pieces]],
                        dtype=float)
        # (3, 1, n) + (LIFTS, 1): every row lifted by every k·P, period by period.
        lifted = (rows[:, None, :] + (np.arange(LIFTS.start, LIFTS.stop) * self.period)[:, None]).reshape(3, -1)
        ramp = np.array([p.value is None for p in pieces] * len(LIFTS))
        lifted.flags.writeable = ramp.flags.writeable = False
        return lifted[0], lifted[1], lifted[2], ramp

    def piece_at(self, theta: float) -> tuple[TransferPiece, float]:
        """The piece holding θ and the lift offset (a multiple of the period) to add."""
        base = self.pieces[0].start
        k = math.floor((theta - base) / self.period)
        x = theta - k * self.period
        i = bisect.bisect_right(self.starts, x) - 1
        return self.pieces[max(i, 0)], float(k * self.period)

    def __call__(self, theta: float) -> float:
        """F(θ), lifted (radians)."""
        p, off = self.piece_at(theta)
        return theta if p.value is None else p.value + off

    def apply(self, thetas: FloatArray) -> FloatArray:
        """F over an array of θ (radians), vectorised; O(m log n)."""
        return self.apply_on_ramp(thetas)[0]

    def apply_on_ramp(self, thetas: FloatArray) -> tuple[FloatArray, np.ndarray]:
        """:meth:`apply` and :meth:`on_ramp` from one lookup (radians); O(m log n)."""
        thetas = np.asarray(thetas, dtype=float)
        if len(self.pieces) == 1 and self.pieces[0].value is None:  # the identity: no lookup
            return thetas.copy(), np.ones(thetas.shape, dtype=bool)
        if KERNELS is not None and thetas.ndim == 1:  # typed loops, the same values (algrasp.compiled)
            return KERNELS.lookup(self, thetas, True)  # type: ignore[no-any-return]
        out, vals = self._lookup(thetas)
        ramp = np.isnan(vals)
        out += vals  # in place: the lift offset k·P plus the step's value, θ on ramps
        np.copyto(out, thetas, where=ramp)
        return out, ramp

    def apply_floats(self, thetas: Sequence[float]) -> list[float]:
        """:meth:`apply` in plain floats, value for value (:meth:`steps_floats`, θ itself on
        ramps), for the few θ a vectorised pass costs more than (radians); O(m log n)."""
        return [t if v != v else v for t, v in zip(thetas, self.steps_floats(thetas))]  # v != v: NaN, a ramp

    def steps_floats(self, thetas: Iterable[float]) -> list[float]:
        """For each θ (radians) the lifted value of the step holding it, NaN on a ramp:
        :meth:`apply_on_ramp`'s lookup in plain floats, the same operations in the same
        order (``math.floor`` made to keep ``np.floor``'s −0.0); O(m log n)."""
        if KERNELS is not None:  # typed loops, the same floats (algrasp.compiled)
            return KERNELS.steps_floats(self, thetas)  # type: ignore[no-any-return]
        first, starts, values = self._floats
        P = self.period
        out = []
        for t in thetas:
            q = (t - first) / P
            f = math.floor(q)
            kP = (float(f) if f or q else q) * P  # q = ±0.0: np.floor keeps its sign
            out.append(kP + values[bisect.bisect_right(starts, t - kP)])
        return out

    def apply_list(self, thetas: list[float]) -> FloatArray:
        """:meth:`apply` of a list of θ (radians): in plain floats for up to ``FEW_PROBES``
        (:meth:`apply_floats`), else vectorised; the same values either way."""
        if len(thetas) <= FEW_PROBES:
            return np.array(self.apply_floats(thetas), dtype=float)
        return self.apply(np.array(thetas, dtype=float))

    def on_ramp(self, thetas: FloatArray) -> np.ndarray:
        """Whether each θ (radians) lies on a ramp (F(θ) = θ), vectorised; O(m log n)."""
        return np.isnan(self._lookup(np.asarray(thetas, dtype=float))[1])

    def _lookup(self, thetas: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Lift offsets k·P (radians) and step values (NaN on ramps) of each θ."""
        if KERNELS is not None and thetas.ndim == 1:  # typed loops, the same values (algrasp.compiled)
            return KERNELS.lookup(self, thetas, False)  # type: ignore[no-any-return]
        first, values = self._search
        kP = np.empty_like(thetas)  # in place (0-d arrays too)
        np.subtract(thetas, first, out=kP)
        kP /= self.period
        np.floor(kP, out=kP)
        kP *= self.period
        # x = θ − k·P ≥ starts[0]; x may round below it: insertion point 0, the last piece.
        x = np.subtract(thetas, kP, out=np.empty_like(thetas))
        return kP, values[self._arrays[0].searchsorted(x, side="right")]

    def circle_images(self, T: float) -> list[tuple[float, float]]:
        """The arcs, on the circle of circumference T (the symmetry period), that hold
        every orientation one action leaves the part in from any start — every step value
        and every ramp — each leaving out one gap between them, shortest first (radians,
        lifted, end − start ≤ T; :func:`holding_arcs`). O(n log n)."""
        lo = [p.start if p.value is None else p.value for p in self.pieces]
        hi = [p.end if p.value is None else p.value for p in self.pieces]
        return arcs_holding(lo, hi, T)

    def symmetry_period(self, tol_rad: float) -> float:
        """Smallest T = P/k with F(θ + T) = F(θ) + T (structure and values within tol)."""
        n = len(self.pieces)
        for k in range(n, 1, -1):
            if n % k or not self._shift_matches(n // k, self.period / k, tol_rad):
                continue
            return self.period / k
        return self.period

    def _shift_matches(self, step: int, T: float, tol: float) -> bool:
        n = len(self.pieces)
        for i, p in enumerate(self.pieces):
            q = self.pieces[(i + step) % n]
            if i + step >= n:
                q = q.shifted(self.period)  # wrapped past the end: lift back up
            if p.is_ramp != q.is_ramp or abs(p.start + T - q.start) > tol or abs(p.end + T - q.end) > tol:
                return False
            if p.value is not None and q.value is not None and abs(p.value + T - q.value) > tol:
                return False
        return True

    def compose_after(self, inner: TransferFunction, tol_rad: float) -> TransferFunction:
        """self ∘ inner (inner acts first), over inner's period (Appendix C).
        O((n + m) log n): self's starts are lifted once and cut each ramp by search; self
        is evaluated at every step value and every cut cell's middle in one pass."""
        if KERNELS is not None:  # typed loops, the same pieces (algrasp.compiled)
            return TransferFunction(inner.period, tuple(KERNELS.compose(self, inner, tol_rad)))
        cells: list[tuple[float, float, bool]] = []  # [a, b) and whether inner steps there
        probes: list[float] = []  # where self is read: the step's value, or the cell's middle
        cuts_all = None  # made for the first ramp of inner: steps need none
        for p in inner.pieces:
            if p.value is not None:
                cells.append((p.start, p.end, True))
                probes.append(p.value)
                continue
            if cuts_all is None:
                cuts_all = self._lifted_starts(min(q.start for q in inner.pieces), max(q.end for q in inner.pieces))
            i, j = bisect.bisect_right(cuts_all, p.start), bisect.bisect_right(cuts_all, p.end)
            cuts = [p.start, *(c for c in cuts_all[i:j] if p.start < c < p.end), p.end]
            for a, b in zip(cuts[:-1], cuts[1:]):
                cells.append((a, b, False))
                probes.append(0.5 * (a + b))  # the middle: no rounding at boundaries
        values = self.values_at(probes)
        out = [TransferPiece(a, b, (x if step else None) if v != v else v)  # v != v: NaN, on a ramp of self
               for (a, b, step), x, v in zip(cells, probes, values)]
        return TransferFunction(inner.period, tuple(canonical(out, inner.period, tol_rad)))

    def values_at(self, thetas: list[float]) -> list[float]:
        """For each θ (radians): the value of the step holding it, lifted (NaN on a ramp),
        exactly as :meth:`piece_at` finds the piece and its lift: in plain floats for a few
        θ (a composition's probes), else in one vectorised pass (the same values)."""
        if len(thetas) <= FEW_PROBES:
            first, cuts, after = self._floats  # after[i + 1]: piece i's value
            P = self.period
            offs = [(math.floor((t - first) / P) + 0.0) * P for t in thetas]
            return [after[max(bisect.bisect_right(cuts, t - off), 1)] + off for t, off in zip(thetas, offs)]
        th = np.array(thetas, dtype=float)
        starts, values = self._arrays
        # + 0.0: no −0.0 lift (math.floor's int 0 lifts by +0.0).
        off = (np.floor((th - self.pieces[0].start) / self.period) + 0.0) * self.period
        i = np.maximum(starts.searchsorted(th - off, side="right") - 1, 0)
        return (values[i] + off).tolist()  # type: ignore[no-any-return]

    def _lifted_starts(self, a: float, b: float) -> list[float]:
        """Every piece start lifted over [a, b] (with a period to spare), sorted."""
        base, P = self.pieces[0].start, self.period
        k0 = math.floor((a - base) / P) - 1
        k1 = math.ceil((b - base) / P) + 1
        return sorted([s + float(k) * P for k in range(k0, k1 + 1) for s in self.starts])


def canonical(pieces: list[TransferPiece], period: float, tol_rad: float) -> list[TransferPiece]:
    """Merge neighbouring ramps and equal-valued steps (also across the wrap); put the
    first start in [0, period) and sort. O(n log n), in plain Python (n is small)."""
    if KERNELS is not None:  # typed loops, the same pieces (algrasp.compiled)
        return list(KERNELS.canonical(pieces, period, tol_rad))
    merged: list[TransferPiece] = []
    last_value: float | None = 0.0
    for p in pieces:  # the kinds compared inline: this loop runs for every piece of every function made
        value = p.value
        if merged and (value is None if last_value is None else
                       value is not None and abs(last_value - value) <= tol_rad):
            merged[-1] = TransferPiece(merged[-1].start, p.end, last_value)
        else:
            merged.append(p)
            last_value = value
    wrapped = None if len(merged) < 2 or merged[0].value is None else merged[0].value + period  # merged[0].shifted's
    if len(merged) > 1 and (last_value is None if wrapped is None else
                            last_value is not None and abs(last_value - wrapped) <= tol_rad):
        last = merged.pop()
        merged[0] = TransferPiece(last.start - period, merged[0].end, None if last.value is None else last.value - period)
    top = period - tol_rad
    if merged and merged[0].start >= 0.0 and merged[-1].start < top and \
            math.floor(merged[-1].start / period + ROUNDING) == 0:
        # Sorted and in [0, top) (the shift below is monotone in the start): nothing moves.
        starts = [p.start for p in merged]
        if starts == sorted(starts):
            return merged
    out = []
    for p in merged:
        start = p.start
        k = math.floor(start / period + ROUNDING) if start >= 0 else math.floor(start / period)
        if k:
            p = p.shifted(-k * period)
        out.append(p.shifted(-period) if p.start >= top else p)
    out.sort(key=_START)
    return out


_START = operator.itemgetter(0)


def from_runs(runs: list[Run], period: float, tol_rad: float) -> TransferFunction:
    """Steps and ramps from the monotone runs of d (or r), θ-ordered over 2π.

    Decreasing runs flow right to their end, increasing runs flow left to their start,
    constant runs are ramps (Appendix A); a local maximum starts the step on its right
    and a ramp's right end starts the step on its right (Appendix B). ``period`` π folds
    the diameter's doubled turn onto one period. O(n).
    """
    n = len(runs)
    if n == 1:
        r = runs[0]
        return TransferFunction(period, (TransferPiece(r.start % period, r.start % period + period, None),))
    begins = [i for i in range(n) if not (runs[i].sign == 1 and runs[i - 1].sign == -1)]
    rot = runs[begins[0]:] + [Run(r.start + TWO_PI, r.end + TWO_PI, r.sign) for r in runs[:begins[0]]]
    pieces: list[TransferPiece] = []
    i = 0
    while i < n:
        r = rot[i]
        if r.sign == 0:
            pieces.append(TransferPiece(r.start, r.end, None))
        elif r.sign == -1 and i + 1 < n and rot[i + 1].sign == 1:
            pieces.append(TransferPiece(r.start, rot[i + 1].end, r.end))
            i += 1
        elif r.sign == -1:
            pieces.append(TransferPiece(r.start, r.end, r.end))
        else:
            pieces.append(TransferPiece(r.start, r.end, r.start))
        i += 1
    if period < TWO_PI - tol_rad:
        first = pieces[0].start
        pieces = [p for p in pieces if p.start < first + period - tol_rad]
        last = pieces[-1]
        pieces[-1] = TransferPiece(last.start, first + period, last.value)
    return TransferFunction(period, tuple(canonical(pieces, period, tol_rad)))


FEW_ARCS = 64
"""Up to this many intervals :func:`arcs_holding` works in plain floats (a vectorised pass costs ~20 array calls)."""


def arcs_holding(lo: list[float], hi: list[float], T: float) -> list[tuple[float, float]]:
    """:func:`holding_arcs` of intervals given as lists (radians): in plain floats for up
    to ``FEW_ARCS`` of them, the same operations in the same order (``math.floor`` made to
    keep ``np.floor``'s −0.0, running maxima as ``np.maximum``'s a ≥ b ? a : b, stable
    sorts), else vectorised; the same arcs either way. O(n log n)."""
    if len(lo) > FEW_ARCS:
        return holding_arcs(np.array(lo, dtype=float), np.array(hi, dtype=float), T)
    if LOOKUPS is not None:  # typed loops, the same arcs (algrasp.compiled)
        return LOOKUPS.arcs_holding(lo, hi, T)  # type: ignore[no-any-return]
    if max(b - a for a, b in zip(lo, hi)) >= T:
        return [(0.0, T)]
    los, his = [], []
    for a, b in zip(lo, hi):
        q = a / T
        f = math.floor(q)
        shift = (float(f) if f or q else q) * T
        los.append(a - shift)
        his.append(b - shift)
    pairs = sorted(zip([a - T for a in los] + los + [a + T for a in los], [b - T for b in his] + his + [b + T for b in his]),
                   key=_START)
    gaps: list[tuple[float, int, float]] = []  # (−gap, k, the reach before it)
    reach = -math.inf
    for k in range(len(pairs) - 1):
        h = pairs[k][1]
        reach = reach if reach >= h else h
        gap = pairs[k + 1][0] - reach
        if 0.0 <= reach < T and gap > 0.0:
            gaps.append((-gap, k, reach))
    if not gaps:
        return [(0.0, T)]
    gaps.sort(key=_START)  # stable: the widest gap left out first, ties in order
    return [(float(pairs[k + 1][0]), float(reach_k + T)) for _, k, reach_k in gaps]


def holding_arcs(lo: FloatArray, hi: FloatArray, T: float) -> list[tuple[float, float]]:
    """Every arc of the circle of circumference T that holds all the intervals [lo_i, hi_i]
    and leaves out one gap between them (the gap's complement), as lifted intervals,
    shortest first — the first is their circular hull; [(0, T)] when they leave no gap.
    Three lifted copies, so intervals reaching past T cover the start; O(n log n)."""
    if (hi - lo).max() >= T:
        return [(0.0, T)]
    shift = np.floor(lo / T) * T
    lo, hi = lo - shift, hi - shift
    L = np.concatenate([lo - T, lo, lo + T])
    H = np.concatenate([hi - T, hi, hi + T])
    order = L.argsort(kind="stable")
    L, H = L[order], H[order]
    reach = np.maximum.accumulate(H)
    gaps = L[1:] - reach[:-1]
    ks = ((reach[:-1] >= 0.0) & (reach[:-1] < T) & (gaps > 0.0)).nonzero()[0]
    if not len(ks):
        return [(0.0, T)]
    ks = ks[(-gaps[ks]).argsort(kind="stable")]  # the widest gap left out: the shortest arc
    return [(float(L[k + 1]), float(reach[k] + T)) for k in ks]
