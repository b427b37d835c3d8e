"""The symmetry period of d or r judged to a value tolerance (conventions §7).

A drawing is never exactly symmetric (a tessellated gear, a cut part): f has period T = P/k
when |f(θ + T) − f(θ)| ≤ tol everywhere. Judged on samples: orders dividing the sample
count by rolling, the others screened by a Fourier bound and confirmed on f itself.
"""

from __future__ import annotations

import bisect
import functools

import numpy as np

from algrasp.compiled import KERNELS
from algrasp.geometry.angles import TWO_PI
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.functions import SupportPairFunction
from algrasp.geometry.tolerances import ROUNDING

SYMMETRY_SAMPLES = 1260
"""Samples per natural period for judging symmetry; divisible by every k ≤ 10 and many more."""
MAX_SYMMETRY_ORDER = 360
MAX_SYMMETRY_CANDIDATES = 4
"""Orders not dividing the sample count that pass the Fourier screen and are then checked
on f itself (best screened first): each costs one evaluation of f at every sample."""

def tolerant_symmetry(f: SupportPairFunction, value_tol: float) -> float:
    """The smallest T = P/k with |f(θ + T) − f(θ)| ≤ value_tol at every extremum of the
    exact analysis and every sample (radians).

    The extrema go first (:func:`_extremum_orders`): one evaluation of f at a few extrema
    shifted by every P/k rules out most orders, and every order of a part without
    symmetry, before any sample is taken. Orders k dividing the sample count are then
    tested by rolling the samples; the others (a 25-tooth gear) are screened with a bound
    from the samples' Fourier series (:func:`_shift_bound`, the sampling's own error as
    slack) and confirmed by evaluating f at the shifted points. Shifts so small that the
    slope alone keeps f within the tolerance (|f′|·T ≤ 4·tol) prove nothing and are not
    tried."""
    P = f.period
    allowed = _extremum_orders(f, value_tol)
    if not len(allowed):
        return P
    M = SYMMETRY_SAMPLES
    theta = np.linspace(0.0, P, M, endpoint=False)
    v = f.values(theta)
    jump = float(np.max(np.abs(np.diff(v))))
    top = min(MAX_SYMMETRY_ORDER, int(P * jump * M / P / (4.0 * value_tol)) if value_tol > 0 else MAX_SYMMETRY_ORDER)
    ks = np.arange(top, 1, -1)
    ks = ks[np.isin(ks, allowed)]
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


_ORDERS = np.arange(MAX_SYMMETRY_ORDER, 1, -1)
"""Every order tried, largest first (read-only)."""
_ALL_SHIFTS = {P: P / _ORDERS for P in (np.pi, TWO_PI)}
"""P/k for every order and each natural period P (d: π, r: 2π), made once (read-only)."""
for _a in (_ORDERS, *_ALL_SHIFTS.values()):
    _a.setflags(write=False)


def _shifts(P: float, ks: np.ndarray) -> np.ndarray:
    """P/k for each order k (radians): made once for every order and P = π or 2π."""
    made = _ALL_SHIFTS.get(P) if ks is _ORDERS else None
    return P / ks if made is None else made

EXTREMA_TESTED = 16
"""Extrema (half the lowest, half the highest) at which every order is tried."""


