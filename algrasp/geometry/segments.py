"""Boundary segments of a part document as immutable value objects.

Each segment knows its end points, its exact :class:`~algrasp.geometry.curves.Piece` form, its
Green's-theorem moments (for area and centre of mass) and a polyline used only for
validity checks and drawings — never for the analysis.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.polynomial import legendre

from algrasp.geometry.angles import to_deg
from algrasp.geometry.curves import (
    FloatArray,
    Piece,
    _readonly,
    bernstein_values,
    conic_arc_pieces,
    homogeneous,
    horner_float,
    real_roots_in,
)
from algrasp.geometry.lazy import cached_property
from algrasp.geometry.tolerances import PARAM_END


@lru_cache(maxsize=32)
def gauss_legendre_01(n: int, panels: int) -> tuple[FloatArray, FloatArray]:
    """Nodes and weights of composite n-point Gauss-Legendre on [0, 1] (``panels`` panels).
    Cached: the arrays are read-only and shared."""
    nodes, wts = legendre.leggauss(n)
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

    def _trace(self, t: FloatArray, origin: tuple[float, float]) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """x, y (relative to ``origin``), dx/dt, dy/dt at parameters t."""
        A, (cx, cy) = self.axes, self.center
        c, s = np.cos(t), np.sin(t)
        return ((cx - origin[0]) + A[0, 0] * c + A[0, 1] * s, (cy - origin[1]) + A[1, 0] * c + A[1, 1] * s,
                -A[0, 0] * s + A[0, 1] * c, -A[1, 0] * s + A[1, 1] * c)

    def moments(self, origin: tuple[float, float] = (0.0, 0.0)) -> tuple[float, float, float, float, float]:
        """Green's integrals (∮ x dy, ½∮ x² dy, −½∮ y² dx, ⅓∮ x³ dy, −⅓∮ y³ dx) of
        x, y measured from ``origin``: trigonometric polynomials of degree ≤ 4, exact."""
        def f(t: FloatArray) -> FloatArray:
            x, y, dx, dy = self._trace(t, origin)
            return np.stack([x * dy, 0.5 * x * x * dy, -0.5 * y * y * dx, x**3 * dy / 3.0, -(y**3) * dx / 3.0])

        a, sx, sy, ixx, iyy = _trig_integral(f, self.start_t, self.end_t)
        return a, sx, sy, ixx, iyy

    def polyline(self, max_turn_rad: float) -> FloatArray:
        n = max(2, int(np.ceil(abs(self.end_t - self.start_t) / max_turn_rad)) + 1)
        return self.at(np.linspace(self.start_t, self.end_t, n))

    def to_dict(self) -> dict[str, object]:
        if self.is_circle:
            return {"type": "arc", "center": list(self.center), "radius": self.rx,
                    "start_deg": float(to_deg(self.start_t)), "end_deg": float(to_deg(self.end_t))}
        return {"type": "ellipse_arc", "center": list(self.center), "rx": self.rx, "ry": self.ry,
                "rotation_deg": float(to_deg(self.rotation)),
                "start_deg": float(to_deg(self.start_t)), "end_deg": float(to_deg(self.end_t))}


def _trig_integral(f: Callable[[FloatArray], FloatArray], t0: float, t1: float) -> list[float]:
    """∫_{t0}^{t1} of each row of f, trigonometric polynomials of degree ≤ 4 (exact: 16
    samples over a period give their Fourier coefficients without aliasing)."""
    n = 16
    F = np.fft.rfft(f(2.0 * np.pi * np.arange(n) / n), axis=-1)
    total = F[..., 0].real / n * (t1 - t0)
    for k in range(1, 5):
        a = 2.0 * F[..., k].real / n
        b = -2.0 * F[..., k].imag / n
        total = total + a * (np.sin(k * t1) - np.sin(k * t0)) / k - b * (np.cos(k * t1) - np.cos(k * t0)) / k
    return [float(v) for v in total]


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

    def split(self, t: float) -> tuple[Bezier, Bezier]:
        """The two halves at parameter ``t`` (de Casteljau on homogeneous points): exact."""
        h = np.hstack([self.points * self.weights[:, None], self.weights[:, None]])
        left, right = [h[0]], [h[-1]]
        while len(h) > 1:
            h = (1.0 - t) * h[:-1] + t * h[1:]
            left.append(h[0])
            right.append(h[-1])
        lh, rh = np.array(left), np.array(right[::-1])
        return (Bezier(lh[:, :2] / lh[:, 2:], lh[:, 2] / lh[:, 2].max()),
                Bezier(rh[:, :2] / rh[:, 2:], rh[:, 2] / rh[:, 2].max()))

    def cusps(self) -> list[float]:
        """Parameters in (0, 1) where the curve stops and turns back (its tangent vanishes):
        a corner of the outline in the middle of a segment, which the hull must see.
        Complexity: one polynomial root search."""
        _, _, _, TX, TY = self._piece.lists
        speed = max(abs(c) for c in TX + TY) or 1.0
        cuts: list[float] = []
        for t in real_roots_in(TX, PARAM_END, 1.0 - PARAM_END):  # a cusp is a double root: once
            if abs(horner_float(TY, t)) <= CUSP_REL * speed and (not cuts or t - cuts[-1] > PARAM_END):
                cuts.append(t)
        return cuts

    def to_dict(self) -> dict[str, object]:
        out: dict[str, object] = {"type": "bezier", "points": self.points.tolist()}
        if self.is_rational:
            out["weights"] = self.weights.tolist()
        return out


Segment = Line | EllipseArc | Bezier

CUSP_REL = 1e-9
"""A tangent shorter than this, relative to the tangent polynomial's size, vanishes (a cusp)."""


def split_cusps(loop: Sequence[Segment]) -> list[Segment]:
    """The loop with every Bezier split at its cusps, so each cusp is a vertex."""
    out: list[Segment] = []
    for seg in loop:
        rest = seg
        cuts = seg.cusps() if isinstance(seg, Bezier) else []
        done = 0.0
        for t in cuts:
            assert isinstance(rest, Bezier)
            head, rest = rest.split((t - done) / (1.0 - done))
            out.append(head)
            done = t
        out.append(rest)
    return out


def loop_polyline(loop: Sequence[Segment], max_turn_rad: float) -> tuple[FloatArray, list[FloatArray]]:
    """A closed polyline through the loop, for validity checks and drawings only.

    Returns all points (N, 2) (each segment without its end point, which is the next
    one's start) and the per-segment parts. Bezier segments get 8(k + 1) chords each,
    evaluated for all segments of one degree in a single batch.
    """
    parts: list[FloatArray | None] = [None] * len(loop)
    groups: dict[int, list[int]] = {}
    for i, seg in enumerate(loop):
        if isinstance(seg, Bezier):
            groups.setdefault(seg.points.shape[0] - 1, []).append(i)
        else:
            parts[i] = seg.polyline(max_turn_rad)[:-1]
    for degree, idx in groups.items():
        basis = bernstein_values(degree, np.linspace(0.0, 1.0, 8 * (degree + 1) + 1)[:-1])
        hom = np.stack([homogeneous(loop[i].points, loop[i].weights) for i in idx])  # type: ignore[union-attr]
        H = np.einsum("nk,skc->snc", basis, hom)
        pts = H[..., :2] / H[..., 2:]
        for j, i in enumerate(idx):
            parts[i] = pts[j]
    done = [p for p in parts if p is not None]
    return np.concatenate(done), done
