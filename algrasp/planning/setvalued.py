"""Set-valued transfer functions F_κ (conventions §7): where a real part may come to rest.

For f = d (squeeze) or r (push) and the dead band (s, σ), each orientation θ is
classified by the drawn slope g = f′(θ) (part units per radian):

* rest is possible where |g| ≤ μ_j·f + s_hi + σ (μ_j the largest jaw friction of a
  squeeze, 0 for a push), certain where |g| ≤ s_lo − σ (conventions §8: the weakest
  holding cell of the ranges);
* downhill motion (direction −sign g) is possible where |g| > s_lo − σ; uphill too where
  moreover |g| ≤ σ (the real slope may have either sign).

A part starting at θ rests somewhere in ``[lower(θ), upper(θ)]``: ``upper`` is the end of
the run of right-movable zones containing θ (it stops at the first zone it cannot cross),
θ itself where it may stay, or the start of the forced-left run it slides down; ``lower``
mirrors it. Both are monotone step/ramp functions — :class:`~algrasp.planning.transfer.TransferFunction`
— so an interval [a, b) maps into [lower(a), upper(b⁻)]. With s = σ = 0 both equal the
exact function of §3.

The classification is made on cells between nodes: a uniform grid of ``GRID_RAD``, every
Gauss-map breakpoint (where f′ jumps) and every extremum of the exact analysis. Each cell
takes the union of the permissions sampled at its two ends and its middle, in every
copy θ + kT of the symmetry period T judged to tolerance (a tessellated gear has the
period of its teeth): the union is conservative, so images only grow. O(c·K) for c cells
and K copies, all in vectorised passes.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from algrasp.errors import NotOrientableError
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.functions import SupportPairFunction
from algrasp.geometry.tolerances import ROUNDING
from algrasp.planning.barriers import barriers
from algrasp.planning.transfer import TransferFunction, TransferPiece, canonical, holding_arcs

GRID_RAD = 2e-3
"""Largest cell of the classification grid (0.115°): dead-zone edges are placed to this
(kinks and extrema are nodes of their own, so stable orientations are exact)."""
SYMMETRY_SAMPLES = 1260
"""Samples per natural period for judging symmetry; divisible by every k ≤ 10 and many more."""
MAX_SYMMETRY_ORDER = 360
MAX_SYMMETRY_CANDIDATES = 4
"""Orders not dividing the sample count that pass the Fourier screen and are then checked
on f itself (best screened first): each costs one evaluation of f at every sample."""
_INSIDE = 1e-6
"""Relative offset of the end samples inside a cell (kinks sit on cell nodes)."""


@dataclass(frozen=True, eq=False)
class SetTransfer:
    """F_κ as its lower and upper bounds (both of period ``symmetry``).

    ``rest_zones`` are the dead zones {|f′| ≤ κ} over one natural period (radians,
    [start, end)); ``period`` is the natural period (π or 2π).
    """

    lower: TransferFunction
    upper: TransferFunction
    period: float
    symmetry: float
    rest_zones: tuple[tuple[float, float], ...]
    outcomes: tuple[tuple[float, float], ...]
    """Closed intervals (radians, lifted) holding every orientation the part can rest in
    after the action, from any start: the rest zones and the stops of the steps."""

    @property
    def orientable(self) -> bool:
        return bool(self.lower.steps or self.upper.steps)

    def image(self, lo: FloatArray, hi: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Hull of the images of the closed intervals [lo, hi] (radians, lifted)."""
        return self.lower.apply(lo), self.upper.apply(hi)

    def circle_images(self) -> list[tuple[float, float]]:
        """The arcs, on the circle of period T, that hold every orientation the part can
        end in from any start (``outcomes``), each leaving out one gap between them:
        [start, end] lifted, end − start ≤ T, shortest first (the first is their circular
        hull; :func:`~algrasp.planning.transfer.holding_arcs`). The image of the whole
        circle: hulls of single points would fill the gaps that uncertain zones bridge, but
        a part only ever rests at an outcome."""
        lo = np.array([a for a, _ in self.outcomes])
        hi = np.array([b for _, b in self.outcomes])
        return holding_arcs(lo, hi, self.symmetry)

    def compose_after(self, inner: SetTransfer, tol_rad: float) -> SetTransfer:
        """self ∘ inner (inner acts first): bounds compose since both are monotone. The
        outcomes are self's outcomes (where it can leave a part at all) that meet the
        image of one of inner's outcomes."""
        lower = self.lower.compose_after(inner.lower, tol_rad)
        upper = self.upper.compose_after(inner.upper, tol_rad)
        lo, hi = self.image(np.array([a for a, _ in inner.outcomes]), np.array([b for _, b in inner.outcomes]))
        # self's outcomes repeat with its period; the composition has inner's.
        T = inner.symmetry
        copies = np.arange(max(1, int(round(T / self.symmetry)))) * self.symmetry
        mine = (np.array(self.outcomes)[None, :, :] + copies[:, None, None]).reshape(-1, 2)
        start = np.mod(mine[:, 0] - lo[:, None], T)  # outcome start relative to each image start
        meets = (start <= (hi - lo)[:, None]) | (start + (mine[:, 1] - mine[:, 0])[None, :] >= T)
        kept = tuple((float(a), float(b)) for a, b in mine[meets.any(axis=0)])
        return SetTransfer(lower, upper, inner.period, inner.symmetry, inner.rest_zones, kept)

