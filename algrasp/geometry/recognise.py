"""What a drawing really means: exact circles in any form, and how far an approximated
curve may be from the part it stands for (conventions §7).

* :func:`as_exact_arc` — a rational Bezier segment (the exact NURBS form of a circle,
  degree-elevated or not) that lies on one circle *to rounding* is that circle's arc, and
  is analysed as an ``arc`` segment, so its ramps and steps are those of the arc.
* :func:`drawing_error` — the slope error σ of a drawing against the part it was made
  from: 0 for exact curves; for a cubic (polynomial) Bezier that approximates a circular
  arc, the largest slope of its radial ripple; for runs of short polygon edges that turn
  by a few degrees each (a tessellated curve: polyline exports, mesh projections), half
  the longest such edge. Both are bounds on how far the support function's derivative of
  the drawing can be from the real part's. Pure: no I/O. O(n) in the segment count.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from algrasp.geometry.angles import to_rad
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.segments import Bezier, EllipseArc, Line, Segment
from algrasp.geometry.tolerances import ROUNDING, TINY, Tolerances

_SAMPLES = 33
"""Points checked on a Bezier segment (ends included) for circle recognition."""
_MIN_ARC_SWEEP_RAD = to_rad(10.0)
"""Shortest sweep of a polynomial Bezier taken for an arc approximation."""
_RIPPLE_SAMPLES = 65
"""Points sampled along a cubic to measure its radial ripple against the fitted circle."""
_TURN_SLACK = 1e-9
"""Relative margin by which a turn from libm's atan2 must clear a limit for the comparison
to be decided without numpy's arctan2 (the two may differ in the last bit)."""


def _circle_through(a: FloatArray, b: FloatArray, c: FloatArray) -> tuple[FloatArray, float] | None:
    """Centre and radius of the circle through three points; None when collinear."""
    A, B = a - c, b - c
    d = 2.0 * (A[0] * B[1] - B[0] * A[1])
    scale = max(float(np.hypot(*A)), float(np.hypot(*B)), TINY)
    if abs(d) <= ROUNDING * scale * scale:
        return None
    a2, b2 = float(A @ A), float(B @ B)
    center = c + np.array([B[1] * a2 - A[1] * b2, A[0] * b2 - B[0] * a2]) / d
    return center, float(np.hypot(*(a - center)))


def _bezier_points(seg: Bezier, t: FloatArray) -> FloatArray:
    """Points of a (rational) Bezier at parameters t by de Casteljau on homogeneous points."""
    hom = np.column_stack([seg.points * seg.weights[:, None], seg.weights])
    work = np.repeat(hom[None, :, :], len(t), axis=0)
    tt = t[:, None, None]
    while work.shape[1] > 1:
        work = (1.0 - tt) * work[:, :-1] + tt * work[:, 1:]
    h = work[:, 0]
    return np.asarray(h[:, :2] / h[:, 2:])


