"""Exact dead-zone edges: where the slope of d or r crosses a threshold, cell by cell.

On a Gauss-map cell whose two contacts are point-like (vertices, circular arcs, the
centre of mass) the function is a sinusoid: with ψ = π/2 − θ, Δ = c_F − c_G = ρ·u(φ₀) the
difference of the contacts' centres and R = R_F + R_G their radii,

    f(θ) = ρ cos(ψ − φ₀) + R,        f′(θ) = ρ sin(ψ − φ₀)   (part units per radian).

So every threshold of conventions §7 is one equation sin(x − δ) = k in x = ψ − φ₀:

* |f′| = t (the stalls, the slope tolerance σ, s_lo − σ): δ = 0, k = ±t/ρ;
* |f′| = μ·f + c (the rest bound with jaw friction μ): ρ sin x ∓ μρ cos x = ±(μR + c),
  i.e. δ = ±atan μ, k = ±(μR + c)/(ρ√(1 + μ²)).

Each has two roots per turn, found in closed form for all cells at once. Cells with a
curve contact (Bezier, NURBS, ellipse pieces) have no closed form: they get a grid no
coarser than ``grid_rad`` instead. O(m·E) for m cells and E equations.

>>> from algrasp.geometry.functions import analyse
>>> from algrasp.geometry.part import load_part
>>> from algrasp.geometry.tolerances import DEFAULT_TOLERANCES as TOL
>>> from algrasp.testing import shapes
>>> sq = load_part(shapes.rectangle(2.0, 2.0))
>>> d = analyse("diameter", sq.hull, sq.center_of_mass, sq.size, TOL)
>>> theta, _ = crossings(d, (0.5,), None, TOL, 2e-3)
>>> bool(np.allclose(np.abs(d.values(theta + 1e-7) - d.values(theta - 1e-7)) / 2e-7, 0.5))
True
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from algrasp.compiled import KERNELS
from algrasp.geometry.angles import TWO_PI
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.functions import SupportPairFunction, contact_cells
from algrasp.geometry.tolerances import Tolerances

CURVE_GRID_RAD = 8e-3
"""Sample spacing on curve pieces (0.46°) where crossings are bracketed: a dead zone or a
gap between two narrower than this where |f′| only touches a threshold can be missed."""
SECANT_STEPS = 8
"""Illinois steps per bracket: an 8 mrad bracket is placed far below the edges' guard
(``EDGE_RAD``, 2e-4 rad), which absorbs what is left."""
INSIDE_FRAC = 1e-9
"""Relative offset of a curve cell's end samples inside it (its ends are kinks)."""


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


def _equations(rho: FloatArray, R: FloatArray, slopes: Sequence[float], jaw: tuple[float, float] | None,
               levels: Sequence[float] = ()) -> tuple[FloatArray, FloatArray]:
    """(δ, k) of every threshold equation sin(x − δ) = k, shapes (1, E) and (m, E); a
    level L of f itself is ρ cos x = L − R, i.e. δ = −π/2, k = (L − R)/ρ. One (m, E)
    buffer, filled column block by column block."""
    S, n_levels = 2 * len(slopes), len(levels)
    delta = [0.0] * S + [-np.pi / 2] * n_levels
    k = np.empty((len(rho), S + n_levels + (0 if jaw is None else 2)))
    rho_col = rho[:, None]
    np.divide(np.array([sign * t for t in slopes for sign in (1.0, -1.0)])[None, :], rho_col, out=k[:, :S])
    if levels:
        np.divide(np.array(levels)[None, :] - R[:, None], rho_col, out=k[:, S:S + n_levels])
    if jaw is not None:
        mu, c = jaw
        beta, A = float(np.arctan(mu)), rho * float(np.hypot(1.0, mu))
        delta += [beta, -beta]
        np.divide(mu * R + c, A, out=k[:, -2])
        np.negative(k[:, -2], out=k[:, -1])  # −(x/A) is (−x)/A exactly: rounding is symmetric
    return np.array(delta)[None, :], k


@dataclass(frozen=True, eq=False)
class _Contacts:
    """The point-like contact cells that can cross a threshold (concentric contacts, where
    f is constant, cannot): per cell the distance ρ and direction φ0 between the two
    contacts' centres, the sum R of their radii, and the cell's normal range [a, b) (ψ,
    radians). What :func:`_point_roots` reads that no threshold changes."""

    rho: FloatArray
    R: FloatArray
    phi0: FloatArray
    a: FloatArray
    b: FloatArray


