"""Exact rational Bezier pieces: the one curve representation the geometry works on.

Lines, circular arcs, elliptic arcs and (rational) Bezier segments all become
:class:`Piece` objects without approximation: a conic arc of at most 90° is exactly a
rational quadratic Bezier. A piece keeps homogeneous power-basis polynomials
``X(t), Y(t), W(t)`` on ``t ∈ [0, 1]`` so that tangents, curvature sign and tangency
conditions are polynomials whose roots we solve (no sampling stands in for a curve).

Polynomial coefficient arrays are in increasing order (numpy.polynomial convention).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from math import comb

import numpy as np
from numpy.typing import NDArray

from algrasp.geometry.lazy import cached_property
from algrasp.geometry.tolerances import COEFF_NOISE, DISCRIMINANT_REL, IMAG_REL, ROUNDING

FloatArray = NDArray[np.float64]


def horner_rows(C: FloatArray, t: FloatArray | float) -> FloatArray:
    """Evaluate power-basis rows C (..., R, L) at parameters ``t``, which broadcast
    against the leading shape (...): returns (R, ...). For one piece's rows (R, L) that
    is (R, *t.shape); for stacked pieces (P, 1, R, L) with t (P, m) it is (R, P, m).
    L multiply-adds over the whole batch."""
    tt = np.asarray(t, dtype=float)[..., None]
    y = C[..., -1] + np.zeros_like(tt)  # broadcast even when L == 1
    for j in range(C.shape[-1] - 2, -1, -1):
        y = y * tt + C[..., j]
    return np.moveaxis(y, -1, 0)


def stack_polys(*polys: FloatArray) -> FloatArray:
    """Rows of equal length (zero-padded) for :func:`horner_rows`; read-only."""
    n = max(len(p) for p in polys)
    out = np.zeros((len(polys), n))
    for i, p in enumerate(polys):
        out[i, : len(p)] = p
    out.setflags(write=False)
    return out


def _lmul(a: list[float], b: list[float]) -> list[float]:
    out = [0.0] * (len(a) + len(b) - 1)
    for i, x in enumerate(a):
        for j, y in enumerate(b):
            out[i + j] += x * y
    return out


def _lder(c: list[float]) -> list[float]:
    return [i * c[i] for i in range(1, len(c))] or [0.0]


def _ladd(a: list[float], b: list[float], sb: float = 1.0) -> list[float]:
    n = max(len(a), len(b))
    return [(a[i] if i < len(a) else 0.0) + sb * (b[i] if i < len(b) else 0.0) for i in range(n)]


def horner_float(c: list[float], t: float) -> float:
    """Horner in plain floats (scalar hot paths)."""
    y = c[-1]
    for a in c[-2::-1]:
        y = y * t + a
    return y


def pmul(a: FloatArray, b: FloatArray) -> FloatArray:
    """Product of power-basis polynomials."""
    return np.convolve(a, b)


def padd(a: FloatArray, b: FloatArray) -> FloatArray:
    """Sum of power-basis polynomials of any lengths."""
    n = max(len(a), len(b))
    out = np.zeros(n)
    out[: len(a)] += a
    out[: len(b)] += b
    return out


def _readonly(a: FloatArray) -> FloatArray:
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a


@lru_cache(maxsize=64)
def _bernstein_lists(k: int) -> list[list[float]]:
    return bernstein_matrix(k).tolist()  # type: ignore[no-any-return]


@lru_cache(maxsize=64)
def bernstein_matrix(k: int) -> FloatArray:
    """M with power = M @ bernstein for degree k (integer entries, exact in floats)."""
    M = np.zeros((k + 1, k + 1))
    for i in range(k + 1):
        # B_{i,k}(t) = C(k,i) t^i (1-t)^(k-i) = sum_j C(k,i) C(k-i,j) (-1)^j t^(i+j)
        for j in range(k - i + 1):
            M[i + j, i] += comb(k, i) * comb(k - i, j) * (-1) ** j
    M.setflags(write=False)
    return M


def bernstein_values(degree: int, t: FloatArray) -> FloatArray:
    """The degree-k Bernstein basis at parameters t (N,) → (N, k+1)."""
    return np.asarray((np.asarray(t, dtype=float)[:, None] ** np.arange(degree + 1)) @ bernstein_matrix(degree))


def homogeneous(points: FloatArray, weights: FloatArray) -> FloatArray:
    """Homogeneous control points (w·x, w·y, w) of a rational Bezier curve, (k+1, 3)."""
    return np.column_stack([points * weights[:, None], weights])


def real_roots_in(poly: FloatArray | list[float], lo: float, hi: float, slack: float = ROUNDING) -> list[float]:
    """Real roots of a power-basis polynomial in ``[lo, hi]`` (sorted, polished).

    Degree ≤ 2 in closed form; otherwise the eigenvalues of the companion matrix.
    Every root is polished by two Newton steps; roots within ``slack`` outside the
    interval are clamped in. O(k³) for degree k.
    """
    c = [float(x) for x in poly]
    scale = max((abs(x) for x in c), default=0.0)
    if scale == 0.0:
        return []
    c = [x / scale for x in c]
    while len(c) > 1 and abs(c[-1]) < COEFF_NOISE:  # leading coefficients that are rounding noise
        c.pop()
    if len(c) <= 1:
        return []
    cands = _quadratic_roots(c) if len(c) <= 3 else _companion_roots(c)
    dc = _lder(c)
    out: list[float] = []
    for x in cands:
        for _ in range(2):
            d = horner_float(dc, x)
            if d != 0.0:
                x -= horner_float(c, x) / d
        if lo - slack <= x <= hi + slack:
            out.append(min(max(x, lo), hi))
    out.sort()
    return out


def _quadratic_roots(c: list[float]) -> list[float]:
    if len(c) == 2:
        return [-c[0] / c[1]]
    a, b, k = c[2], c[1], c[0]
    disc = b * b - 4 * a * k
    if disc < -DISCRIMINANT_REL * max(b * b, abs(4 * a * k)):
        return []
    r = math.sqrt(max(disc, 0.0))
    q = -0.5 * (b + math.copysign(r, b))  # avoids cancellation
    roots = [q / a]
    if q != 0.0:
        roots.append(k / q)
    return roots


def _companion_roots(c: list[float]) -> list[float]:
    n = len(c) - 1
    C = np.zeros((n, n))
    C[1:, :-1] = np.eye(n - 1)
    C[:, -1] = [-x / c[-1] for x in c[:-1]]
    ev = np.linalg.eigvals(C)
    return [float(z.real) for z in ev if abs(z.imag) <= IMAG_REL * max(1.0, abs(z.real))]


@dataclass(frozen=True, eq=False)
class Piece:
    """A rational Bezier curve piece on ``t ∈ [0, 1]``.

    Attributes:
        points: (k+1, 2) control points.
        weights: (k+1,) positive weights (all equal for a polynomial curve).
        circle: ``(cx, cy, radius)`` when the piece is exactly a circular arc.
        source: index of the boundary segment the piece came from.
    """

    points: FloatArray
    weights: FloatArray
    circle: tuple[float, float, float] | None = None
    source: int = -1

    def __post_init__(self) -> None:
        object.__setattr__(self, "points", _readonly(self.points))
        object.__setattr__(self, "weights", _readonly(self.weights))

    # Derived polynomials are computed on first use (intermediate pieces of a split
    # never need most of them), in plain float lists: for degrees ≤ 20 this is several
    # times faster than chains of small array operations.
    @cached_property
    def lists(self) -> tuple[list[float], list[float], list[float], list[float], list[float]]:
        """X, Y, W, TX, TY as coefficient lists (increasing order)."""
        w = self.weights.tolist()
        pts = self.points.tolist()
        M = _bernstein_lists(len(w) - 1)
        X = [sum(m * p[0] * wi for m, p, wi in zip(row, pts, w)) for row in M]
        Y = [sum(m * p[1] * wi for m, p, wi in zip(row, pts, w)) for row in M]
        if max(w) == min(w):
            W = [w[0]]  # polynomial curve: W is an exact constant
            TX, TY = [w[0] * c for c in _lder(X)], [w[0] * c for c in _lder(Y)]
        else:
            W = [sum(m * wi for m, wi in zip(row, w)) for row in M]
            dW = _lder(W)
            TX = _ladd(_lmul(_lder(X), W), _lmul(X, dW), -1.0)
            TY = _ladd(_lmul(_lder(Y), W), _lmul(Y, dW), -1.0)
        return X, Y, W, TX, TY

    @cached_property
    def X(self) -> FloatArray:
        return _readonly(np.array(self.lists[0]))

    @cached_property
    def Y(self) -> FloatArray:
        return _readonly(np.array(self.lists[1]))

    @cached_property
    def W(self) -> FloatArray:
        return _readonly(np.array(self.lists[2]))

    @cached_property
    def TX(self) -> FloatArray:
        """x of the tangent numerator X′W − XW′ (direction of B′(t))."""
        return _readonly(np.array(self.lists[3]))

    @cached_property
    def TY(self) -> FloatArray:
        return _readonly(np.array(self.lists[4]))

    @cached_property
    def XYW(self) -> FloatArray:
        return stack_polys(self.X, self.Y, self.W)

    @cached_property
    def tangent_lists(self) -> tuple[list[float], list[float], list[float], list[float]]:
        """TX, TY, TX′, TY′ as coefficient lists: Newton on the tangent condition needs all four."""
        _, _, _, TX, TY = self.lists
        return TX, TY, _lder(TX), _lder(TY)

    @cached_property
    def TANGENTS(self) -> FloatArray:
        """:attr:`tangent_lists` as rows for :func:`horner_rows`."""
        return stack_polys(*(np.array(c) for c in self.tangent_lists))

    @property
    def degree(self) -> int:
        return int(self.points.shape[0] - 1)

    @property
    def is_rational(self) -> bool:
        return bool(np.ptp(self.weights) > 0.0)

    def point(self, t: FloatArray | float) -> FloatArray:
        """Points at parameters ``t`` (shape (..., 2))."""
        if isinstance(t, float):
            X, Y, W, _, _ = self.lists
            w = horner_float(W, t)
            return np.array([horner_float(X, t) / w, horner_float(Y, t) / w])
        x, y, w = horner_rows(self.XYW, t)
        return np.stack([x / w, y / w], axis=-1)

    def tangent(self, t: FloatArray | float) -> FloatArray:
        """Tangent directions (not normalised, same sense as B'(t)); shape (..., 2)."""
        if isinstance(t, float):
            _, _, _, TX, TY = self.lists
            return np.array([horner_float(TX, t), horner_float(TY, t)])
        tx, ty = horner_rows(self.TANGENTS[:2], t)
        return np.stack([tx, ty], axis=-1)

    def normal_angle(self, t: FloatArray | float) -> FloatArray:
        """Angle of the right-hand normal (outward for a counter-clockwise loop)."""
        tan = self.tangent(t)
        return np.arctan2(-tan[..., 0], tan[..., 1])

    @cached_property
    def curvature_list(self) -> list[float]:
        """Polynomial T × T′ (T the tangent numerator), with the sign of the curvature.

        T × T′ = W·det[P, P′, P″] for the homogeneous curve P = (X, Y, W), so the
        curvature is κ = (T × T′)·W² / |T|³ (W > 0 for positive weights).
        """
        TX, TY, dTX, dTY = self.tangent_lists
        return _ladd(_lmul(TX, dTY), _lmul(TY, dTX), -1.0)

    def tangent_dot_poly(self, direction: FloatArray) -> FloatArray:
        """Polynomial ⟨T(t), v⟩: its roots are where the tangent is normal to ``v``."""
        return padd(direction[0] * self.TX, direction[1] * self.TY)

    def tangent_from_point_poly(self, a: FloatArray) -> FloatArray:
        """Polynomial cross(T(t), B(t) − a)·W(t): zero where the line from ``a`` touches."""
        ex = padd(self.X, -a[0] * self.W)
        ey = padd(self.Y, -a[1] * self.W)
        return padd(pmul(self.TX, ey), -pmul(self.TY, ex))

    def restrict(self, a: float, b: float) -> Piece:
        """The sub-piece for parameters [a, b], reparametrised to [0, 1] (exact)."""
        if a <= 0.0 and b >= 1.0:
            return self
        hom = [[x * w, y * w, w] for (x, y), w in zip(self.points.tolist(), self.weights.tolist())]
        if b < 1.0:
            hom, _ = _de_casteljau(hom, b)
        if a > 0.0:
            _, hom = _de_casteljau(hom, a / b)
        return self._from_hom(hom)

    def _from_hom(self, hom: list[list[float]]) -> Piece:
        top = max(h[2] for h in hom)
        return Piece(np.array([[h[0] / h[2], h[1] / h[2]] for h in hom]), np.array([h[2] / top for h in hom]),
                     self.circle, self.source)

    def reversed(self) -> Piece:
        return Piece(self.points[::-1], self.weights[::-1], self.circle, self.source)

    def support_param(self, direction: FloatArray) -> float:
        """Parameter of the point of the piece extreme in ``direction`` (ends included)."""
        cands = [0.0, 1.0, *real_roots_in(self.tangent_dot_poly(direction), 0.0, 1.0)]
        vals = self.point(np.array(cands)) @ direction
        return float(cands[int(np.argmax(vals))])


def _de_casteljau(pts: list[list[float]], t: float) -> tuple[list[list[float]], list[list[float]]]:
    """Split homogeneous control points (k+1 lists [wx, wy, w]) at ``t``; (left, right).

    Plain floats: for the small degrees here this beats array operations tenfold.
    """
    s = 1.0 - t
    left = [pts[0]]
    right = [pts[-1]]
    while len(pts) > 1:
        pts = [[s * a[0] + t * b[0], s * a[1] + t * b[1], s * a[2] + t * b[2]] for a, b in zip(pts[:-1], pts[1:])]
        left.append(pts[0])
        right.append(pts[-1])
    return left, right[::-1]


def conic_arc_pieces(
    center: FloatArray, axes: FloatArray, t0: float, t1: float, circle: tuple[float, float, float] | None, source: int
) -> list[Piece]:
    """Exact rational quadratic pieces of ``center + axes @ (cos t, sin t)``, t0 → t1.

    ``axes`` is the 2×2 matrix mapping the unit circle to the ellipse. Each piece spans
    at most 90° of parameter so its weight cos(Δ/2) stays ≥ cos 45°.
    """
    sweep = t1 - t0
    n = max(1, int(np.ceil(abs(sweep) / (np.pi / 2) - ROUNDING)))
    out = []
    for i in range(n):
        a = t0 + sweep * i / n
        b = t0 + sweep * (i + 1) / n
        half = (b - a) / 2.0
        mid = (a + b) / 2.0
        unit = np.array([[np.cos(a), np.sin(a)], [np.cos(mid) / np.cos(half), np.sin(mid) / np.cos(half)], [np.cos(b), np.sin(b)]])
        pts = center + unit @ axes.T
        out.append(Piece(pts, np.array([1.0, np.cos(half), 1.0]), circle, source))
    return out
