"""Exact rational Bezier pieces: the one curve representation the geometry works on.

Lines, circular arcs, elliptic arcs and (rational) Bezier segments all become
:class:`Piece` objects without approximation: a conic arc of at most 90° is exactly a
rational quadratic Bezier. A piece keeps homogeneous power-basis polynomials
``X(t), Y(t), W(t)`` on ``t ∈ [0, 1]`` so that tangents, curvature sign and tangency
conditions are polynomials whose roots we solve (no sampling stands in for a curve).

Polynomial coefficient arrays are in increasing order (numpy.polynomial convention).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from math import comb

import numpy as np
import numpy.polynomial.polynomial as npoly
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


def horner(c: FloatArray, t: FloatArray | float) -> FloatArray:
    """Evaluate a power-basis polynomial (increasing order) at ``t``; O(k) per point.

    Plain Horner: numpy.polynomial.polyval's argument checking costs more than the
    arithmetic for the small degrees here.
    """
    t = np.asarray(t, dtype=float)
    y = np.full(t.shape, c[-1], dtype=float)
    for a in c[-2::-1]:
        y = y * t + a
    return y


def horner_rows(C: FloatArray, t: FloatArray | float) -> FloatArray:
    """Evaluate the rows of C (m, k+1), each a power-basis polynomial, at ``t``.

    Returns shape (m, *t.shape): one pass for several polynomials of one piece.
    """
    t = np.asarray(t, dtype=float)
    y = np.multiply.outer(C[:, -1], np.ones_like(t))
    for j in range(C.shape[1] - 2, -1, -1):
        y = y * t + C[:, j].reshape((-1,) + (1,) * t.ndim)
    return y


def stack_polys(*polys: FloatArray) -> FloatArray:
    """Rows of equal length (zero-padded) for :func:`horner_rows`; read-only."""
    n = max(len(p) for p in polys)
    out = np.zeros((len(polys), n))
    for i, p in enumerate(polys):
        out[i, : len(p)] = p
    out.setflags(write=False)
    return out


def pmul(a: FloatArray, b: FloatArray) -> FloatArray:
    """Product of power-basis polynomials."""
    return np.convolve(a, b)


def pder(c: FloatArray) -> FloatArray:
    """Derivative of a power-basis polynomial (the zero polynomial stays [0])."""
    if len(c) <= 1:
        return np.zeros(1)
    return np.asarray(c[1:] * np.arange(1, len(c)), dtype=float)


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
def _bernstein_matrix(k: int) -> FloatArray:
    """M with power = M @ bernstein for degree k (integer entries, exact in floats)."""
    M = np.zeros((k + 1, k + 1))
    for i in range(k + 1):
        # B_{i,k}(t) = C(k,i) t^i (1-t)^(k-i) = sum_j C(k,i) C(k-i,j) (-1)^j t^(i+j)
        for j in range(k - i + 1):
            M[i + j, i] += comb(k, i) * comb(k - i, j) * (-1) ** j
    M.setflags(write=False)
    return M


def bernstein_to_power(coeffs: FloatArray) -> FloatArray:
    """Convert Bernstein coefficients (k+1,) or (k+1, m) to power basis on [0, 1]. O(k²)."""
    return np.asarray(_bernstein_matrix(coeffs.shape[0] - 1) @ coeffs, dtype=float)


def real_roots_in(poly: FloatArray, lo: float, hi: float, slack: float = 1e-12) -> list[float]:
    """Real roots of a power-basis polynomial in ``[lo, hi]`` (sorted, polished).

    Roots come from the companion matrix, then two Newton steps polish them; roots
    within ``slack`` outside the interval are clamped in. O(k³) for degree k.
    """
    p = npoly.polytrim(np.asarray(poly, dtype=float), tol=0.0)
    if p.size <= 1 or not np.any(p):
        return []
    scale = np.max(np.abs(p))
    p = p / scale
    p = _trim_tiny_leading(p)
    if p.size <= 1:
        return []
    roots = npoly.polyroots(p)
    dp = npoly.polyder(p)
    out: list[float] = []
    for r in roots:
        if abs(r.imag) > 1e-7 * max(1.0, abs(r.real)):
            continue
        x = float(r.real)
        for _ in range(2):
            d = float(npoly.polyval(x, dp))
            if d != 0.0:
                x -= float(npoly.polyval(x, p)) / d
        if lo - slack <= x <= hi + slack:
            out.append(min(max(x, lo), hi))
    out.sort()
    return out


def _trim_tiny_leading(p: FloatArray) -> FloatArray:
    """Drop leading coefficients that are rounding noise (relative 1e-13)."""
    n = p.size
    while n > 1 and abs(p[n - 1]) < 1e-13:
        n -= 1
    return p[:n]


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
    X: FloatArray = field(init=False, repr=False)
    Y: FloatArray = field(init=False, repr=False)
    W: FloatArray = field(init=False, repr=False)
    TX: FloatArray = field(init=False, repr=False)
    TY: FloatArray = field(init=False, repr=False)
    XYW: FloatArray = field(init=False, repr=False)
    TANGENTS: FloatArray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        pts = _readonly(self.points)
        w = _readonly(self.weights)
        object.__setattr__(self, "points", pts)
        object.__setattr__(self, "weights", w)
        hom = np.column_stack([pts[:, 0] * w, pts[:, 1] * w, w])
        power = bernstein_to_power(hom)
        X, Y, W = power[:, 0], power[:, 1], power[:, 2]
        if not np.ptp(w) > 0.0:
            W = w[:1].copy()  # a polynomial curve: keep W an exact constant (no rounding tail)
        dX, dY, dW = pder(X), pder(Y), pder(W)
        # Direction of B'(t) is (X'W - XW', Y'W - YW') / W²: keep the numerator.
        TX = padd(pmul(dX, W), -pmul(X, dW))
        TY = padd(pmul(dY, W), -pmul(Y, dW))
        for name, val in (("X", X), ("Y", Y), ("W", W), ("TX", TX), ("TY", TY)):
            object.__setattr__(self, name, _readonly(val))
        object.__setattr__(self, "XYW", stack_polys(X, Y, W))
        # Rows TX, TY, TX′, TY′: Newton on the tangent condition needs all four.
        object.__setattr__(self, "TANGENTS", stack_polys(TX, TY, pder(TX), pder(TY)))

    @property
    def degree(self) -> int:
        return int(self.points.shape[0] - 1)

    @property
    def is_rational(self) -> bool:
        return bool(np.ptp(self.weights) > 0.0)

    def point(self, t: FloatArray | float) -> FloatArray:
        """Points at parameters ``t`` (shape (..., 2))."""
        x, y, w = horner_rows(self.XYW, t)
        return np.stack([x / w, y / w], axis=-1)

    def tangent(self, t: FloatArray | float) -> FloatArray:
        """Tangent directions (not normalised, same sense as B'(t)); shape (..., 2)."""
        tx, ty = horner_rows(self.TANGENTS[:2], t)
        return np.stack([tx, ty], axis=-1)

    def normal_angle(self, t: FloatArray | float) -> FloatArray:
        """Angle of the right-hand normal (outward for a counter-clockwise loop)."""
        tan = self.tangent(t)
        return np.arctan2(-tan[..., 0], tan[..., 1])

    def curvature_sign_poly(self) -> FloatArray:
        """Polynomial with the sign of the curvature: det[P, P', P''] (P homogeneous)."""
        P = [self.X, self.Y, self.W]
        d1 = [pder(c) for c in P]
        d2 = [pder(c) for c in d1]
        det = np.zeros(1)
        for i, j, k, s in ((0, 1, 2, 1), (1, 2, 0, 1), (2, 0, 1, 1), (0, 2, 1, -1), (1, 0, 2, -1), (2, 1, 0, -1)):
            det = padd(det, s * pmul(pmul(P[i], d1[j]), d2[k]))
        return det

    def tangent_dot_poly(self, direction: FloatArray) -> FloatArray:
        """Polynomial ⟨T(t), v⟩: its roots are where the tangent is normal to ``v``."""
        return padd(direction[0] * self.TX, direction[1] * self.TY)

    def tangent_from_point_poly(self, a: FloatArray) -> FloatArray:
        """Polynomial cross(T(t), B(t) − a)·W(t): zero where the line from ``a`` touches."""
        ex = padd(self.X, -a[0] * self.W)
        ey = padd(self.Y, -a[1] * self.W)
        return padd(pmul(self.TX, ey), -pmul(self.TY, ex))

    def split(self, ts: list[float]) -> list[Piece]:
        """Split at the sorted interior parameters ``ts`` (exact de Casteljau)."""
        out: list[Piece] = []
        hom = np.column_stack([self.points * self.weights[:, None], self.weights])
        prev = 0.0
        rest = hom
        for t in ts:
            local = (t - prev) / (1.0 - prev)
            left, rest = _de_casteljau(rest, local)
            out.append(self._from_hom(left))
            prev = t
        out.append(self._from_hom(rest))
        return out

    def _from_hom(self, hom: FloatArray) -> Piece:
        w = hom[:, 2]
        return Piece(hom[:, :2] / w[:, None], w / np.max(w), self.circle, self.source)

    def reversed(self) -> Piece:
        return Piece(self.points[::-1], self.weights[::-1], self.circle, self.source)

    def support_param(self, direction: FloatArray) -> float:
        """Parameter of the point of the piece extreme in ``direction`` (ends included)."""
        cands = [0.0, 1.0, *real_roots_in(self.tangent_dot_poly(direction), 0.0, 1.0)]
        vals = self.point(np.array(cands)) @ direction
        return float(cands[int(np.argmax(vals))])


def _de_casteljau(hom: FloatArray, t: float) -> tuple[FloatArray, FloatArray]:
    """Split homogeneous control points at ``t``; returns (left, right)."""
    pts = hom.copy()
    n = pts.shape[0]
    left = [pts[0].copy()]
    right = [pts[-1].copy()]
    for _ in range(1, n):
        pts = (1.0 - t) * pts[:-1] + t * pts[1:]
        left.append(pts[0].copy())
        right.append(pts[-1].copy())
    return np.array(left), np.array(right[::-1])


def conic_arc_pieces(
    center: FloatArray, axes: FloatArray, t0: float, t1: float, circle: tuple[float, float, float] | None, source: int
) -> list[Piece]:
    """Exact rational quadratic pieces of ``center + axes @ (cos t, sin t)``, t0 → t1.

    ``axes`` is the 2×2 matrix mapping the unit circle to the ellipse. Each piece spans
    at most 90° of parameter so its weight cos(Δ/2) stays ≥ cos 45°.
    """
    sweep = t1 - t0
    n = max(1, int(np.ceil(abs(sweep) / (np.pi / 2) - 1e-12)))
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
