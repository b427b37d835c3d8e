"""Diameter d(θ) and radius r(θ) functions (conventions §3) and their exact extrema.

Both are sums of two support terms. With u(ψ) = (cos ψ, sin ψ) and ψ = π/2 − θ:

    d(θ) = h(ψ) + h(ψ + π),        r(θ) = ⟨c, u(ψ)⟩ + h(ψ + π),

h being the hull's support function. S¹ is split into *cells* at the Gauss-map
breakpoints of both terms; in a cell the two contact features F (at ψ) and G (at
ψ + π) are fixed and f(ψ) = ⟨c_F(ψ) − c_G(ψ + π), u⟩, f′(ψ) = ⟨c_F − c_G, u′⟩.

* Both features point-like (vertices, circular arcs, the centre of mass):
  f = ⟨Δ, u⟩ + R_F + R_G with Δ the difference of centres — f′ has the closed-form
  zeros ψ = atan2(Δ) + kπ, and the cell is a region of constant value exactly when
  the centres coincide (concentric arcs, an arc centred on the opposite vertex or on
  the centre of mass). This is decided from the geometry, not from samples.
* Otherwise (a curve piece is involved) f′ = 0 is Lemma 1's system: the chord is
  normal to both curves. Roots are isolated by sign changes of f′ on a grid no
  coarser than ``root_grid_rad`` and refined (all cells together, by a vectorised Dekker
  iteration) to machine precision.

The result is a cyclic list of monotone *runs* (sign of dd/dθ: +1, −1 or 0) whose
boundaries are the extrema, classified as in Appendix A.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Literal, NamedTuple

import numpy as np

from algrasp.compiled import GEOMETRY
from algrasp.geometry.angles import TWO_PI, wrap_from
from algrasp.geometry.bank import IntArray
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.hull import ConvexHull, unit
from algrasp.geometry.lazy import cached_property
from algrasp.geometry.tolerances import EPS_REL, ROUNDING_FINE, Tolerances

Kind = Literal["diameter", "radius"]
Equilibrium = Literal["stable", "unstable", "semistable", "semiunstable"]

_CLASSIFY: dict[tuple[int, int], tuple[str, Equilibrium]] = {
    (1, -1): ("max", "unstable"),
    (-1, 1): ("min", "stable"),
    (-1, 0): ("min", "semistable"),
    (0, 1): ("min", "semistable"),
    (1, 0): ("max", "semiunstable"),
    (0, -1): ("max", "semiunstable"),
}


class Run(NamedTuple):
    """θ-interval [start, end) (radians, lifted) on which the function has ``sign``.

    Named tuples here and for :class:`Extremum`: immutable like the frozen dataclasses
    they replace, at half the construction cost (a small part makes dozens of each)."""

    start: float
    end: float
    sign: int


class Extremum(NamedTuple):
    theta: float  # radians, wrapped to [0, period)
    value: float
    kind: str  # "min" | "max"
    equilibrium: Equilibrium


@dataclass(frozen=True, eq=False)
class SupportPairFunction:
    """d or r of one part: evaluation at any θ plus the exact monotone runs.

    Attributes:
        kind: "diameter" (period π) or "radius" (period 2π).
        hull: the part's exact hull.
        com: centre of mass (radius function only).
        runs: cyclic θ-runs over one full turn, sorted, covering [runs[0].start, +2π).
        extrema: extrema over one period, sorted by θ.
        constant_intervals: [start, end) θ-intervals of constant value over one period
            (end may exceed the period when the interval wraps).
    """

    kind: Kind
    hull: ConvexHull
    com: tuple[float, float]
    runs: tuple[Run, ...]
    extrema: tuple[Extremum, ...]
    constant_intervals: tuple[tuple[float, float], ...]

    @property
    def period(self) -> float:
        return np.pi if self.kind == "diameter" else TWO_PI

    @cached_property
    def kink_thetas(self) -> FloatArray:
        """θ (radians, lifted) of every Gauss-map breakpoint of both terms (where f′ may
        jump) and of every run start (the extrema); computed once, read-only."""
        # In plain floats, one array made (each θ the same difference numpy would take).
        bp = self.hull.table.breakpoint_list
        near = [np.pi / 2 - b for b in bp] if self.kind == "diameter" else []
        out = np.array([*near, *(1.5 * np.pi - b for b in bp), *(r.start for r in self.runs)], dtype=float)
        out.flags.writeable = False
        return out

    def __call__(self, theta: float) -> float:
        """Value at θ (radians): exact support-function evaluation, O(log n)."""
        psi = np.pi / 2 - theta
        u = unit(psi)
        far = self.hull.support(psi + np.pi)
        near = self.hull.support(psi) if self.kind == "diameter" else float(np.asarray(self.com) @ u)
        return float(near + far)


    def values(self, theta: FloatArray) -> FloatArray:
        """Values at an array of θ (radians), vectorised; O(m log n). The diameter of a
        hull of vertices only: compiled when built (:mod:`algrasp.compiled`), the same values."""
        theta = np.asarray(theta, dtype=float)
        if self.kind == "diameter" and GEOMETRY is not None and theta.ndim == 1 and self.hull.table.vertices_only:
            table = self.hull.table
            return GEOMETRY.width_values(table.breakpoint_list, table.center_list, theta)  # type: ignore[no-any-return]
        psi = np.pi / 2 - theta
        if self.kind == "diameter":  # both terms in one support pass
            h = self.hull.support_many(np.concatenate([psi, psi + np.pi]))
            return h[: len(psi)] + h[len(psi):]
        return np.asarray(unit(psi) @ np.asarray(self.com)) + self.hull.support_many(psi + np.pi)


def wrap(theta: float, period: float, tol: float) -> float:
    """θ mod period in [0, period), with values within ``tol`` of the period sent to 0."""
    x = theta % period
    return 0.0 if period - x <= tol else float(x)


Cell = tuple[int, int, float, float]
"""(near, far, ψ_a, ψ_b): a contact cell (:func:`contact_cells`)."""


@functools.lru_cache(maxsize=16)
def _cells(kind: Kind, hull: ConvexHull, angle_rad: float) -> tuple[Cell, ...]:
    """Cells (near, far, a, b) over one turn in ψ: the breakpoints of both terms merged
    (cuts closer than ``angle_rad`` are one), with the features at ψ and at ψ + π in
    between (near −1 for the radius: the centre of mass). O(n log n) for n features, in
    plain floats (a few per feature; numpy's per-call cost would dominate). Once per hull
    (identity), kind and tolerance: the runs and the dead-zone edges both read them.
    Compiled when built (:mod:`algrasp.compiled`), with the same cells."""
    bp = hull.table.breakpoint_list
    made = None if GEOMETRY is None else GEOMETRY.cells(bp, kind == "diameter", angle_rad)
    if made is not None:
        return made  # type: ignore[no-any-return]
    raw = [b - math.pi for b in bp]  # where the far feature changes; raw[0] is the least cut
    if kind == "diameter":
        raw += bp
    base = raw[0]
    cuts = [wrap_from(c, base) for c in raw]
    n = len(bp)
    order = sorted(range(len(cuts)), key=cuts.__getitem__)
    # Before the first cut: the features of the last cuts of each term (cyclically).
    far = next(k for k in reversed(order) if k < n)
    near = next((k - n for k in reversed(order) if k >= n), -1)
    edges: list[tuple[float, int, int]] = []  # (ψ, near, far) from each cell's start
    prev = -math.inf
    for k in order:
        c = cuts[k]
        if k < n:
            far = k
        else:
            near = k - n
        if c - prev > angle_rad:
            edges.append((c, near, far))
        else:  # within angle_rad of the cut before: the same cell start, features updated
            edges[-1] = (edges[-1][0], near, far)
        prev = c
    ends = [e[0] for e in edges[1:]] + [edges[0][0] + TWO_PI]
    return tuple((i, j, a, b) for (a, i, j), b in zip(edges, ends) if b - a > angle_rad)


def contact_cells(f: SupportPairFunction, tol: Tolerances) -> tuple[Cell, ...]:
    """The cells (near, far, ψ_a, ψ_b) of ``f`` over one turn in ψ (radians, lifted): on
    each, the contact features at ψ and ψ + π are fixed (near −1: the centre of mass)."""
    return _cells(f.kind, f.hull, tol.angle_rad)


def _grid(a: float, b: float, tol: Tolerances) -> FloatArray:
    """Sign-change grid of a cell: spacing ≤ root_grid_rad, at least 9 points."""
    return np.linspace(a, b, max(8, int(np.ceil((b - a) / tol.root_grid_rad))) + 1)


def _point_like_runs(F: tuple[float, float], G: tuple[float, float], a: float, b: float, size: float,
                     tol: Tolerances) -> list[Run]:
    """Closed form for features with centres F and G: f′ = ⟨Δ, u′(ψ)⟩ = |Δ| sin(atan2 Δ − ψ),
    Δ = F − G; constant iff Δ = 0."""
    dx, dy = F[0] - G[0], F[1] - G[1]
    if math.hypot(dx, dy) <= tol.concentric_rel * size:
        return [Run(a, b, 0)]
    phi = math.atan2(dy, dx)
    k0 = math.ceil((a - phi) / math.pi)
    edges = [a]
    for k in range(k0, k0 + 3):  # a cell is at most a turn wide: these cover its roots
        x = phi + k * math.pi
        if a < x < b:
            edges.append(x)
    edges.append(b)
    runs = []
    for x, y in zip(edges[:-1], edges[1:]):
        m = 0.5 * (x + y)
        sign = -dx * math.sin(m) + dy * math.cos(m)
        if y - x > tol.angle_rad:
            runs.append(Run(x, y, (sign > 0) - (sign < 0)))
    return runs


@dataclass(frozen=True)
class _Derivative:
    """f′(ψ) = ⟨c_F(ψ) − c_G(ψ + π), u′(ψ)⟩ for many (F, G, ψ) at once.

    ``near``/``far`` index the hull's features; near index −1 is the centre of mass.
    Every call is one vectorised pass over all features (support points by Newton on
    the exact curves, :class:`~algrasp.geometry.bank.FeatureTable`).
    """

    hull: ConvexHull
    com: FloatArray

    def __call__(self, near: IntArray, far: IntArray, psi: FloatArray) -> FloatArray:
        # One pass for both ends of every chord (the centre of mass needs none).
        own = near >= 0
        pts = self.hull.table.points(np.concatenate([far, near[own]]), np.concatenate([psi + np.pi, psi[own]]))
        chord = -pts[: len(psi)]
        chord[own] += pts[len(psi):]
        chord[~own] += self.com
        return np.asarray(-chord[:, 0] * np.sin(psi) + chord[:, 1] * np.cos(psi))


def _refine(f: _Derivative, near: IntArray, far: IntArray, lo: FloatArray, hi: FloatArray,
            flo: FloatArray, fhi: FloatArray) -> FloatArray:
    """Roots of f′ in the brackets [lo, hi] (opposite signs at the ends), all at once.

    Dekker's method, vectorised: each pass takes the secant step through the last two
    iterates when it lands inside the bracket (superlinear at a simple root), else the
    bracket's regula-falsi point, else its midpoint, and shrinks the bracket. Stops when
    the bracket or the last step is below rounding (1e-15 rad) or f′ = 0; ≤ 100 passes,
    each one evaluation for all unfinished roots.
    """
    lo, hi, flo, fhi = lo.copy(), hi.copy(), flo.copy(), fhi.copy()
    first = np.abs(flo) < np.abs(fhi)  # the better end is the current iterate
    x, fx = np.where(first, lo, hi), np.where(first, flo, fhi)
    xp, fp = np.where(first, hi, lo), np.where(first, fhi, flo)
    active = np.ones(lo.shape, dtype=bool)
    for _ in range(100):
        a = np.nonzero(active)[0]
        if not a.size:
            break
        xn = _next_point(lo[a], hi[a], flo[a], fhi[a], x[a], fx[a], xp[a], fp[a])
        fn = f(near[a], far[a], xn)
        step = np.abs(xn - x[a])
        xp[a], fp[a], x[a], fx[a] = x[a], fx[a], xn, fn
        left = fn * fhi[a] > 0.0  # the root lies left of xn: xn is the new right end
        hi[a[left]], fhi[a[left]] = xn[left], fn[left]
        lo[a[~left]], flo[a[~left]] = xn[~left], fn[~left]
        tiny = ROUNDING_FINE + EPS_REL * np.abs(xn)
        active[a[(fn == 0.0) | (step <= tiny) | (hi[a] - lo[a] <= tiny)]] = False
    return x


def _next_point(lo: FloatArray, hi: FloatArray, flo: FloatArray, fhi: FloatArray,
                x: FloatArray, fx: FloatArray, xp: FloatArray, fp: FloatArray) -> FloatArray:
    """Secant point if strictly inside the bracket, else regula falsi, else the midpoint."""
    with np.errstate(divide="ignore", invalid="ignore"):
        secant = x - fx * (x - xp) / (fx - fp)
        falsi = (lo * fhi - hi * flo) / (fhi - flo)
    falsi = np.where((falsi > lo) & (falsi < hi), falsi, 0.5 * (lo + hi))
    return np.where((secant > lo) & (secant < hi), secant, falsi)


def _curve_cell_runs(f: _Derivative, cells: list[Cell], tol: Tolerances) -> list[list[Run]]:
    """Monotone ψ-runs of every cell with a curve piece: f′ on each cell's grid (one
    batch), sign changes refined together (:func:`_refine`), run signs read at the run
    midpoints (one batch). O(g) for g grid points in all, independent of the cell count."""
    grids = [_grid(a, b, tol) for _, _, a, b in cells]
    cell = np.repeat(np.arange(len(cells)), [len(g) for g in grids])
    cell_near = np.array([c[0] for c in cells], dtype=np.intp)
    cell_far = np.array([c[1] for c in cells], dtype=np.intp)
    near, far = cell_near[cell], cell_far[cell]
    psi = np.concatenate(grids)
    vals = f(near, far, psi)
    change = np.nonzero((vals[:-1] * vals[1:] < 0.0) & (cell[:-1] == cell[1:]))[0]
    roots = _refine(f, near[change], far[change], psi[change], psi[change + 1], vals[change], vals[change + 1])
    edges: list[list[float]] = [[a] for _, _, a, _ in cells]
    for k, r in zip(cell[change].tolist(), roots.tolist()):
        edges[k].append(r)
    for k, (_, _, _, b) in enumerate(cells):
        edges[k].append(b)
    spans = [(k, x, y) for k, e in enumerate(edges) for x, y in zip(e[:-1], e[1:])]
    ks = np.array([k for k, _, _ in spans], dtype=np.intp)
    mids = np.array([0.5 * (x + y) for _, x, y in spans])
    signs = np.copysign(1.0, f(cell_near[ks], cell_far[ks], mids))
    out: list[list[Run]] = [[] for _ in cells]
    for (k, x, y), sgn in zip(spans, signs.tolist()):
        if y - x > tol.angle_rad:
            out[k].append(Run(x, y, int(sgn)))
    return out


def _merge(runs: list[Run], sliver: float) -> list[Run]:
    """Join neighbours of equal sign; rounding slivers join their left neighbour."""
    out: list[Run] = []
    for r in runs:
        if out and r.end - r.start <= sliver:
            out[-1] = Run(out[-1].start, r.end, out[-1].sign)
            continue
        if out and out[-1].sign == r.sign:
            out[-1] = Run(out[-1].start, r.end, r.sign)
        else:
            out.append(r)
    if len(out) > 1 and out[0].sign == out[-1].sign:
        first = out.pop(0)
        out[-1] = Run(out[-1].start, first.end + TWO_PI, first.sign)
    return out


def theta_runs(kind: Kind, hull: ConvexHull, com: tuple[float, float], size: float, tol: Tolerances) -> list[Run]:
    """Cyclic θ-runs of d or r over one turn. O(c + g) array work for c cells and g
    grid points in all (the cells with curves are handled in one batch)."""
    cells = _cells(kind, hull, tol.angle_rad)
    centers = [f.center if f.point_like else None for f in hull.features]
    centers.append(com)  # near index −1: the centre of mass, a point
    if GEOMETRY is not None and not len(hull.table.s0):  # all point-like: compiled, the same runs
        return GEOMETRY.point_runs(cells, centers, tol.concentric_rel * size, tol.angle_rad,  # type: ignore[no-any-return]
                                   tol.sliver_rad, Run)
    curved = [c for c in cells if centers[c[0]] is None or centers[c[1]] is None]
    curve_runs = iter(_curve_cell_runs(_Derivative(hull, np.asarray(com, dtype=float)), curved, tol) if curved else [])
    psi_runs: list[Run] = []
    for i, j, a, b in cells:
        ci, cj = centers[i], centers[j]
        if ci is not None and cj is not None:
            psi_runs.extend(_point_like_runs(ci, cj, a, b, size, tol))
        else:
            psi_runs.extend(next(curve_runs))
    merged = _merge(psi_runs, tol.sliver_rad)
    # θ = π/2 − ψ reverses the order and the sign of the derivative.
    return [Run(np.pi / 2 - r.end, np.pi / 2 - r.start, -r.sign) for r in reversed(merged)]


_LABELS = [[_CLASSIFY.get((p, q)) for q in (-1, 0, 1)] for p in (-1, 0, 1)]
""":data:`_CLASSIFY` as a table by (sign before + 1, sign after + 1), for the kernel."""


def _extremum_keys(runs: list[Run], period: float, angle_rad: float) -> list[tuple[float, float, tuple[str, Equilibrium]]]:
    """(start, θ wrapped into the period, label) of each extremum between the cyclic
    ``runs``, once per period (the diameter's turn holds two copies): by θ rounded to 9
    digits, the first kept. O(n); compiled when built (:mod:`algrasp.compiled`)."""
    if GEOMETRY is not None:
        return GEOMETRY.extremum_keys(runs, period, angle_rad, _LABELS)  # type: ignore[no-any-return]
    labelled: dict[float, tuple[float, float, tuple[str, Equilibrium]]] = {}
    for prev, nxt in zip([runs[-1], *runs[:-1]], runs):
        label = _CLASSIFY.get((prev.sign, nxt.sign))
        if label is not None:
            key = wrap(nxt.start, period, angle_rad)
            labelled.setdefault(round(key, 9), (nxt.start, key, label))
    return list(labelled.values())


def analyse(kind: Kind, hull: ConvexHull, com: tuple[float, float], size: float, tol: Tolerances) -> SupportPairFunction:
    """Exact runs, extrema and constant regions of the diameter or radius function."""
    runs = theta_runs(kind, hull, com, size, tol)
    shell = SupportPairFunction(kind, hull, com, tuple(runs), (), ())
    period = shell.period
    found = _extremum_keys(runs, period, tol.angle_rad)
    values = shell.values(np.array([t for t, _, _ in found])).tolist() if found else []
    extrema = [Extremum(key, value, label[0], label[1]) for (_, key, label), value in zip(found, values)]
    const = {round(wrap(r.start, period, tol.angle_rad), 9): (wrap(r.start, period, tol.angle_rad),
                                                             wrap(r.start, period, tol.angle_rad) + r.end - r.start)
             for r in runs if r.sign == 0}
    if len(runs) == 1 and runs[0].sign == 0:
        const = {0.0: (0.0, period)}
    return SupportPairFunction(kind, hull, com, tuple(runs),
                               tuple(sorted(extrema, key=lambda e: e.theta)),
                               tuple(sorted(const.values())))
