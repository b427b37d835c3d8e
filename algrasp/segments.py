"""Boundary segments of a part document as immutable value objects.

Each segment knows its end points, its exact :class:`~algrasp.curves.Piece` form, its
Green's-theorem moments (for area and centre of mass) and a polyline used only for
validity checks and drawings — never for the analysis.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property, lru_cache

import numpy as np

from algrasp.curves import FloatArray, Piece, _readonly, conic_arc_pieces, horner_rows

Moments = tuple[float, float, float]


@lru_cache(maxsize=32)
def gauss_legendre_01(n: int, panels: int) -> tuple[FloatArray, FloatArray]:
    """Nodes and weights of composite n-point Gauss-Legendre on [0, 1] (``panels`` panels)."""
    nodes, wts = np.polynomial.legendre.leggauss(n)
    edges = np.linspace(0.0, 1.0, panels + 1)
    t = np.concatenate([(a + b) / 2 + (b - a) / 2 * nodes for a, b in zip(edges[:-1], edges[1:])])
    w = np.concatenate([(b - a) / 2 * wts for a, b in zip(edges[:-1], edges[1:])])
    t.setflags(write=False)
    w.setflags(write=False)
    return t, w
"""(∮ x dy, ½ ∮ x² dy, −½ ∮ y² dx): area and first moments of the enclosed region."""


@dataclass(frozen=True)
class Line:
    start: tuple[float, float]
    end: tuple[float, float]

    def pieces(self, source: int) -> list[Piece]:
        # A straight segment contributes only its end points to the hull.
        return []

    def reversed(self) -> Line:
        return Line(self.end, self.start)

    def moments(self) -> Moments:
        (px, py), (qx, qy) = self.start, self.end
        a = (px + qx) / 2.0 * (qy - py)
        sx = 0.5 * (qy - py) * (px * px + px * qx + qx * qx) / 3.0
        sy = -0.5 * (qx - px) * (py * py + py * qy + qy * qy) / 3.0
        return a, sx, sy

    def second_moments(self) -> tuple[float, float]:
        """(⅓∮ x³ dy, −⅓∮ y³ dx) = (∬ x² dA, ∬ y² dA) contributions."""
        (px, py), (qx, qy) = self.start, self.end
        ixx = (qy - py) * (px**3 + px * px * qx + px * qx * qx + qx**3) / 12.0
        iyy = -(qx - px) * (py**3 + py * py * qy + py * qy * qy + qy**3) / 12.0
        return ixx, iyy

    def polyline(self, max_turn_rad: float) -> FloatArray:
        return np.array([self.start, self.end], dtype=float)

    def to_dict(self) -> dict[str, object]:
        return {"type": "line", "start": list(self.start), "end": list(self.end)}


@dataclass(frozen=True)
class EllipseArc:
    """``center + R(rotation)·(rx cos t, ry sin t)`` for t from ``start`` to ``end`` (rad).

    A circular arc is the case ``rx == ry`` (``is_circle``), kept as such so that its
    centre decides regions of constant diameter exactly.
    """

    center: tuple[float, float]
    rx: float
    ry: float
    rotation: float
    start_t: float
    end_t: float
    is_circle: bool = False

    @property
    def axes(self) -> FloatArray:
        c, s = np.cos(self.rotation), np.sin(self.rotation)
        return np.array([[c * self.rx, -s * self.ry], [s * self.rx, c * self.ry]])

    def at(self, t: FloatArray | float) -> FloatArray:
        t = np.asarray(t, dtype=float)
        unit = np.stack([np.cos(t), np.sin(t)], axis=-1)
        return np.asarray(self.center) + unit @ self.axes.T

    @property
    def start(self) -> tuple[float, float]:
        p = self.at(self.start_t)
        return float(p[0]), float(p[1])

    @property
    def end(self) -> tuple[float, float]:
        p = self.at(self.end_t)
        return float(p[0]), float(p[1])

    def pieces(self, source: int) -> list[Piece]:
        circle = (self.center[0], self.center[1], self.rx) if self.is_circle else None
        return conic_arc_pieces(np.asarray(self.center), self.axes, self.start_t, self.end_t, circle, source)

    def reversed(self) -> EllipseArc:
        return EllipseArc(self.center, self.rx, self.ry, self.rotation, self.end_t, self.start_t, self.is_circle)

    def moments(self) -> Moments:
        # The integrands are trigonometric polynomials of degree ≤ 3 in t: 8 samples
        # over a full period give their Fourier coefficients exactly.
        A = self.axes
        cx, cy = self.center

        def xy(t: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
            c, s = np.cos(t), np.sin(t)
            x = cx + A[0, 0] * c + A[0, 1] * s
            y = cy + A[1, 0] * c + A[1, 1] * s
            dx = -A[0, 0] * s + A[0, 1] * c
            dy = -A[1, 0] * s + A[1, 1] * c
            return x, y, dx, dy

        def f_a(t: FloatArray) -> FloatArray:
            x, _, _, dy = xy(t)
            return x * dy

        def f_sx(t: FloatArray) -> FloatArray:
            x, _, _, dy = xy(t)
            return 0.5 * x * x * dy

        def f_sy(t: FloatArray) -> FloatArray:
            _, y, dx, _ = xy(t)
            return -0.5 * y * y * dx

        return tuple(_trig_integral(f, self.start_t, self.end_t) for f in (f_a, f_sx, f_sy))  # type: ignore[return-value]

    def second_moments(self) -> tuple[float, float]:
        """(⅓∮ x³ dy, −⅓∮ y³ dx): trigonometric polynomials of degree 4, exact."""
        A, (cx, cy) = self.axes, self.center

        def f_xx(t: FloatArray) -> FloatArray:
            c, s = np.cos(t), np.sin(t)
            x = cx + A[0, 0] * c + A[0, 1] * s
            return x**3 * (-A[1, 0] * s + A[1, 1] * c) / 3.0

        def f_yy(t: FloatArray) -> FloatArray:
            c, s = np.cos(t), np.sin(t)
            y = cy + A[1, 0] * c + A[1, 1] * s
            return -(y**3) * (-A[0, 0] * s + A[0, 1] * c) / 3.0

        return _trig_integral(f_xx, self.start_t, self.end_t), _trig_integral(f_yy, self.start_t, self.end_t)

    def polyline(self, max_turn_rad: float) -> FloatArray:
        n = max(2, int(np.ceil(abs(self.end_t - self.start_t) / max_turn_rad)) + 1)
        return self.at(np.linspace(self.start_t, self.end_t, n))

    def to_dict(self) -> dict[str, object]:
        if self.is_circle:
            return {"type": "arc", "center": list(self.center), "radius": self.rx,
                    "start_deg": float(np.degrees(self.start_t)), "end_deg": float(np.degrees(self.end_t))}
        return {"type": "ellipse_arc", "center": list(self.center), "rx": self.rx, "ry": self.ry,
                "rotation_deg": float(np.degrees(self.rotation)),
                "start_deg": float(np.degrees(self.start_t)), "end_deg": float(np.degrees(self.end_t))}


def _trig_integral(f: object, t0: float, t1: float) -> float:
    """∫_{t0}^{t1} f for a trigonometric polynomial f of degree ≤ 4 (exact: 16 samples
    over a period give its Fourier coefficients without aliasing)."""
    n = 16
    ts = 2.0 * np.pi * np.arange(n) / n
    F = np.fft.rfft(f(ts))  # type: ignore[operator]
    total = float(F[0].real / n) * (t1 - t0)
    for k in range(1, 5):
        a = 2.0 * F[k].real / n
        b = -2.0 * F[k].imag / n
        total += a * (np.sin(k * t1) - np.sin(k * t0)) / k - b * (np.cos(k * t1) - np.cos(k * t0)) / k
    return total


@dataclass(frozen=True)
class Bezier:
    """A (rational) Bezier segment: control points (k+1, 2), weights (k+1,)."""

    points: FloatArray
    weights: FloatArray

    def __post_init__(self) -> None:
        object.__setattr__(self, "points", _readonly(self.points))
        object.__setattr__(self, "weights", _readonly(self.weights))

    @property
    def start(self) -> tuple[float, float]:
        return float(self.points[0, 0]), float(self.points[0, 1])

    @property
    def end(self) -> tuple[float, float]:
        return float(self.points[-1, 0]), float(self.points[-1, 1])

    @property
    def is_rational(self) -> bool:
        return bool(np.ptp(self.weights) > 0.0)

    @cached_property
    def _piece(self) -> Piece:
        return Piece(self.points, self.weights, None, -1)

    def piece(self, source: int = -1) -> Piece:
        """The exact piece (built once per segment)."""
        if source == -1:
            return self._piece
        return Piece(self.points, self.weights, None, source)

    def pieces(self, source: int) -> list[Piece]:
        return [self.piece(source)]

    def reversed(self) -> Bezier:
        return Bezier(self.points[::-1], self.weights[::-1])

    def moments(self) -> Moments:
        p = self._piece
        k = p.degree
        # Rational integrands: composite Gauss-Legendre (16 × 24 nodes), converged to
        # rounding for smooth low-degree curves. Polynomial: x² y′ has degree 3k − 1 and
        # n Gauss points integrate degree 2n − 1 exactly.
        t, w = gauss_legendre_01(24, 16) if self.is_rational else gauss_legendre_01((3 * k) // 2 + 1, 1)
        x, y, W = horner_rows(p.XYW, t)
        x, y = x / W, y / W
        tx, ty = horner_rows(p.TANGENTS[:2], t)
        dx, dy = tx / (W * W), ty / (W * W)
        return float(w @ (x * dy)), float(w @ (0.5 * x * x * dy)), float(w @ (-0.5 * y * y * dx))

    def second_moments(self) -> tuple[float, float]:
        """(⅓∮ x³ dy, −⅓∮ y³ dx): x³ y′ has degree 4k − 1, so 2k Gauss points are exact
        for polynomial curves; rational curves use the composite rule of :meth:`moments`."""
        p = self._piece
        t, w = gauss_legendre_01(24, 16) if self.is_rational else gauss_legendre_01(2 * p.degree + 1, 1)
        x, y, W = horner_rows(p.XYW, t)
        x, y = x / W, y / W
        tx, ty = horner_rows(p.TANGENTS[:2], t)
        return float(w @ (x**3 * ty / (W * W))) / 3.0, -float(w @ (y**3 * tx / (W * W))) / 3.0

    def polyline(self, max_turn_rad: float) -> FloatArray:
        return self._piece.point(np.linspace(0.0, 1.0, 8 * self.points.shape[0] + 1))

    def to_dict(self) -> dict[str, object]:
        out: dict[str, object] = {"type": "bezier", "points": self.points.tolist()}
        if self.is_rational:
            out["weights"] = self.weights.tolist()
        return out


Segment = Line | EllipseArc | Bezier