def _fit(seg: Bezier, t: FloatArray) -> tuple[FloatArray, FloatArray, float] | None:
    """Samples, and the circle through the start, middle and end samples."""
    pts = _bezier_points(seg, t)
    circle = _circle_through(pts[0], pts[len(pts) // 2], pts[-1])
    if circle is None:
        return None
    return pts, circle[0], circle[1]


def _sweep(pts: FloatArray, center: FloatArray) -> float | None:
    """Signed angle swept from the first to the last sample; None unless monotone."""
    ang = np.unwrap(np.arctan2(pts[:, 1] - center[1], pts[:, 0] - center[0]))
    steps = np.diff(ang)
    if not (np.all(steps > 0.0) or np.all(steps < 0.0)) or np.max(np.abs(steps)) >= math.pi:
        return None
    return float(ang[-1] - ang[0])


def as_exact_arc(seg: Bezier, size: float, tol: Tolerances) -> EllipseArc | None:
    """The circular arc a rational Bezier segment exactly is, or None.

    Exact means every sample lies on the circle through the segment's start, middle and
    end within ``tol.circle_fit_rel`` × size (rounding of the written control points).
    Polynomial (non-rational) curves are never circles. O(degree · samples).

    >>> import numpy as np
    >>> from algrasp.geometry.tolerances import DEFAULT_TOLERANCES
    >>> quarter = Bezier(np.array([[1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]), np.array([1.0, 2 ** -0.5, 1.0]))
    >>> arc = as_exact_arc(quarter, 2.0, DEFAULT_TOLERANCES)
    >>> round(arc.rx, 12), round(float(np.degrees(arc.end_t - arc.start_t)), 9)
    (1.0, 90.0)
    """
    if not seg.is_rational or len(seg.points) < 3:
        return None
    return _arc_through(_bezier_points(seg, np.linspace(0.0, 1.0, _SAMPLES)), tol.circle_fit_rel * size)


def exact_circles(loop: Sequence[Segment], size: float, tol: Tolerances) -> list[Segment]:
    """The loop with every exactly circular rational Bezier replaced by its arc, and
    every ellipse arc with equal semi-axes (to rounding) marked circular."""
    out: list[Segment] = []
    for seg in loop:
        if isinstance(seg, Bezier):
            out.append(as_exact_arc(seg, size, tol) or seg)
        elif isinstance(seg, EllipseArc) and not seg.is_circle and abs(seg.rx - seg.ry) <= tol.circle_fit_rel * size:
            r = 0.5 * (seg.rx + seg.ry)
            out.append(EllipseArc(seg.center, r, r, 0.0, seg.start_t + seg.rotation, seg.end_t + seg.rotation, True))
        else:
            out.append(seg)
    return out


@dataclass(frozen=True)
class DrawingError:
    """How far a drawing may be from its part (conventions §7).

    Attributes:
        slope: σ per jaw — bound on |h′_drawing − h′_part| of the support function (part
            units per radian); the diameter's σ is twice this, the radius's once.
        value: bound on |h_drawing − h_part| (part units): the tolerance of symmetry.
        sources: what was recognised, for reports (``"12 tessellated vertices"``).
    """

    slope: float
    value: float
    sources: tuple[str, ...]


def drawing_error(loop: Sequence[Segment], tol: Tolerances) -> DrawingError:
    """σ and the value error of a boundary loop. See the module docs."""
    slope_p, value_p, n_vertices = _polyline_error(loop, tol)
    slope_c, value_c, n_cubics = _cubic_error(loop, tol)
    sources = []
    if n_vertices:
        sources.append(f"{n_vertices} tessellated vertices")
    if n_cubics:
        sources.append(f"{n_cubics} polynomial arc approximations")
    return DrawingError(max(slope_p, slope_c), max(value_p, value_c), tuple(sources))


def _polyline_error(loop: Sequence[Segment], tol: Tolerances) -> tuple[float, float, int]:
    """Runs of ≥ ``tol.tessellation_min_run`` line-line vertices turning by at most
    ``tol.tessellation_turn_rad``: the support point of the curve they approximate lies
    between the midpoints of the chords around the polygon's contact vertex, so the slope
    error is at most half the longest chord (an edge between two such vertices: a real
    flat next to a tessellated arc is exact); the value error is the sagitta, ℓ·β/8."""
    n = len(loop)
    if n < 3 or _no_small_run(loop, tol.tessellation_turn_rad, True, tol.tessellation_min_run):
        return 0.0, 0.0, 0
    turns = np.abs(_signed_turns(loop))
    small = turns <= tol.tessellation_turn_rad  # NaN (a curve beside the vertex) is never small
    if not small.any():  # no candidate vertex: no run, no chord (most parts)
        return 0.0, 0.0, 0
    keep = _long_runs(small, tol.tessellation_min_run)
    # Segment j joins vertices j − 1 and j: a chord of the curve when both are tessellated.
    chord = keep & np.concatenate([keep[-1:], keep[:-1]])
    if not chord.any():
        return 0.0, 0.0, 0
    seg_len = np.array([math.hypot(s.end[0] - s.start[0], s.end[1] - s.start[1]) if isinstance(s, Line) else 0.0
                        for s in loop])
    # A real flat between two tessellated arcs (a keyway, the flats of Fig. 11) is no chord.
    chord &= seg_len <= 2.0 * float(np.median(seg_len[chord]))
    longest = float(seg_len[chord].max())
    return 0.5 * longest, longest * float(turns[keep].max()) / 8.0, int(keep.sum())


def _long_runs(flags: np.ndarray, min_run: int) -> np.ndarray:
    """Cyclic runs of True at least ``min_run`` long, as a mask (isolated small turns are
    real kinks)."""
    out = np.zeros(len(flags), dtype=bool)
    for run in _run_list(flags, min_run):
        out[run] = True
    return out


def _cubic_error(loop: Sequence[Segment], tol: Tolerances) -> tuple[float, float, int]:
    """Polynomial Beziers within ``tol.arc_approximation_rel`` of a circular arc are arc
    approximations: σ is the largest slope of the radial ripple e(φ) = |p − c| − R against
    the polar angle (the support function moves by e′ to first order)."""
    slope = value = 0.0
    count = 0
    if not any(isinstance(seg, Bezier) for seg in loop):  # nothing to sample
        return slope, value, count
    t = np.linspace(0.0, 1.0, _RIPPLE_SAMPLES)
    coarse = np.linspace(0.0, 1.0, 9)
    for seg in loop:
        if not isinstance(seg, Bezier) or seg.is_rational or len(seg.points) < 3:
            continue
        quick = _fit(seg, coarse)  # most free-form pieces fail here, cheaply
        if quick is None or np.max(np.abs(np.hypot(*(quick[0] - quick[1]).T) - quick[2])) > tol.arc_approximation_rel * quick[2]:
            continue
        fit = _fit(seg, t)
        if fit is None:
            continue
        pts, center, radius = fit
        ripple = np.hypot(*(pts - center).T) - radius
        if np.max(np.abs(ripple)) > tol.arc_approximation_rel * radius:
            continue
        phi = np.unwrap(np.arctan2(pts[:, 1] - center[1], pts[:, 0] - center[0]))
        dphi = np.diff(phi)
        # An arc approximation sweeps a real angle monotonically (a nearly straight piece
        # fits a huge circle and proves nothing).
        if abs(phi[-1] - phi[0]) < _MIN_ARC_SWEEP_RAD or not (np.all(dphi > 0.0) or np.all(dphi < 0.0)):
            continue
        count += 1
        slope = max(slope, float(np.max(np.abs(np.diff(ripple) / dphi))))
        value = max(value, float(np.max(np.abs(ripple))))
    return slope, value, count


def _signed_turns(loop: Sequence[Segment]) -> FloatArray:
    """Signed turn at each vertex i (end of segment i); NaN unless both sides are lines.
    One array pass."""
    lines = [isinstance(seg, Line) for seg in loop]
    nan = (math.nan, math.nan)
    d = np.array([(seg.end[0] - seg.start[0], seg.end[1] - seg.start[1]) if line else nan for seg, line in zip(loop, lines)])
    e = np.concatenate([d[1:], d[:1]])  # the next segment's (np.roll, without its overhead)
    # The dot product written out, bit for bit np.sum's (+0.0: its sum starts from +0, so
    # −0 + −0 gives +0; atan2 tells the zeros apart).
    turns = np.arctan2(d[:, 0] * e[:, 1] - d[:, 1] * e[:, 0], d[:, 0] * e[:, 0] + d[:, 1] * e[:, 1] + 0.0)
    if all(lines):  # a polygon: every vertex joins two lines
        return np.asarray(turns)
    is_line = np.array(lines)
    return np.asarray(np.where(is_line & np.concatenate([is_line[1:], is_line[:1]]), turns, np.nan))


def _no_small_run(loop: Sequence[Segment], limit: float, zero_is_small: bool, min_run: int) -> bool:
    """Whether provably no cyclic run of ``min_run`` vertices of an all-line loop (nor all of
    them) turns by at most ``limit`` (by more than zero unless ``zero_is_small``) as
    :func:`_signed_turns` has it (numpy's arctan2 of the same cross and dot products): a
    vertex is certainly not small when its turn from math.atan2 clears the limit by
    ``_TURN_SLACK``, or its cross product is exactly zero (a turn of exactly 0 or π, the
    same from both). Then the tessellation checks find nothing. False when unsure, or not
    all lines. O(n) in plain floats."""
    if not all(isinstance(s, Line) for s in loop):
        return False
    bound = limit * (1.0 + _TURN_SLACK)
    maybe = []
    for seg, nxt in zip(loop, [*loop[1:], loop[0]]):
        d0, d1 = seg.end[0] - seg.start[0], seg.end[1] - seg.start[1]
        e0, e1 = nxt.end[0] - nxt.start[0], nxt.end[1] - nxt.start[1]
        cross, dot = d0 * e1 - d1 * e0, d0 * e0 + d1 * e1 + 0.0
        # atan2(±0, dot): ±π when dot < 0, else ±0.
        maybe.append(((math.pi <= bound) if dot < 0.0 else zero_is_small) if cross == 0.0
                     else abs(math.atan2(cross, dot)) <= bound)
    if all(maybe):
        return False
    first, run = maybe.index(False), 0
    for k in range(first + 1, first + len(maybe) + 1):
        run = run + 1 if maybe[k % len(maybe)] else 0
        if run >= min_run:
            return False
    return True


def _run_list(flags: np.ndarray, min_run: int) -> list[list[int]]:
    """Cyclic runs of True vertices, at least ``min_run`` long, as index lists."""
    n = len(flags)
    if flags.all():
        return [list(range(n))]
    start = int(np.argmin(flags))
    runs, run = [], []
    for k in range(1, n + 1):
        i = (start + k) % n
        if flags[i]:
            run.append(i)
        else:
            if len(run) >= min_run:
                runs.append(run)
            run = []
    return runs


def _arc_through(pts: FloatArray, residual: float | None = None, rel: float = 0.0) -> EllipseArc | None:
    """The circular arc through a chain of points (the circle through the first, middle
    and last), if every point is within ``residual`` (or ``rel`` × radius) of it and the
    points run round it monotonically."""
    circle = _circle_through(pts[0], pts[len(pts) // 2], pts[-1])
    if circle is None:
        return None
    center, radius = circle
    if np.max(np.abs(np.hypot(*(pts - center).T) - radius)) > (rel * radius if residual is None else residual):
        return None
    sweep = _sweep(pts, center)
    if sweep is None:
        return None
    start = math.atan2(pts[0, 1] - center[1], pts[0, 0] - center[0])
    return EllipseArc((float(center[0]), float(center[1])), radius, radius, 0.0, start, start + sweep, is_circle=True)


def snap_tessellations(loop: Sequence[Segment], tol: Tolerances) -> tuple[list[Segment], int]:
    """Runs of polygon edges that tessellate a circular arc (each vertex turning the same
    way by at most ``tol.snap_turn_rad``, all vertices on one circle) become that arc:
    the drawing's polygon stands for the circle (mesh projections, polyline exports).
    Returns the loop and how many arcs were recognised. O(n)."""
    n = len(loop)
    if _no_small_run(loop, tol.snap_turn_rad, False, tol.tessellation_min_run):  # most polygons: no array work
        return list(loop), 0
    turns = _signed_turns(loop)
    amount = np.abs(turns)
    small = (amount <= tol.snap_turn_rad) & (amount > 0.0)  # NaN (a curve beside the vertex) is neither
    if not small.any():  # no vertex turns by a tessellation's few degrees: nothing to snap
        return list(loop), 0
    whole = _tessellated_circle(loop, turns, tol) if small.all() else None
    if whole is not None:
        return whole, 1
    replace: dict[int, tuple[int, EllipseArc]] = {}  # first segment → (count, arc)
    for run in _run_list(small, tol.tessellation_min_run):
        if len(run) == n or len(set(np.sign(turns[run]))) != 1:
            continue
        segs = [run[0], *[(i + 1) % n for i in run]]
        pts = np.array([loop[segs[0]].start] + [loop[i].end for i in segs])
        arc = _arc_through(pts, rel=tol.arc_approximation_rel)
        if arc is not None:
            replace[segs[0]] = (len(segs), arc)
    if not replace:
        return list(loop), 0
    if any(f + c > n for f, (c, _) in replace.items()):
        return _rotate(loop, replace, n), len(replace)
    covered = {(first + k) % n for first, (count, _) in replace.items() for k in range(count)}
    out: list[Segment] = []
    for i in range(n):
        if i in replace:
            out.append(replace[i][1])
        elif i not in covered:
            out.append(loop[i])
    return out, len(replace)


def _tessellated_circle(loop: Sequence[Segment], turns: FloatArray, tol: Tolerances) -> list[Segment] | None:
    """A loop all of whose vertices turn the same way by a tessellation's few degrees as
    the circle it tessellates (two halves), when the vertices lie on one; else None."""
    if not np.all(np.sign(turns) == np.sign(turns[0])):
        return None
    n = len(loop)
    pts = np.array([seg.start for seg in loop] + [loop[0].start])
    rel = tol.arc_approximation_rel
    halves = [_arc_through(pts[: n // 2 + 1], rel=rel), _arc_through(pts[n // 2:], rel=rel)]
    return [h for h in halves if h is not None] if all(h is not None for h in halves) else None


def _rotate(loop: Sequence[Segment], replace: dict[int, tuple[int, EllipseArc]], n: int) -> list[Segment]:
    """Rebuild a loop whose replaced run wraps: start right after the wrapping run."""
    wrap = next(f for f, (c, _) in replace.items() if f + c > n)
    count, arc = replace[wrap]
    start = (wrap + count) % n
    out: list[Segment] = []
    i = start
    while i != wrap:
        if i in replace:
            out.append(replace[i][1])
            i = (i + replace[i][0]) % n
        else:
            out.append(loop[i])
            i = (i + 1) % n
    out.append(arc)
    return out
