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

import numpy as np

from algrasp.geometry.angles import TWO_PI
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.functions import SupportPairFunction, contact_cells
from algrasp.geometry.tolerances import Tolerances


def _equations(rho: FloatArray, R: FloatArray, slopes: Sequence[float],
               jaw: tuple[float, float] | None) -> tuple[FloatArray, FloatArray]:
    """(δ, k) of every threshold equation sin(x − δ) = k, shapes (m, E)."""
    delta = [np.zeros_like(rho) for _ in range(2 * len(slopes))]
    k = [sign * t / rho for t in slopes for sign in (1.0, -1.0)]
    if jaw is not None:
        mu, c = jaw
        beta, A = float(np.arctan(mu)), rho * float(np.hypot(1.0, mu))
        delta += [np.full_like(rho, beta), np.full_like(rho, -beta)]
        k += [(mu * R + c) / A, -(mu * R + c) / A]
    return np.stack(delta, axis=1), np.stack(k, axis=1)


def _point_roots(cells: np.ndarray, centres: FloatArray, radii: FloatArray, slopes: Sequence[float],
                 jaw: tuple[float, float] | None) -> FloatArray:
    """θ of every threshold crossing on the point-like cells (rows: near, far, ψ_a, ψ_b)."""
    near, far = cells[:, 0].astype(np.intp), cells[:, 1].astype(np.intp)
    delta_xy = centres[near] - centres[far]
    rho = np.hypot(delta_xy[:, 0], delta_xy[:, 1])
    R = radii[near] + radii[far]
    live = rho > 0.0  # concentric contacts: f is constant, its slope crosses nothing
    rho, R, phi0, a, b = rho[live], R[live], np.arctan2(delta_xy[live, 1], delta_xy[live, 0]), cells[live, 2], cells[live, 3]
    delta, k = _equations(rho, R, slopes, jaw)
    real = np.abs(k) <= 1.0
    s = np.arcsin(np.clip(k, -1.0, 1.0))
    x = np.stack([delta + s, delta + np.pi - s], axis=2)  # (m, E, 2)
    psi = phi0[:, None, None] + x
    psi = a[:, None, None] + np.mod(psi - a[:, None, None], TWO_PI)  # the root in [a, a + 2π)
    keep = real[:, :, None] & (psi < b[:, None, None])
    return np.asarray(np.pi / 2 - psi[keep])


def _curve_grid(cells: np.ndarray, grid_rad: float) -> FloatArray:
    """θ of a grid no coarser than ``grid_rad`` over each curve cell (ends included)."""
    if not len(cells):
        return np.zeros(0)
    n = np.maximum(2, np.ceil((cells[:, 3] - cells[:, 2]) / grid_rad).astype(np.intp) + 1)
    frac = np.concatenate([np.linspace(0.0, 1.0, k) for k in n.tolist()])
    a = np.repeat(cells[:, 2], n)
    return np.asarray(np.pi / 2 - (a + frac * np.repeat(cells[:, 3] - cells[:, 2], n)))


def crossings(f: SupportPairFunction, slopes: Sequence[float], jaw: tuple[float, float] | None,
              tol: Tolerances, grid_rad: float) -> tuple[FloatArray, FloatArray]:
    """θ (radians, lifted; fold them with mod) where |f′| crosses each of ``slopes`` or,
    with ``jaw = (μ, c)``, μ·f + c; and a grid of ``grid_rad`` on the cells with a curve
    contact. Thresholds ≤ 0 are skipped (|f′| ≥ 0 crosses nothing below 0)."""
    table = f.hull.table
    # Row −1 of the centre table is the centre of mass (the radius's near contact).
    centres = np.vstack([table.centers, np.asarray(f.com, dtype=float)[None, :]])
    radii = np.append(table.radii, 0.0)
    curve = np.array([not ft.point_like for ft in f.hull.features] + [False])
    cells = np.array(contact_cells(f, tol), dtype=float).reshape(-1, 4)
    near, far = cells[:, 0].astype(np.intp), cells[:, 1].astype(np.intp)
    curved = curve[near] | curve[far]
    positive = tuple(t for t in slopes if t > 0.0)
    return _point_roots(cells[~curved], centres, radii, positive, jaw), _curve_grid(cells[curved], grid_rad)