def _extremum_orders(f: SupportPairFunction, value_tol: float) -> np.ndarray:
    """Orders k (2..MAX_SYMMETRY_ORDER) with |f(θ_e + P/k) − f(θ_e)| ≤ value_tol at the
    tested extrema θ_e: a necessary condition, exact, in one vectorised evaluation of
    O(EXTREMA_TESTED · MAX_SYMMETRY_ORDER) points. Without extrema (f constant) every order."""
    ks = _ORDERS
    if not f.extrema:
        return ks.copy()
    # The lowest and highest extrema (np.median would import numpy.ma on first use), in
    # plain floats until the lowest has been tried (sorted: a stable sort, as argsort's).
    values = [e.value for e in f.extrema]
    order_list = sorted(range(len(values)), key=values.__getitem__)
    lowest = f.extrema[order_list[0]]
    if _none_at(f, lowest.theta, lowest.value, ks, value_tol):
        return ks[:0]
    theta, value, order = np.array([e.theta for e in f.extrema]), np.array(values), np.array(order_list)
    pick = order if len(order) <= EXTREMA_TESTED else np.concatenate([order[:EXTREMA_TESTED // 2], order[-(EXTREMA_TESTED // 2):]])
    # The lowest and the highest extremum first: they rule out most orders at an eighth of
    # the cost; the survivors are then tried at every picked extremum (the same test).
    for chosen in (pick[[0, -1]], pick):
        shifts = _shifts(f.period, ks)
        shifted = f.values((theta[chosen][None, :] + shifts[:, None]).ravel()).reshape(len(ks), -1)
        ks = ks[np.all(np.abs(shifted - value[chosen][None, :]) <= value_tol, axis=1)]
        if not len(ks):
            break
    return np.asarray(ks)


SCREEN_SLACK = ROUNDING
"""Relative slack (to f's value) by which every order must fail at the lowest extremum
for :func:`_none_at` to rule them all out: far above the rounding of one evaluation of
f, so the test it saves would have failed them too."""


def _none_at(f: SupportPairFunction, theta: float, value: float, ks: np.ndarray, value_tol: float) -> bool:
    """Whether every order k fails at one extremum (θ, f(θ)) by more than the slack: then
    :func:`_extremum_orders` allows none (a part without symmetry, at half the cost of
    trying two extrema; the lowest, where f rises on both sides). O(len(ks)), or
    O(r log len(ks)) for r runs when :func:`_none_by_runs` settles it."""
    threshold = value_tol + SCREEN_SLACK * abs(value)
    if ks is _ORDERS and _none_by_runs(f, theta, value, threshold):
        return True
    shifts = _shifts(f.period, ks)
    shifted = f.values(theta + shifts)
    return bool((np.abs(shifted - value) > threshold).all())


MONOTONE_SLACK = 1e-5
"""Relative margin (to f's largest extremum, which bounds |f′|) by which the points
:func:`_none_by_runs` evaluates must clear the threshold: a hundred times what a run's
absorbed slivers (``sliver_rad``, 1e-7 rad) and merged cuts (``angle_rad``) can make f
dip inside it, far above the evaluations' rounding."""
_SHIFT_LISTS = {P: shifts.tolist() for P, shifts in _ALL_SHIFTS.items()}
""":data:`_ALL_SHIFTS` as floats, ascending (the orders descend)."""


def _none_by_runs(f: SupportPairFunction, theta: float, value: float, threshold: float) -> bool:
    """True when every shifted point θ + P/k (k = 2 … ``MAX_SYMMETRY_ORDER``) lies more than
    ``threshold`` + the slack above f(θ) = ``value`` (the lowest extremum), so that every
    order fails there, judged from a few evaluations: f is monotone on each run (its
    extrema are exact where every contact is point-like: closed forms), so on the
    shifted points inside one run it is least at the first or the last of them. False
    (undecided: the full evaluation decides) when one of those is not that far above, or
    when a curve contact makes the runs' ends bracketed roots. O(r log k) for r runs."""
    if len(f.hull.table.s0):
        return False
    P, shifts = f.period, _SHIFT_LISTS.get(f.period)
    if shifts is None:
        return False
    if KERNELS is not None:  # typed loops, the same decision (algrasp.compiled)
        return bool(KERNELS.none_by_runs(f, theta, value, threshold, _ALL_SHIFTS[P], MONOTONE_SLACK))
    cuts = sorted({(r.start - theta) % P for r in f.runs} | {0.0, P})  # run ends as offsets from θ
    picks: list[int] = []
    for a, b in zip(cuts[:-1], cuts[1:]):
        i, j = bisect.bisect_left(shifts, a), bisect.bisect_left(shifts, b)
        if j > i:
            picks += (i, j - 1)
    if not picks:
        return True
    guard = threshold + MONOTONE_SLACK * max(e.value for e in f.extrema)
    lows = f.values(theta + np.array([shifts[i] for i in picks]))
    return bool((lows - value > guard).all())


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


@functools.lru_cache(maxsize=8)
def symmetry_period(f: SupportPairFunction, value_tol: float) -> float:
    """:func:`tolerant_symmetry`, once per function and tolerance: the probes of a limit
    search (one part, many physics) share it. Keyed on the function object (identity)."""
    return tolerant_symmetry(f, value_tol)
