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
  coarser than ``root_grid_rad`` and refined by Brent's method to machine precision.

The result is a cyclic list of monotone *runs* (sign of dd/dθ: +1, −1 or 0) whose
boundaries are the extrema, classified as in Appendix A.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from scipy.optimize import brentq

from algrasp.curves import FloatArray
from algrasp.hull import TWO_PI, ConvexHull, HullFeature, unit
from algrasp.tolerances import Tolerances

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


@dataclass(frozen=True)
class Run:
    """θ-interval [start, end) (radians, lifted) on which the function has ``sign``."""

    start: float
    end: float
    sign: int


@dataclass(frozen=True)
class Extremum:
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

    def __call__(self, theta: float) -> float:
        """Value at θ (radians): exact support-function evaluation, O(log n)."""
        psi = np.pi / 2 - theta
        u = unit(psi)
        far = self.hull.support(psi + np.pi)
        near = self.hull.support(psi) if self.kind == "diameter" else float(np.asarray(self.com) @ u)
        return float(near + far)


    def values(self, theta: FloatArray) -> FloatArray:
        """Values at an array of θ (radians), vectorised; O(m log n)."""
        psi = np.pi / 2 - np.asarray(theta, dtype=float)
        far = self.hull.support_many(psi + np.pi)
        if self.kind == "diameter":
            return self.hull.support_many(psi) + far
        return np.asarray(unit(psi) @ np.asarray(self.com)) + far


def wrap(theta: float, period: float, tol: float) -> float:
    """θ mod period in [0, period), with values within ``tol`` of the period sent to 0."""
    x = theta % period
    return 0.0 if period - x <= tol else float(x)


def _cells(kind: Kind, hull: ConvexHull, tol: Tolerances) -> list[tuple[float, float]]:
    """Cells [a, b] in ψ over one turn: breakpoints of both terms merged."""
    far = hull.breakpoints - np.pi
    cuts = far if kind == "radius" else np.concatenate([hull.breakpoints, far])
    base = float(cuts.min())
    cuts = np.sort(base + (cuts - base) % TWO_PI)
    keep = np.concatenate([[True], np.diff(cuts) > tol.angle_rad])
    cuts = cuts[keep]
    edges = np.append(cuts, cuts[0] + TWO_PI)
    return [(float(a), float(b)) for a, b in zip(edges[:-1], edges[1:]) if b - a > tol.angle_rad]


def _derivative(F: HullFeature, G: HullFeature, psi: FloatArray | np.float64) -> FloatArray:
    """f′(ψ) = ⟨c_F(ψ) − c_G(ψ + π), u′(ψ)⟩, vectorised."""
    chord = F.support_point(psi) - G.support_point(psi + np.pi)
    return -chord[..., 0] * np.sin(psi) + chord[..., 1] * np.cos(psi)


def _grid(a: float, b: float, tol: Tolerances) -> FloatArray:
    """Sign-change grid of a cell: spacing ≤ root_grid_rad, at least 9 points."""
    return np.linspace(a, b, max(8, int(np.ceil((b - a) / tol.root_grid_rad))) + 1)


def _cell_roots(F: HullFeature, G: HullFeature, grid: FloatArray, vals: FloatArray) -> list[float]:
    """Zeros of f′ inside a cell with a curve piece: sign changes of f′ on the grid,
    each refined by Brent's method to machine precision."""
    roots = []
    for i in range(len(grid) - 1):
        if vals[i] * vals[i + 1] < 0.0:
            def fprime(x: float) -> float:
                return float(_derivative(F, G, np.float64(x)))
            roots.append(float(brentq(fprime, grid[i], grid[i + 1], xtol=1e-15, rtol=1e-15)))
    return roots


def _point_like_runs(F: HullFeature, G: HullFeature, a: float, b: float, size: float, tol: Tolerances) -> list[Run]:
    """Closed form: f′ = ⟨Δ, u′(ψ)⟩ = |Δ| sin(atan2 Δ − ψ); constant iff Δ = 0."""
    dx, dy = F.center[0] - G.center[0], F.center[1] - G.center[1]
    if math.hypot(dx, dy) <= tol.concentric_rel * size:
        return [Run(a, b, 0)]
    phi = math.atan2(dy, dx)
    k0 = math.ceil((a - phi) / math.pi)
    roots = [phi + k * math.pi for k in range(k0, k0 + 3) if a < phi + k * math.pi < b]
    edges = [a, *roots, b]
    runs = []
    for x, y in zip(edges[:-1], edges[1:]):
        m = 0.5 * (x + y)
        sign = -dx * math.sin(m) + dy * math.cos(m)
        if y - x > tol.angle_rad:
            runs.append(Run(x, y, (sign > 0) - (sign < 0)))
    return runs