def _contacts(cells: np.ndarray, centres: FloatArray, radii: FloatArray) -> _Contacts:
    """:class:`_Contacts` of the point-like cells (rows: near, far, ψ_a, ψ_b)."""
    near, far = cells[:, 0].astype(np.intp), cells[:, 1].astype(np.intp)
    delta_xy = centres[near] - centres[far]
    rho = np.hypot(delta_xy[:, 0], delta_xy[:, 1])
    R = radii[near] + radii[far]
    live = rho > 0.0
    if live.all():  # no concentric contacts (a polygon's cells): nothing to leave out
        return _Contacts(rho, R, np.arctan2(delta_xy[:, 1], delta_xy[:, 0]), cells[:, 2], cells[:, 3])
    return _Contacts(rho[live], R[live], np.arctan2(delta_xy[live, 1], delta_xy[live, 0]), cells[live, 2], cells[live, 3])


def _point_roots(c: _Contacts, slopes: Sequence[float], jaw: tuple[float, float] | None,
                 levels: Sequence[float]) -> FloatArray:
    """θ of every threshold crossing on the point-like cells."""
    delta, k = _equations(c.rho, c.R, slopes, jaw, levels)
    real = np.abs(k) <= 1.0
    s = np.arcsin(np.minimum(np.maximum(k, -1.0), 1.0))  # np.clip's values, without its dispatch
    x = np.empty((*s.shape, 2))  # (m, E, 2)
    x[..., 0], x[..., 1] = delta + s, delta + np.pi - s
    psi = c.phi0[:, None, None] + x
    psi = c.a[:, None, None] + np.mod(psi - c.a[:, None, None], TWO_PI)  # the root in [a, a + 2π)
    keep = real[:, :, None] & (psi < c.b[:, None, None])
    return np.asarray(np.pi / 2 - psi[keep])


def _curve_grid(cells: np.ndarray, grid_rad: float) -> tuple[FloatArray, np.ndarray]:
    """θ of a grid no coarser than ``grid_rad`` over each curve cell, its ends a hair
    inside (they are breakpoints, where f′ jumps), and the cell of each point."""
    if not len(cells):
        return np.zeros(0), np.zeros(0, dtype=np.intp)
    n = np.maximum(2, np.ceil((cells[:, 3] - cells[:, 2]) / grid_rad).astype(np.intp) + 1)
    frac = np.concatenate([np.linspace(INSIDE_FRAC, 1.0 - INSIDE_FRAC, k) for k in n.tolist()])
    a = np.repeat(cells[:, 2], n)
    psi = a + frac * np.repeat(cells[:, 3] - cells[:, 2], n)
    return np.asarray(np.pi / 2 - psi), np.repeat(np.arange(len(cells)), n)


def _threshold_gaps(theta: FloatArray, f: SupportPairFunction, slopes_at: Sequence[float],
                    jaw: tuple[float, float] | None, levels: Sequence[float]) -> FloatArray:
    """|f′| − threshold (and f − level) at each θ for every threshold, shape (E, m)."""
    return _gaps(*slopes(f, theta), slopes_at, jaw, levels)


def _gaps(g: FloatArray, v: FloatArray, slopes_at: Sequence[float], jaw: tuple[float, float] | None,
          levels: Sequence[float]) -> FloatArray:
    """:func:`_threshold_gaps` from f′ and f already evaluated."""
    a = np.abs(g)
    rows = [a - t for t in slopes_at]
    if jaw is not None:
        rows.append(a - (jaw[0] * v + jaw[1]))
    rows += [v - L for L in levels]
    return np.stack(rows)


def _curve_roots(f: SupportPairFunction, grid: _Grid, slopes_at: Sequence[float],
                 jaw: tuple[float, float] | None, levels: Sequence[float]) -> FloatArray:
    """Threshold crossings between consecutive samples ``theta`` of the same curve cell,
    bracketed by a sign change and placed by ``SECANT_STEPS`` Illinois steps (all at once)."""
    theta, cell = grid.theta, grid.cell
    h = _gaps(grid.slope, grid.value, slopes_at, jaw, levels)
    change = (np.sign(h[:, :-1]) != np.sign(h[:, 1:])) & (cell[:-1] == cell[1:])[None, :]
    row, col = np.nonzero(change)
    if not len(row):
        return np.zeros(0)
    lo, hi, h_lo, h_hi = theta[col], theta[col + 1], h[row, col], h[row, col + 1]
    x = hi
    for _ in range(SECANT_STEPS):  # Illinois regula falsi: superlinear, never leaves the bracket
        x = np.clip(hi - h_hi * (hi - lo) / np.where(h_hi != h_lo, h_hi - h_lo, 1.0), np.minimum(lo, hi), np.maximum(lo, hi))
        h_x = _threshold_gaps(x, f, slopes_at, jaw, levels)[row, np.arange(len(row))]
        flip = np.sign(h_x) != np.sign(h_hi)
        lo, h_lo = np.where(flip, hi, lo), np.where(flip, h_hi, 0.5 * h_lo)
        hi, h_hi = x, h_x
    return np.asarray(x)


