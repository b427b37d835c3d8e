"""The cells of a set-valued transfer function (:mod:`algrasp.planning.setvalued`) and what
they give: per cell [x_i, x_{i+1}) of one symmetry period T, whether a part there may move
right, left or rest and how far an energy barrier lets it go; from these, the runs of
movable cells, the lower and upper step/ramp bounds and the rest zones. Vectorised over
the cells (the runs over three lifted copies), O(n) passes for n cells; pure, radians.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from algrasp.compiled import KERNELS
from algrasp.errors import NotOrientableError
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.lazy import cached_property
from algrasp.planning.transfer import TransferFunction, TransferPiece, canonical


def _run_bounds(flags: np.ndarray) -> np.ndarray:
    """For each cell i (cyclic, lifted indices), along the last axis of ``flags`` (4, n):
    in rows 0 and 1 the first False cell at or after i (the end of the run of True flags
    containing i, i itself where flags[i] is False), in rows 2 and 3 the first cell of
    that run (i + 1 where flags[i] is False). One pass over three copies."""
    n = flags.shape[-1]
    f3 = np.concatenate([flags, flags, flags], axis=-1)
    at = np.arange(-n, 2 * n)
    next_false = np.minimum.accumulate(np.where(f3[:2], 4 * n, at)[:, ::-1], axis=-1)[:, ::-1]
    last_false = np.maximum.accumulate(np.where(f3[2:], -4 * n, at), axis=-1)
    return np.concatenate([next_false[:, n:2 * n], last_false[:, n:2 * n] + 1])


@dataclass(frozen=True)
class Cells:
    """Cells [x_i, x_i + width_i) over one period T with their permissions and barriers."""

    x: FloatArray
    T: float
    right: np.ndarray
    left: np.ndarray
    rest: np.ndarray
    barrier_right: FloatArray
    barrier_left: FloatArray

    def at(self, j: np.ndarray) -> FloatArray:
        """Lifted start of cell j (any integer)."""
        lift, i = np.divmod(j, len(self.x))
        return np.asarray(self.x[i] + lift * self.T)

    @cached_property
    def runs(self) -> FloatArray:
        """(4, n) lifted cell starts, found in one stacked pass: where the run of
        right-movable and of forced-right cells (neither left nor rest) containing each
        cell ends, and where the run of left-movable and of forced-left cells starts."""
        R, L, S = self.right, self.left, self.rest
        if KERNELS is not None:  # typed loops, the same values (algrasp.compiled)
            return np.asarray(KERNELS.runs(self.x, self.T, R, L, S))
        return self.at(_run_bounds(np.array([R, ~L & ~S, L, ~R & ~S])))

    @cached_property
    def run_limits(self) -> tuple[FloatArray, FloatArray]:
        """Where the run of right- (left-) movable cells containing each cell ends (starts),
        lifted; ±∞ for a run all round the circle (only the barriers stop it)."""
        run_right = np.full(len(self.x), np.inf) if self.right.all() else self.runs[0]
        run_left = np.full(len(self.x), -np.inf) if self.left.all() else self.runs[2]
        return run_right, run_left


def bounds(c: Cells, tol_rad: float) -> tuple[TransferFunction, TransferFunction]:
    """Lower and upper step/ramp functions from per-cell permissions and barriers."""
    R, L, S = c.right, c.left, c.rest
    run_right, run_left = c.run_limits
    if KERNELS is not None:  # typed loops to the merged pieces, the same values (algrasp.compiled)
        found = KERNELS.bound_pieces(c.x, c.T, R, L, S, run_right, run_left, c.runs, c.barrier_right, c.barrier_left, tol_rad)
        if found is None:
            raise turning_error()
        return _pieces_tf(found[0], c.T, tol_rad), _pieces_tf(found[1], c.T, tol_rad)
    up = np.where(R, np.minimum(run_right, c.barrier_right), np.where(S, np.nan, c.runs[3]))
    lo = np.where(L, np.maximum(run_left, c.barrier_left), np.where(S, np.nan, c.runs[1]))
    if not (np.isfinite(up[R]).all() and np.isfinite(lo[L]).all()):
        raise turning_error()
    ends = np.concatenate([c.x[1:], [c.x[0] + c.T]])
    up, lo = _monotone(c.x, ends, up, lo, c.T)
    return _tf(c.x, ends, lo, c.T, tol_rad), _tf(c.x, ends, up, c.T, tol_rad)


def turning_error() -> NotOrientableError:
    """The refusal of a dead band under which the part may turn without end."""
    return NotOrientableError("dead_band", "with this dead band the part may turn without end: the slopes of "
                              "the drawing are all within the shape tolerance")


def _monotone(x: FloatArray, ends: FloatArray, up: FloatArray, lo: FloatArray, T: float) -> tuple[FloatArray, FloatArray]:
    """Raise upper (lower lower) where barriers made them dip: both must be monotone.
    A ramp (NaN: θ itself) spans [x_i, end_i); a dipping ramp becomes a step. Cell i is
    compared with every cell before it over the period before (after it, over the period
    after)."""
    nan = np.isnan(up)
    top, bottom = np.where(nan, ends, up), np.where(nan, x, up)
    before = np.maximum.accumulate(np.concatenate([[top.max() - T], top[:-1] + 0.0]))
    up = np.where(bottom < before, np.maximum(before, top + 0.0), up)  # (+ 0.0: no −0.0 value; a comparison needs none)
    nan = np.isnan(lo)
    top, bottom = np.where(nan, ends, lo), np.where(nan, x, lo)
    after = np.minimum.accumulate(np.concatenate([bottom[1:] + 0.0, [bottom.min() + T]])[::-1])[::-1]
    lo = np.where(top > after, np.minimum(after, bottom + 0.0), lo)
    return up, lo


def _tf(starts: FloatArray, ends: FloatArray, values: FloatArray, T: float, tol_rad: float) -> TransferFunction:
    """Cells → pieces, neighbours with the same value (or both ramps) merged first in
    one array pass, so only the distinct pieces become objects."""
    nan = np.isnan(values)
    # Cell i starts a piece unless it and cell i − 1 are both ramps or agree to tol (a
    # NaN, a ramp, agrees with no value); cell 0 always does.
    new = np.empty(len(values), dtype=bool)
    new[0] = True
    np.logical_not((nan[1:] & nan[:-1]) | (np.abs(values[1:] - values[:-1]) <= tol_rad), out=new[1:])
    first = new.nonzero()[0]
    last = np.concatenate([first[1:], [len(values)]]) - 1
    return _pieces_tf(zip(starts[first].tolist(), ends[last].tolist(), values[first].tolist()), T, tol_rad)


def _pieces_tf(found: Iterable[tuple[float, float, float | None]], T: float, tol_rad: float) -> TransferFunction:
    """The function of merged pieces (start, end, value; NaN or None: a ramp)."""
    pieces = [TransferPiece(a, b, None if v is None or v != v else v) for a, b, v in found]  # v != v: NaN
    return TransferFunction(T, tuple(canonical(pieces, T, tol_rad)))


def rest_zones(nodes: FloatArray, T: float, rest: np.ndarray, P: float) -> tuple[tuple[float, float], ...]:
    """Maximal rest-possible zones over one natural period P (K = P/T copies of the cells),
    [start, end) in radians; a zone wrapping past P starts below 0. Vectorised."""
    K = int(round(P / T))
    if KERNELS is not None:  # typed loops, the same zones (algrasp.compiled)
        return KERNELS.rest_zones(nodes, T, rest, P, K)  # type: ignore[no-any-return]
    x, r = nodes, rest  # one copy (nodes are never −0.0: + 0·T would change nothing)
    if K > 1:
        x, r = (nodes[None, :] + (np.arange(K) * T)[:, None]).ravel(), np.concatenate([rest] * K)
    if r.all():
        return ((0.0, P),)
    if not r.any():
        return ()
    ends = np.concatenate([x[1:], [P]])
    first = r & ~np.concatenate([r[-1:], r[:-1]])
    last = r & ~np.concatenate([r[1:], r[:1]])
    a, b = x[first], ends[last]
    if r[0] and r[-1]:  # the zone through 0 starts at the last start and ends at the first end
        b = np.concatenate([b[1:], b[:1]])
        a[-1] -= P
    return tuple(zip(a.tolist(), b.tolist()))