def _curve_runs(F: HullFeature, G: HullFeature, grid: FloatArray, vals: FloatArray, tol: Tolerances) -> list[Run]:
    """Monotone ψ-runs of a cell with a curve piece, from f′ sampled on its grid."""
    a, b = float(grid[0]), float(grid[-1])
    edges = [a, *_cell_roots(F, G, grid, vals), b]
    signs = [math.copysign(1.0, float(_derivative(F, G, np.float64(0.5 * (x + y))))) if y > x else 0.0
             for x, y in zip(edges[:-1], edges[1:])]
    return [Run(x, y, int(s)) for x, y, s in zip(edges[:-1], edges[1:], signs) if y - x > tol.angle_rad]


def _batched_derivatives(pairs: list[tuple[HullFeature, HullFeature, FloatArray]]) -> list[FloatArray]:
    """f′ on every curve cell's grid, evaluating each feature's support points in one
    vectorised call (per-call overhead, not arithmetic, dominates small grids)."""
    wanted: dict[int, list[FloatArray]] = {}
    feats: dict[int, HullFeature] = {}
    for F, G, grid in pairs:
        for feat, psi in ((F, grid), (G, grid + np.pi)):
            feats[id(feat)] = feat
            wanted.setdefault(id(feat), []).append(psi)
    points: dict[int, list[FloatArray]] = {}
    for key, chunks in wanted.items():
        pts = feats[key].support_point(np.concatenate(chunks))
        points[key] = np.split(pts, np.cumsum([len(c) for c in chunks])[:-1])
    taken = {key: 0 for key in wanted}
    out = []
    for F, G, grid in pairs:
        cf = points[id(F)][taken[id(F)]]
        taken[id(F)] += 1
        cg = points[id(G)][taken[id(G)]]
        taken[id(G)] += 1
        chord = cf - cg
        out.append(-chord[:, 0] * np.sin(grid) + chord[:, 1] * np.cos(grid))
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
    """Cyclic θ-runs of d or r over one turn. O(c · g) for c cells, g grid points/cell."""
    psi_runs: list[Run] = []
    cells = _cells(kind, hull, tol)
    mids = np.array([(a + b) / 2 for a, b in cells])
    base = hull.features[0].psi0
    near = np.searchsorted(hull.breakpoints, base + (mids - base) % TWO_PI, side="right") - 1
    far = np.searchsorted(hull.breakpoints, base + (mids + np.pi - base) % TWO_PI, side="right") - 1
    com_feature = HullFeature("point", -np.inf, np.inf, center=com)
    pairs = [(com_feature if kind == "radius" else hull.features[max(i, 0)], hull.features[max(j, 0)])
             for i, j in zip(near.tolist(), far.tolist())]
    curved = [(F, G, _grid(a, b, tol)) for (F, G), (a, b) in zip(pairs, cells) if not (F.point_like and G.point_like)]
    curve_vals = iter(_batched_derivatives(curved))
    curved_iter = iter(curved)
    for (F, G), (a, b) in zip(pairs, cells):
        if F.point_like and G.point_like:
            psi_runs.extend(_point_like_runs(F, G, a, b, size, tol))
        else:
            _, _, grid = next(curved_iter)
            psi_runs.extend(_curve_runs(F, G, grid, next(curve_vals), tol))
    merged = _merge(psi_runs, tol.sliver_rad)
    # θ = π/2 − ψ reverses the order and the sign of the derivative.
    return [Run(np.pi / 2 - r.end, np.pi / 2 - r.start, -r.sign) for r in reversed(merged)]


def analyse(kind: Kind, hull: ConvexHull, com: tuple[float, float], size: float, tol: Tolerances) -> SupportPairFunction:
    """Exact runs, extrema and constant regions of the diameter or radius function."""
    runs = theta_runs(kind, hull, com, size, tol)
    shell = SupportPairFunction(kind, hull, com, tuple(runs), (), ())
    period = shell.period
    labelled = [(nxt.start, _CLASSIFY[(prev.sign, nxt.sign)]) for prev, nxt in zip([runs[-1], *runs[:-1]], runs)
                if (prev.sign, nxt.sign) in _CLASSIFY]
    values = shell.values(np.array([t for t, _ in labelled])) if labelled else np.zeros(0)
    extrema: dict[float, Extremum] = {}
    for (theta, label), value in zip(labelled, values.tolist()):
        key = wrap(theta, period, tol.angle_rad)
        extrema.setdefault(round(key, 9), Extremum(key, value, label[0], label[1]))
    const = {round(wrap(r.start, period, tol.angle_rad), 9): (wrap(r.start, period, tol.angle_rad),
                                                             wrap(r.start, period, tol.angle_rad) + r.end - r.start)
             for r in runs if r.sign == 0}
    if len(runs) == 1 and runs[0].sign == 0:
        const = {0.0: (0.0, period)}
    return SupportPairFunction(kind, hull, com, tuple(runs),
                               tuple(sorted(extrema.values(), key=lambda e: e.theta)),
                               tuple(sorted(const.values())))