def point_contacts(f: SupportPairFunction, tol: Tolerances) -> _Contacts | None:
    """The contact cells :func:`crossings` solves in closed form when they are all of
    f's cells (no curve contact: no grid, so every crossing is a closed-form root), else
    None. O(1) after the first call per function."""
    grid = _grid(f, tol, CURVE_GRID_RAD)
    return None if len(grid.theta) else grid.contacts


def crossings(f: SupportPairFunction, slopes: Sequence[float], jaw: tuple[float, float] | None,
              tol: Tolerances, grid_rad: float, levels: Sequence[float] = ()) -> tuple[FloatArray, FloatArray]:
    """θ (radians, lifted; fold them with mod) where |f′| crosses each of ``slopes`` or,
    with ``jaw = (μ, c)``, μ·f + c; and a grid of ``grid_rad`` on the cells with a curve
    contact, whose crossings are bracketed on it and placed by regula falsi; and where f
    crosses each of ``levels`` (a basin's rim). Thresholds ≤ 0 are skipped (|f′| ≥ 0
    crosses nothing below 0)."""
    grid = _grid(f, tol, grid_rad)
    positive = tuple(t for t in slopes if t > 0.0)
    exact = (_point_roots if KERNELS is None else KERNELS.point_roots)(grid.contacts, positive, jaw, levels)  # algrasp.compiled
    if not len(grid.theta):
        return exact, grid.theta
    return np.concatenate([exact, _curve_roots(f, grid, positive, jaw, levels)]), grid.theta


@dataclass(frozen=True, eq=False)
class _Grid:
    """What :func:`crossings` reads of f that no threshold changes: the point-like contact
    cells' geometry (:class:`_Contacts`) and, on the curve cells, the grid θ, its cells
    and f′ and f there. Read-only arrays."""

    contacts: _Contacts
    theta: FloatArray
    cell: np.ndarray
    slope: FloatArray
    value: FloatArray


_NO_RADIUS = np.zeros(1)
"""The centre of mass's radius (a point), the row the radii table gains."""
_NO_GRID, _NO_CELLS = np.zeros(0), np.zeros(0, dtype=np.intp)
"""The empty grid of a hull without curve features (read-only, shared)."""
_NO_GRID.setflags(write=False)
_NO_RADIUS.setflags(write=False)
_NO_CELLS.setflags(write=False)


@lru_cache(maxsize=8)
def _grid(f: SupportPairFunction, tol: Tolerances, grid_rad: float) -> _Grid:
    """:class:`_Grid` once per function (identity), tolerances and spacing: a limit
    search's probes and a basin's rims ask again with other thresholds only."""
    table = f.hull.table
    if not len(table.s0) and KERNELS is not None:  # one call, the same arrays (algrasp.compiled)
        out = _Grid(_Contacts(*KERNELS.contacts(contact_cells(f, tol), table.centers, table.radii, f.com)),
                    _NO_GRID, _NO_CELLS, _NO_GRID, _NO_GRID)
    else:
        out = _grid_of(f, tol, grid_rad)
    c = out.contacts
    for a in (c.rho, c.R, c.phi0, c.a, c.b, out.theta, out.cell, out.slope, out.value):
        if a.flags.writeable:  # (the shared empty grid already is not)
            a.setflags(write=False)
    return out


def _grid_of(f: SupportPairFunction, tol: Tolerances, grid_rad: float) -> _Grid:
    """:class:`_Grid` in numpy: the contacts' arrays, and the grid on curve cells."""
    table = f.hull.table
    # Row −1 of the centre table is the centre of mass (the radius's near contact).
    centres = np.concatenate([table.centers, np.array([f.com], dtype=float)])  # np.vstack's, without its wrapper
    radii = np.concatenate([table.radii, _NO_RADIUS])
    cells = np.array(contact_cells(f, tol), dtype=float).reshape(-1, 4)
    if not len(table.s0):  # no curve feature (polygons, circular arcs): no grid at all
        out = _Grid(_contacts(cells, centres, radii), _NO_GRID, _NO_CELLS, _NO_GRID, _NO_GRID)
    else:
        curve = np.array([not ft.point_like for ft in f.hull.features] + [False])
        near, far = cells[:, 0].astype(np.intp), cells[:, 1].astype(np.intp)
        curved = curve[near] | curve[far]
        theta, cell = _curve_grid(cells[curved], grid_rad)
        slope, value = slopes(f, theta) if len(theta) else (np.zeros(0), np.zeros(0))
        out = _Grid(_contacts(cells[~curved], centres, radii), theta, cell, slope, value)
    return out