def slopes(f: SupportPairFunction, theta: FloatArray) -> tuple[FloatArray, FloatArray]:
    """f′(θ) (part units per radian) and f(θ) from one pass of exact support points.

    With ψ = π/2 − θ, u = (cos ψ, sin ψ) and p(ψ) the support point (both ends of the chord
    from one batched call): f = ⟨p_near − p(ψ + π), u⟩ and f′ = −⟨p_near − p(ψ + π), u′⟩,
    p_near = p(ψ) for d and the centre of mass c for r.
    """
    psi = np.pi / 2 - np.asarray(theta, dtype=float)
    n = len(psi)
    if f.kind == "diameter":
        both = f.hull.support_points(np.concatenate([psi, psi + np.pi]))
        chord = both[:n] - both[n:]
    else:
        chord = np.asarray(f.com, dtype=float) - f.hull.support_points(psi + np.pi)
    c, s = np.cos(psi), np.sin(psi)
    return np.asarray(chord[:, 0] * s - chord[:, 1] * c), np.asarray(chord[:, 0] * c + chord[:, 1] * s)


def tolerant_symmetry(f: SupportPairFunction, value_tol: float) -> float:
    """The smallest T = P/k with |f(θ + T) − f(θ)| ≤ value_tol at every sample (radians).

    Orders k dividing the sample count are tested by rolling the samples; the others (a
    25-tooth gear) are screened with a bound from the samples' Fourier series
    (:func:`_shift_bound`, the sampling's own error as slack) and confirmed by evaluating f
    at the shifted points. Shifts so small that the slope alone keeps f within
    the tolerance (|f′|·T ≤ 4·tol) prove nothing and are not tried."""
    P = f.period
    M = SYMMETRY_SAMPLES
    theta = np.linspace(0.0, P, M, endpoint=False)
    v = f.values(theta)
    jump = float(np.max(np.abs(np.diff(v))))
    top = min(MAX_SYMMETRY_ORDER, int(P * jump * M / P / (4.0 * value_tol)) if value_tol > 0 else MAX_SYMMETRY_ORDER)
    ks = np.arange(top, 1, -1)
    if not len(ks):
        return P
    screen = _shift_bound(v, ks)
    errors: dict[int, float] = {}
    divisors = ks[M % ks == 0]  # exact and cheap: every divisor is rolled, all in one pass
    rolled = v[(np.arange(M)[None, :] + (M // divisors)[:, None]) % M]
    errors.update(zip(divisors.tolist(), np.max(np.abs(rolled - v[None, :]), axis=1).tolist()))
    others = ks[(screen <= value_tol + 0.5 * jump) & (M % ks != 0)]
    for k in others[np.argsort(screen[np.isin(ks, others)])][:MAX_SYMMETRY_CANDIDATES].tolist():
        errors[k] = float(np.max(np.abs(f.values(theta + P / k) - v)))
    passing = {k: e for k, e in errors.items() if e <= value_tol}
    if not passing:
        return P
    # A near miss (a 26-fold shift of a 25-tooth gear) passes a loose tolerance too, but
    # only the true order and its divisors repeat f to the drawing's own noise.
    best = min(passing.values())
    return P / max(k for k, e in passing.items() if e <= 10.0 * best + ROUNDING * float(np.max(np.abs(v))))


SCREEN_HARMONICS = 64
"""Harmonics of f treated one by one in the symmetry screen; the rest are bounded together."""


def _shift_bound(v: FloatArray, ks: np.ndarray) -> FloatArray:
    """Upper bound on max |f(θ + P/k) − f(θ)| for each k from f's Fourier series:
    Σ_j |c_j|·|e^{2πij/k} − 1| over the largest harmonics, plus 2·Σ|c_j| over the rest.
    O(len(ks) · SCREEN_HARMONICS)."""
    c = np.fft.rfft(v) / len(v)
    amp = np.abs(c) * np.where(np.arange(len(c)) == 0, 1.0, 2.0)  # one-sided spectrum
    top = np.argsort(amp)[::-1][:SCREEN_HARMONICS]
    rest = 2.0 * float(amp.sum() - amp[top].sum())
    # |e^{2πij/k} − 1| = 2|sin(πj/k)|: real arithmetic, a third of the complex exp's cost.
    return np.asarray(2.0 * np.abs(np.sin(np.pi * np.outer(1.0 / ks, top))) @ amp[top] + rest)


def _nodes(f: SupportPairFunction, T: float) -> tuple[FloatArray, np.ndarray]:
    """Cell nodes in [0, T): grid, breakpoints (θ of every Gauss-map breakpoint) and
    extrema; and whether f′ may jump at each (breakpoints and extrema do, grid nodes not)."""
    grid = np.linspace(0.0, T, max(8, int(np.ceil(T / GRID_RAD))), endpoint=False)
    bp = f.hull.breakpoints
    theta_bp = np.concatenate([np.pi / 2 - bp, 1.5 * np.pi - bp]) if f.kind == "diameter" else 1.5 * np.pi - bp
    runs = np.array([r.start for r in f.runs])
    raw = np.mod(np.concatenate([grid, theta_bp, runs]), T)
    flags = np.concatenate([np.zeros(len(grid), dtype=bool), np.ones(len(theta_bp) + len(runs), dtype=bool)])
    order = np.argsort(raw, kind="stable")
    raw, flags = raw[order], flags[order]
    group = np.concatenate([[0], np.cumsum(np.diff(raw) > ROUNDING)])
    if T - raw[-1] <= ROUNDING:
        group[group == group[-1]] = 0  # a node a hair below T is node 0
    nodes = raw[np.unique(group, return_index=True)[1]]
    kink = np.zeros(len(nodes), dtype=bool)
    np.logical_or.at(kink, group, flags)
    return nodes, kink


def _samples(f: SupportPairFunction, x: FloatArray, kink: np.ndarray, T: float) -> tuple[FloatArray, FloatArray]:
    """f′ and f just inside both ends of every cell in every copy: (n, 2, K) each.

    f′ is continuous at grid nodes, so one evaluation there serves the cells on both sides;
    at kinks the left and right limits are evaluated apart. The end of the last cell is
    node 0 of the next copy."""
    K = int(round(f.period / T))
    widths = np.diff(np.append(x, T))
    copies = np.arange(K) * T
    right = x + _INSIDE * widths
    left = x[kink] - _INSIDE * np.roll(widths, 1)[kink]
    theta = np.concatenate([right, left])[:, None] + copies[None, :]
    g, v = (a.reshape(theta.shape) for a in slopes(f, theta.ravel()))
    n = len(x)
    g_end, v_end = g[np.arange(1, n + 1) % n].copy(), v[np.arange(1, n + 1) % n].copy()
    at_kink = np.full(n, -1)
    at_kink[np.nonzero(kink)[0]] = n + np.arange(int(kink.sum()))
    nxt = np.arange(1, n + 1) % n
    jump = kink[nxt]
    g_end[jump], v_end[jump] = g[at_kink[nxt[jump]]], v[at_kink[nxt[jump]]]
    g_end[-1], v_end[-1] = np.roll(g_end[-1], -1), np.roll(v_end[-1], -1)
    return np.stack([g[:n], g_end], axis=1), np.stack([v[:n], v_end], axis=1)


@functools.lru_cache(maxsize=8)
def _sampled(f: SupportPairFunction, value_tol: float) -> tuple[float, FloatArray, np.ndarray, FloatArray, FloatArray]:
    """Symmetry, cell nodes and samples of f: all that does not depend on the dead band,
    so the probes of a limit search (one part, many physics) compute them once. Keyed on
    the function object (compared by identity); the arrays are read-only."""
    T = tolerant_symmetry(f, value_tol)
    x, kink = _nodes(f, T)
    g, v = _samples(f, x, kink, T)
    for a in (x, kink, g, v):
        a.setflags(write=False)
    return T, x, kink, g, v


def _permissions(g: FloatArray, v: FloatArray, stall: tuple[float, float], sigma: float,
                 jaw_friction: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(right, left, rest) possible, each OR-ed over the last two axes (samples, copies).

    Motion is possible only where the weakest holding cell lets go (least stall, no jaw
    friction): |g| > s_lo − σ; rest wherever the strongest cell may hold:
    |g| ≤ μ_j·f + s_hi + σ (``v`` holds f, so the jaw term is the friction couple of two
    contacts f apart; 0 for a push)."""
    a = np.abs(g)
    movable = a > stall[0] - sigma
    either = a <= sigma
    right = movable & ((g < 0.0) | either)
    left = movable & ((g > 0.0) | either)
    rest = a <= jaw_friction * np.abs(v) + stall[1] + sigma
    axes = tuple(range(1, g.ndim))
    return np.asarray(right.any(axis=axes)), np.asarray(left.any(axis=axes)), np.asarray(rest.any(axis=axes))


def shallow_basins(values: FloatArray, depth: float) -> np.ndarray:
    """Cells (cyclic sequence of f at cell starts) of a basin whose minimum lies less than
    ``depth`` below the lower of its two bounding maxima, up to that rim: the real f
    (within depth/2 of the drawn one) may have no minimum there. O(m).

    >>> shallow_basins(np.array([5, 4, 3, 2.9, 2.95, 2, 1, 2, 3, 4.0]), 0.1).astype(int).tolist()
    [0, 0, 0, 1, 1, 0, 0, 0, 0, 0]
    """
    m = len(values)
    out = np.zeros(m, dtype=bool)
    step = np.sign(np.diff(np.append(values, values[0])))
    nz = np.nonzero(step)[0]
    if depth <= 0.0 or len(nz) < 2:
        return out
    s = step[nz]
    turn = s != np.roll(s, 1)  # the sign changes at nz[k]: an extremum at its start index
    idx, kinds = nz[turn], s[turn]  # kinds +1: a minimum (f rises after it), −1: a maximum
    if len(idx) < 2:
        return out
    for k in np.nonzero(kinds > 0)[0].tolist():
        lo, hi = idx[k - 1], idx[(k + 1) % len(idx)]  # the maxima around minimum idx[k]
        rim = min(values[lo], values[hi])
        if rim - values[idx[k]] < depth:
            span = np.arange(lo, hi + (m if hi < lo else 0) + 1) % m
            out[span[values[span] <= rim]] = True  # the basin below its lower rim
    return out


def _run_edges(flags: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For each cell i (cyclic, lifted indices): the first cell of the run of True flags
    containing it, and the first False cell after it. Vectorised over three copies."""
    n = len(flags)
    idx = np.arange(-n, 2 * n)
    f3 = np.tile(flags, 3)
    big = 4 * n
    last_false = np.maximum.accumulate(np.where(~f3, idx, -big))
    next_false = np.minimum.accumulate(np.where(~f3, idx, big)[::-1])[::-1]
    return last_false[n:2 * n] + 1, next_false[n:2 * n]


@dataclass(frozen=True)
class _Cells:
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
        n = len(self.x)
        return np.asarray(self.x[np.mod(j, n)] + np.floor_divide(j, n) * self.T)


def _bounds(c: _Cells, tol_rad: float) -> tuple[TransferFunction, TransferFunction]:
    """Lower and upper step/ramp functions from per-cell permissions and barriers."""
    R, L, S = c.right, c.left, c.rest
    # A run of movable cells all round the circle has no end: only the barriers stop it.
    _, right_end = _run_edges(R)
    left_start, _ = _run_edges(L)
    forced_left_start, _ = _run_edges(~R & ~S)
    _, forced_right_end = _run_edges(~L & ~S)
    run_right = np.full(len(R), np.inf) if R.all() else c.at(right_end)
    run_left = np.full(len(L), -np.inf) if L.all() else c.at(left_start)
    up = np.where(R, np.minimum(run_right, c.barrier_right), np.where(S, np.nan, c.at(forced_left_start)))
    lo = np.where(L, np.maximum(run_left, c.barrier_left), np.where(S, np.nan, c.at(forced_right_end)))
    if not (np.all(np.isfinite(up[R])) and np.all(np.isfinite(lo[L]))):
        raise NotOrientableError("dead_band", "with this dead band the part may turn without end: the slopes of "
                                 "the drawing are all within the shape tolerance")
    ends = np.append(c.x[1:], c.x[0] + c.T)
    up, lo = _monotone(c.x, ends, up, lo, c.T)
    return _tf(c.x, ends, lo, c.T, tol_rad), _tf(c.x, ends, up, c.T, tol_rad)


def _monotone(x: FloatArray, ends: FloatArray, up: FloatArray, lo: FloatArray, T: float) -> tuple[FloatArray, FloatArray]:
    """Raise upper (lower lower) where barriers made them dip: both must be monotone.
    A ramp (NaN: θ itself) spans [x_i, end_i); a dipping ramp becomes a step."""
    n = len(x)
    lift = np.repeat(np.arange(-1, 2), n) * T
    u3 = np.tile(up, 3) + lift
    top = np.where(np.isnan(u3), np.tile(ends, 3) + lift, u3)
    bottom = np.where(np.isnan(u3), np.tile(x, 3) + lift, u3)
    before = np.concatenate([[-np.inf], np.maximum.accumulate(top)[:-1]])[n:2 * n] - 0.0
    up = np.where(bottom[n:2 * n] < before, np.maximum(before, top[n:2 * n]), up)
    l3 = np.tile(lo, 3) + lift
    bot = np.where(np.isnan(l3), np.tile(x, 3) + lift, l3)
    tp = np.where(np.isnan(l3), np.tile(ends, 3) + lift, l3)
    after = np.concatenate([np.minimum.accumulate(bot[::-1])[::-1][1:], [np.inf]])[n:2 * n]
    lo = np.where(tp[n:2 * n] > after, np.minimum(after, bot[n:2 * n]), lo)
    return up, lo


def _tf(starts: FloatArray, ends: FloatArray, values: FloatArray, T: float, tol_rad: float) -> TransferFunction:
    """Cells → pieces, neighbours with the same value (or both ramps) merged first in
    one array pass, so only the distinct pieces become objects."""
    nan = np.isnan(values)
    same = (nan & np.roll(nan, 1)) | (~nan & ~np.roll(nan, 1) & (np.abs(values - np.roll(values, 1)) <= tol_rad))
    same[0] = False
    first = np.nonzero(~same)[0]
    last = np.append(first[1:], len(values)) - 1
    pieces = [TransferPiece(float(a), float(b), None if np.isnan(v) else float(v))
              for a, b, v in zip(starts[first].tolist(), ends[last].tolist(), values[first].tolist())]
    return TransferFunction(T, tuple(canonical(pieces, T, tol_rad)))


def _rest_zones(nodes: FloatArray, T: float, rest: np.ndarray, P: float) -> tuple[tuple[float, float], ...]:
    """Maximal rest-possible zones over one natural period P (K = P/T copies of the cells),
    [start, end) in radians; a zone wrapping past P starts below 0. Vectorised."""
    K = int(round(P / T))
    x = (nodes[None, :] + (np.arange(K) * T)[:, None]).ravel()
    r = np.tile(rest, K)
    if r.all():
        return ((0.0, P),)
    if not r.any():
        return ()
    ends = np.append(x[1:], P)
    first = r & ~np.roll(r, 1)
    last = r & ~np.roll(r, -1)
    a, b = x[first], ends[last]
    if r[0] and r[-1]:  # the zone through 0 starts at the last start and ends at the first end
        b = np.roll(b, -1)
        a[-1] -= P
    return tuple(zip(a.tolist(), b.tolist()))


def set_transfer(f: SupportPairFunction, stall: tuple[float, float], sigma: float, value_tol: float, tol_rad: float,
                 jaw_friction: float = 0.0, value_err: float | None = None, shallow: float = 0.0) -> SetTransfer:
    """F_κ of d or r (see module docs) over a stall range ``(s_lo, s_hi)`` and, for a
    squeeze, the largest jaw friction. ``value_tol`` judges the drawing's symmetry;
    ``value_err`` (default the same) bounds how far the real f is from the drawn one
    (the barriers: the manufacturing profile tolerance counts here); basins of f less
    than ``shallow`` deep may be left either way (:func:`shallow_basins`). Raises NotOrientableError when the part may turn
    without end. O((c + b)·K·log) for c grid cells, b breakpoints, K symmetric copies."""
    P = f.period
    T, x, kink, g, v = _sampled(f, value_tol)
    right, left, rest = _permissions(g, v, stall, sigma, jaw_friction)
    err = value_tol if value_err is None else value_err
    # A drawn minimum shallower than the manufacturing tolerance may be no minimum of the
    # real part (nor of the simulation's compliant contact): its basin may go either way.
    basin = shallow_basins(v[:, 0, :].T.ravel(), shallow).reshape(v.shape[2], -1).any(axis=0)
    right, left = right | basin, left | basin
    # The energy bound holds for the weakest stall: every cell lowers f at least that fast.
    br, bl = barriers(x, T, v[:, 0, :].T, v.max(axis=1).T, stall[0], err)
    cells = _Cells(x, T, right, left, rest, br, bl)
    lower, upper = _bounds(cells, tol_rad)
    zones = _rest_zones(x, T, rest, T)
    stops = [(p.value, p.value) for F in (lower, upper) for p in F.steps if p.value is not None]
    return SetTransfer(lower, upper, P, T, _rest_zones(x, T, rest, P), (*zones, *stops))
