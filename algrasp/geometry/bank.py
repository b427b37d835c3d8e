"""Many curve pieces evaluated in single array passes.

The exact geometry works piece by piece, but the work per piece (a few Horner steps of
a low-degree polynomial) is far smaller than numpy's per-call overhead. Here the
power-basis coefficients of all pieces are stacked into one array (P, 7, L) — rows X,
Y, W, TX, TY, TX′, TY′ of :class:`~algrasp.geometry.curves.Piece`, zero-padded to a common
length L (padding with zero high-order coefficients leaves every value unchanged) — so
that evaluating any number of (piece, parameter) pairs is one gather plus L Horner
steps, whatever the number of pieces.

:class:`FeatureTable` applies this to the Gauss map of a hull: support points and arc
lengths of all features at once (used for the diameter/radius analysis).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from algrasp.compiled import GEOMETRY
from algrasp.geometry.angles import TWO_PI
from algrasp.geometry.curves import FloatArray, Piece, bernstein_matrix, horner_rows
from algrasp.geometry.gauss import HullFeature
from algrasp.geometry.lazy import cached_property
from algrasp.geometry.tolerances import ROUNDING_FINE

IntArray = NDArray[np.intp]
X, Y, W, TX, TY, DTX, DTY = range(7)
POINT_ROWS = [X, Y, W]
_NEWTON_STEPS = 6  # from an interpolated start: quadratic convergence reaches rounding in 3–4
_TABLE_SIZE = 33  # normal-angle samples per feature that start Newton


def unit_vectors(psi: FloatArray) -> FloatArray:
    """Unit vectors (cos ψ, sin ψ) of an array of angles (m,) → (m, 2); one buffer,
    no stacking (this sits on every support-function evaluation)."""
    out = np.empty((*np.shape(psi), 2))
    np.cos(psi, out=out[..., 0])
    np.sin(psi, out=out[..., 1])
    return out


def _no_radius(radii: Iterable[float]) -> bool:
    """Every radius +0.0 (−0.0 has its sign bit)."""
    return all(r == 0.0 and math.copysign(1.0, r) > 0.0 for r in radii)


def _no_negative_zero(centers: list[tuple[float, float]]) -> bool:
    """No coordinate −0.0 (a quick membership test first: most parts have no zero at all)."""
    flat = [c for xy in centers for c in xy]
    return 0.0 not in flat or not any(c == 0.0 and math.copysign(1.0, c) < 0.0 for c in flat)


def _der(c: FloatArray) -> FloatArray:
    """Derivatives of stacked power-basis polynomials (P, m) → (P, m)."""
    out = np.zeros_like(c)
    out[:, :-1] = c[:, 1:] * np.arange(1, c.shape[1])
    return out


def _mul(a: FloatArray, b: FloatArray) -> FloatArray:
    """Products of stacked polynomials (P, m) × (P, n) → (P, m + n − 1)."""
    out = np.zeros((a.shape[0], a.shape[1] + b.shape[1] - 1))
    for j in range(b.shape[1]):
        out[:, j : j + a.shape[1]] += a * b[:, j : j + 1]
    return out


def _group_rows(pieces: Sequence[Piece]) -> list[FloatArray]:
    """The seven coefficient rows of pieces sharing degree and rationality, (P, m) each."""
    degree, rational = pieces[0].degree, pieces[0].is_rational
    M = bernstein_matrix(degree)
    w = np.stack([p.weights for p in pieces])
    pts = np.stack([p.points for p in pieces])
    Xc, Yc = (pts[..., 0] * w) @ M.T, (pts[..., 1] * w) @ M.T
    if rational:
        Wc = w @ M.T
        dW = _der(Wc)
        TXc = _mul(_der(Xc), Wc) - _mul(Xc, dW)
        TYc = _mul(_der(Yc), Wc) - _mul(Yc, dW)
    else:  # constant weight: W is exactly that constant, as in Piece.lists
        Wc = np.zeros_like(Xc)
        Wc[:, 0] = w[:, 0]
        TXc, TYc = w[:, :1] * _der(Xc), w[:, :1] * _der(Yc)
    return [Xc, Yc, Wc, TXc, TYc, _der(TXc), _der(TYc)]


def coefficient_stack(pieces: Sequence[Piece]) -> FloatArray:
    """Stacked rows (P, 7, L) of ``pieces``, in their order; read-only. O(P·L²)."""
    groups: dict[tuple[int, bool], list[int]] = {}
    for i, p in enumerate(pieces):
        groups.setdefault((p.degree, p.is_rational), []).append(i)
    built = {key: _group_rows([pieces[i] for i in idx]) for key, idx in groups.items()}
    length = max((r.shape[1] for rows in built.values() for r in rows), default=1)
    out = np.zeros((len(pieces), 7, length))
    for key, idx in groups.items():
        for r, rows in enumerate(built[key]):
            out[idx, r, : rows.shape[1]] = rows
    out.setflags(write=False)
    return out


def _horner2(coef: FloatArray, t: FloatArray) -> FloatArray:
    """Row-wise Horner: coef (n, L), t (n,) → (n,)."""
    y = coef[:, -1] + 0.0 * t
    for j in range(coef.shape[1] - 2, -1, -1):
        y = y * t + coef[:, j]
    return y


def points(coef: FloatArray, idx: IntArray, t: FloatArray) -> FloatArray:
    """Points of pieces ``idx`` of the stack ``coef`` (P, 7, L) at t (n,) → (n, 2)."""
    x, y, w = (_horner2(coef[idx, r], t) for r in POINT_ROWS)
    return np.stack([x / w, y / w], axis=-1)


def normal_angles(coef: FloatArray, t: FloatArray) -> FloatArray:
    """Outward-normal angles (counter-clockwise loops) of pieces (P, 7, L) at t (P, m)."""
    tx, ty = horner_rows(coef[:, None, [TX, TY]], t)
    angle: FloatArray = np.arctan2(-tx, ty)
    return angle


_NO_CURVES = (np.zeros((0, 7, 1)), np.zeros(0), np.zeros(0), np.zeros(0))
"""coef, s0, s1 and psi0 of a table without curve features (read-only, shared)."""
for _a in _NO_CURVES:
    _a.setflags(write=False)


@dataclass(frozen=True, eq=False)
class FeatureTable:
    """All features of a hull's Gauss map as arrays (F features, C of them curves).

    Attributes:
        breakpoints: (F,) psi0 of each feature (sorted, lifted).
        centers, radii: (F, 2), (F,) for points and circular arcs (zero for curves).
        slot: (F,) row of each curve feature in the curve arrays, −1 otherwise.
        coef: (C, 7, L) coefficient rows of the curve features' pieces.
        s0, s1, psi0: (C,) parameter range and first normal of each curve feature.
    """

    breakpoints: FloatArray
    centers: FloatArray
    radii: FloatArray
    slot: IntArray
    coef: FloatArray
    s0: FloatArray
    s1: FloatArray
    psi0: FloatArray

    @classmethod
    def build(cls, features: Sequence[HullFeature]) -> FeatureTable:
        curves = [f for f in features if f.kind == "curve"]
        breakpoints = np.array([f.psi0 for f in features])
        if not curves:  # points and circular arcs: the curve arrays are the shared empty ones
            table = cls(breakpoints, np.array([f.center for f in features], dtype=float),
                        np.array([f.radius for f in features], dtype=float), np.full(len(features), -1, dtype=np.intp),
                        *_NO_CURVES)
            # The cached properties the features give in plain floats, set now (their arrays' .tolist()).
            pairs = [(float(f.center[0]), float(f.center[1])) for f in features]
            table.__dict__.update(breakpoint_list=[float(f.psi0) for f in features], center_list=pairs,
                                  vertices_only=_no_radius(f.radius for f in features) and _no_negative_zero(pairs))
            return table
        slots, n = [], 0
        for f in features:
            slots.append(n if f.kind == "curve" else -1)
            n += f.kind == "curve"
        slot = np.array(slots, dtype=np.intp)
        centers = np.array([f.center if f.kind != "curve" else (0.0, 0.0) for f in features], dtype=float)
        radii = np.array([f.radius if f.kind != "curve" else 0.0 for f in features], dtype=float)
        coef = coefficient_stack([f.piece for f in curves])  # type: ignore[misc]
        return cls(breakpoints, centers, radii, slot, coef, np.array([f.s0 for f in curves]),
                   np.array([f.s1 for f in curves]), np.array([f.psi0 for f in curves]))

    @cached_property
    def breakpoint_list(self) -> list[float]:
        """:attr:`breakpoints` as floats (for scalar work on the features)."""
        return self.breakpoints.tolist()  # type: ignore[no-any-return]

    @cached_property
    def _normal_table(self) -> tuple[FloatArray, FloatArray]:
        """(ψ, t) samples (C, 33) per curve feature, ψ lifted above psi0 and monotone."""
        u = np.linspace(0.0, 1.0, _TABLE_SIZE)
        ts = self.s0[:, None] + (self.s1 - self.s0)[:, None] * u
        raw = normal_angles(self.coef, ts)
        p0 = self.psi0[:, None]
        return np.maximum.accumulate(p0 + (raw - p0 + np.pi) % TWO_PI - np.pi, axis=1), ts

    @cached_property
    def _later_breakpoints(self) -> tuple[float, FloatArray]:
        """The first breakpoint and the others (a read-only view), for :meth:`feature_index`."""
        rest = self.breakpoints[1:]
        rest.setflags(write=False)
        return float(self.breakpoints[0]), rest

    def feature_index(self, psi: FloatArray) -> tuple[IntArray, FloatArray]:
        """Feature holding each normal ψ (right-open ranges) and ψ lifted into the table's turn."""
        base, rest = self._later_breakpoints
        x = base + (np.asarray(psi, dtype=float) - base) % TWO_PI
        # x ≥ breakpoints[0]: the breakpoints after the first at or below x count the
        # feature, at most F − 1 (x may round up to base + 2π: the last feature).
        return np.searchsorted(rest, x, side="right"), x

    def params(self, slots: IntArray, psi: FloatArray) -> FloatArray:
        """Parameters where curve features ``slots`` have outward normal ψ: Newton on
        ⟨T(t), u(ψ)⟩ = 0 from the interpolated table, kept in [s0, s1]. O(n·(33 + L))."""
        tab_psi, tab_t = self._normal_table
        p0 = self.psi0[slots]
        local = p0 + (psi - p0 + np.pi) % TWO_PI - np.pi
        rows, trows = tab_psi[slots], tab_t[slots]
        k = np.minimum(np.maximum(np.sum(rows <= local[:, None], axis=1), 1), _TABLE_SIZE - 1)
        n = np.arange(len(slots))
        lo_p, hi_p, lo_t, hi_t = rows[n, k - 1], rows[n, k], trows[n, k - 1], trows[n, k]
        span = hi_p - lo_p
        frac = np.minimum(np.maximum(np.divide(local - lo_p, span, out=np.zeros_like(span), where=span > 0.0), 0.0), 1.0)
        t = lo_t + frac * (hi_t - lo_t)
        lo, hi = self.s0[slots], self.s1[slots]
        c, s = np.cos(psi)[:, None], np.sin(psi)[:, None]
        # ⟨T(t), u(ψ)⟩ and its t-derivative as one polynomial each per query.
        q_coef = self.coef[slots, TX] * c + self.coef[slots, TY] * s
        dq_coef = self.coef[slots, DTX] * c + self.coef[slots, DTY] * s
        for _ in range(_NEWTON_STEPS):
            q, dq = _horner2(q_coef, t), _horner2(dq_coef, t)
            step = np.divide(q, dq, out=np.zeros_like(q), where=dq != 0.0)
            t = np.minimum(np.maximum(t - step, lo), hi)
            if not np.any(np.abs(step) >= ROUNDING_FINE):
                break
        result: FloatArray = t
        return result

    @cached_property
    def center_list(self) -> list[tuple[float, float]]:
        """:attr:`centers` as float pairs (for the compiled support of vertices)."""
        return [(x, y) for x, y in self.centers.tolist()]

    @cached_property
    def vertices_only(self) -> bool:
        """Every feature a vertex (radius +0.0, no curve) and no centre coordinate −0.0: the
        support point is the centre itself, exactly c + 0·u(ψ), and the support value
        ⟨c, u⟩ + 0.0 (a polygon's hull)."""
        # In plain floats (a few features; ~8 array calls otherwise): −0.0 has its sign bit.
        return not len(self.s0) and _no_radius(self.radii.tolist()) and _no_negative_zero(self.center_list)

    def support_of(self, psi: FloatArray) -> FloatArray:
        """Support values h(ψ) (n,) at normals ψ (n,): :meth:`support` of
        :meth:`feature_index`. Vertices only and one-dimensional ψ: compiled when built
        (:mod:`algrasp.compiled`; the same lift, bisection and sums, numpy's cosines and sines)."""
        psi = np.asarray(psi, dtype=float)
        if GEOMETRY is not None and psi.ndim == 1 and self.vertices_only:
            return GEOMETRY.vertex_support(self.breakpoint_list, self.center_list, psi)  # type: ignore[no-any-return]
        return self.support(*self.feature_index(psi))

    @cached_property
    def _center_columns(self) -> tuple[FloatArray, FloatArray]:
        """The centres' x and y as contiguous read-only arrays (F,)."""
        cx, cy = np.ascontiguousarray(self.centers[:, 0]), np.ascontiguousarray(self.centers[:, 1])
        cx.setflags(write=False)
        cy.setflags(write=False)
        return cx, cy

    def points(self, idx: IntArray, psi: FloatArray) -> FloatArray:
        """Support points (n, 2) of features ``idx`` for outward normals ψ (n,)."""
        if self.vertices_only:  # c + 0·u is c: no trigonometry
            return self.centers[idx]
        psi = np.asarray(psi, dtype=float)
        out: FloatArray = self.centers[idx] + self.radii[idx, None] * unit_vectors(psi)
        hit = self._curve_points(idx, psi)
        if hit is not None:
            out[hit[0]] = hit[1]
        return out

    def support(self, idx: IntArray, psi: FloatArray) -> FloatArray:
        """Support values h(ψ) = ⟨p, u(ψ)⟩ (n,) of features ``idx`` at normals ψ (n,):
        ⟨c, u⟩ + r for points and circular arcs, the exact support point's for curves."""
        if self.vertices_only:  # radius +0 everywhere, no curve: the same sums, one pass
            cx, cy = self._center_columns
            return np.asarray(cx[idx] * np.cos(psi) + cy[idx] * np.sin(psi) + 0.0)
        u = unit_vectors(psi)
        c = self.centers[idx]
        out: FloatArray = c[:, 0] * u[:, 0] + c[:, 1] * u[:, 1] + self.radii[idx]
        hit = self._curve_points(idx, psi)
        if hit is not None:
            curve, p = hit
            out[curve] = p[:, 0] * u[curve, 0] + p[:, 1] * u[curve, 1]
        return out

    def _curve_points(self, idx: IntArray, psi: FloatArray) -> tuple[NDArray[np.bool_], FloatArray] | None:
        """Which queries (features ``idx``, normals ψ) fall on curve features, and their
        exact support points (Newton, :meth:`params`); None when none do (polygons and
        circular arcs need no lookup at all)."""
        if not len(self.s0):
            return None
        slots = self.slot[idx]
        curve = slots >= 0
        if not np.any(curve):
            return None
        sl = slots[curve]
        return curve, points(self.coef, sl, self.params(sl, psi[curve]))

    def curve_lengths(self, nodes: FloatArray, weights: FloatArray) -> FloatArray:
        """Arc lengths (C,) of the curve features by the quadrature rule (nodes, weights) on [0, 1]."""
        t = self.s0[:, None] + (self.s1 - self.s0)[:, None] * nodes
        tx, ty, w = horner_rows(self.coef[:, [TX, TY, W]][:, None], t)
        return np.asarray((self.s1 - self.s0) * ((np.hypot(tx, ty) / (w * w)) @ weights))
