"""The validated part: immutable, counter-clockwise, with exact area, centre of mass and hull.

``load_part(document)`` is the one entry point: it parses (``algrasp.geometry.document``),
checks closure, degeneracy and simplicity, orients the loop counter-clockwise and
computes the exact convex hull (``algrasp.geometry.hull``).
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import shapely
from shapely.geometry import LineString, Point, Polygon

from algrasp.compiled import GEOMETRY
from algrasp.errors import PartDocumentError
from algrasp.geometry.angles import to_rad
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.document import number, parse_loops
from algrasp.geometry.hull import ConvexHull, exact_hull
from algrasp.geometry.limits import DEFAULT_LIMITS, Limits
from algrasp.geometry.moments import loop_moments
from algrasp.geometry.recognise import exact_circles, snap_tessellations
from algrasp.geometry.segments import Bezier, Line, Segment, loop_polyline, split_cusps
from algrasp.geometry.tolerances import DEFAULT_TOLERANCES, Tolerances

_TESSELLATION_TURN_RAD = to_rad(2.0)  # only for the simplicity check, never for analysis


@dataclass(frozen=True)
class Part:
    """A validated planar part, as :func:`load_part` makes it (lengths in ``units``).

    Attributes
    ----------
    name, units : str
        From the document (units default ``"mm"``).
    boundary : tuple of Segment
        Segments of the outer loop, counter-clockwise.
    holes : tuple of tuple of Segment
        Segment loops of the holes, each clockwise.
    area : float
        Area of boundary minus holes (unit²).
    center_of_mass : tuple of float
        Given, or the area centroid (unit).
    com_given : bool
        Whether the document gave the centre of mass.
    size : float
        Diagonal of the bounding box of all control points (unit).
    hull : ConvexHull
        The exact convex hull of the boundary.
    source_document : Mapping[str, Any]
        The document as given (for records and replay).
    polar_moment : float
        ∬ |p − c|² dA over the region, about the centre of mass (unit⁴); times the areal
        density it is the rotational inertia.
    recognised : tuple of str
        What the robust model read into the drawing (tessellated arcs).

    Examples
    --------
    >>> from algrasp import load_part
    >>> part = load_part({"name": "r", "boundary": [[0, 0], [4, 0], [4, 2], [0, 2]]})
    >>> part.area, part.center_of_mass, part.com_given, round(part.polar_moment, 6), part.hull.perimeter
    (8.0, (2.0, 1.0), False, 13.333333, 12.0)
    """

    name: str
    units: str
    boundary: tuple[Segment, ...]
    holes: tuple[tuple[Segment, ...], ...]
    area: float
    center_of_mass: tuple[float, float]
    com_given: bool
    size: float
    hull: ConvexHull
    source_document: Mapping[str, Any]
    polar_moment: float
    recognised: tuple[str, ...] = ()


def load_part(doc: Mapping[str, Any], tol: Tolerances = DEFAULT_TOLERANCES, limits: Limits = DEFAULT_LIMITS,
              snap: bool = False) -> Part:
    """Validate a part document and build the :class:`Part`. Raises PartDocumentError.

    Rational Beziers and ellipse arcs that are exactly circular become arcs. With
    ``snap`` (the robust model) polygon runs that tessellate circular arcs become the
    arcs too (:func:`algrasp.geometry.recognise.snap_tessellations`); ``Part.recognised`` says so.
    """
    boundary, holes, recognised, size = _read_loops(doc, tol, limits, snap)
    field = "polygon" if "polygon" in doc else "boundary"
    _check_precision([boundary, *holes], size, field, tol)
    _check_loop(boundary, field, size, tol)
    for i, hole in enumerate(holes):
        _check_loop(hole, f"holes[{i}]", size, tol)
    # Moments about a point of the part: about the world origin a part far from it
    # loses digits to cancellation (see algrasp.geometry.moments).
    origin = boundary[0].start
    moments = loop_moments(boundary, origin)
    if abs(moments[0]) <= tol.zero_area_rel * size * size:
        raise PartDocumentError(field, f"the boundary encloses zero area ({moments[0]:.3g})")
    try:
        _check_simple(boundary, holes, field)
    except PartDocumentError:
        if not recognised:
            raise
        # The arcs read into a dense polygon cross where its vertices did not: the
        # drawing is analysed as drawn (a simple polygon is never refused for our reading).
        return load_part(doc, tol, limits, snap=False)
    if moments[0] < 0.0:
        boundary = [s.reversed() for s in reversed(boundary)]
        moments = -moments
    oriented_holes = []
    for hole in holes:
        hm = loop_moments(hole, origin)
        if hm[0] > 0.0:
            hole = [s.reversed() for s in reversed(hole)]
            hm = -hm
        moments = moments + hm
        oriented_holes.append(tuple(hole))
    area, sx, sy, ixx, iyy = (float(m) for m in moments)
    if area <= tol.zero_area_rel * size * size:
        raise PartDocumentError("holes", "the holes leave the part with zero area")
    hull = exact_hull(boundary, size, tol)
    com, given = _center_of_mass(doc, (origin[0] + sx / area, origin[1] + sy / area), hull)
    # ∬|p − c|² dA about the centre of mass c (given, or the centroid), from the moments about the origin.
    cx, cy = com[0] - origin[0], com[1] - origin[1]
    polar = ixx + iyy - 2.0 * (cx * sx + cy * sy) + area * (cx * cx + cy * cy)
    notes = (f"{recognised} tessellated arc(s) recognised as circular arcs",) if recognised else ()
    return Part(str(doc.get("name", "part")), str(doc.get("units", "mm")), tuple(boundary), tuple(oriented_holes),
                float(area), com, given, size, hull, doc, float(polar), notes)


def _read_loops(doc: Mapping[str, Any], tol: Tolerances, limits: Limits,
                snap: bool) -> tuple[list[Segment], list[list[Segment]], int, float]:
    """The document's boundary and holes as the analysis reads them, how many tessellated
    arcs were recognised (with ``snap``), and the size. A polygon without holes has no
    circle or cusp to find: the same loops, the size read once unless arcs were recognised."""
    boundary, holes = parse_loops(doc, limits)
    polygon = not holes and all(isinstance(seg, Line) for seg in boundary)
    drawn_size = _size([boundary, *holes])
    if not polygon:  # exact circles in any form (conventions §7): analysed as the arcs they are
        boundary = exact_circles(boundary, drawn_size, tol)
        holes = [exact_circles(h, drawn_size, tol) for h in holes]
        boundary, holes = split_cusps(boundary), [split_cusps(h) for h in holes]  # a cusp is a corner
    recognised = 0
    if snap:
        boundary, recognised = snap_tessellations(boundary, tol)
    return boundary, holes, recognised, drawn_size if polygon and not recognised else _size([boundary, *holes])


def _center_of_mass(doc: Mapping[str, Any], centroid: tuple[float, float],
                    hull: ConvexHull) -> tuple[tuple[float, float], bool]:
    """The given centre of mass (checked inside the hull), or the area centroid."""
    if "center_of_mass" not in doc:
        return (float(centroid[0]), float(centroid[1])), False
    raw = doc["center_of_mass"]
    if not isinstance(raw, (list, tuple)) or len(raw) != 2:
        raise PartDocumentError("center_of_mass", "expected a point [x, y]")
    com = (number(raw[0], "center_of_mass[0]"), number(raw[1], "center_of_mass[1]"))
    margin = hull.inside_margin(np.array(com))
    if margin <= 0.0:
        raise PartDocumentError("center_of_mass", f"({com[0]:g}, {com[1]:g}) lies outside the convex hull (by {-margin:.3g})")
    return com, True


def _check_precision(loops: list[list[Segment]], size: float, field: str, tol: Tolerances) -> None:
    """A part far smaller than its distance from the origin has no exact analysis in
    double precision (its coordinates differ in the last digits only)."""
    reach = max(max(abs(c) for c in s.start) for loop in loops for s in loop)
    if size < tol.position_rel * reach:
        raise PartDocumentError(field, f"the part ({size:.3g} across) lies {reach:.3g} from the origin: too small "
                                "for its position in double precision; move it near the origin")


def _size(loops: list[list[Segment]]) -> float:
    """Diagonal of the bounding box of all control points (arcs: their full circle).
    In plain floats: numpy's per-call cost outweighs a few points per segment."""
    if len(loops) == 1 and all(isinstance(seg, Line) for seg in loops[0]):  # a polygon: its vertices
        xs = [seg.start[0] for seg in loops[0]]
        ys = [seg.start[1] for seg in loops[0]]
        return math.hypot(max(xs) - min(xs), max(ys) - min(ys))
    xs = []
    ys = []
    for loop in loops:
        for seg in loop:
            if isinstance(seg, Line):
                xs.append(seg.start[0])
                ys.append(seg.start[1])
            elif isinstance(seg, Bezier):
                for x, y in seg.points.tolist():
                    xs.append(x)
                    ys.append(y)
            else:
                r = max(seg.rx, seg.ry)
                xs += [seg.center[0] - r, seg.center[0] + r]
                ys += [seg.center[1] - r, seg.center[1] + r]
    return math.hypot(max(xs) - min(xs), max(ys) - min(ys))


def _length(seg: Segment) -> float:
    """Length for the zero-length test: exact for lines and circular arcs, the control
    polygon's extent for Bezier curves (zero exactly when all control points coincide)."""
    if isinstance(seg, Line):
        return math.hypot(seg.end[0] - seg.start[0], seg.end[1] - seg.start[1])
    if isinstance(seg, Bezier):
        return float(np.hypot(*np.ptp(seg.points, axis=0)))
    return abs(seg.end_t - seg.start_t) * min(seg.rx, seg.ry)


def _check_loop(loop: list[Segment], field: str, size: float, tol: Tolerances) -> None:
    """Zero-length segments and gaps between consecutive segments."""
    shortest, widest = tol.zero_length_rel * size, tol.closure_rel * size
    for i, seg in enumerate(loop):
        length = _length(seg)
        if length <= shortest:
            raise PartDocumentError(f"{field}[{i}]", f"zero-length segment (length {length:.3g})", i)
    for i, seg in enumerate(loop):
        nxt = loop[(i + 1) % len(loop)]
        (ex, ey), (sx, sy) = seg.end, nxt.start
        gap = math.hypot(ex - sx, ey - sy)
        if gap > widest:
            j = (i + 1) % len(loop)
            raise PartDocumentError(f"{field}[{i}].end",
                                    f"open loop: gap of {gap:.6g} between the end of segment {i} and the start of segment {j}", i)


def _polyline(loop: list[Segment]) -> tuple[FloatArray, list[FloatArray] | None]:
    """The closed polyline's points and each segment's part of it (None for a polygon:
    its parts are its vertices, made only to explain an invalid loop)."""
    if all(isinstance(s, Line) for s in loop):
        return np.array([s.start for s in loop]), None
    return loop_polyline(loop, _TESSELLATION_TURN_RAD)


def _invalid(reason: str, shell: FloatArray, parts: list[FloatArray] | None, field: str) -> PartDocumentError:
    return PartDocumentError(field, _explain(reason, list(shell[:, None, :]) if parts is None else parts, field))


SIMPLE_RING_MAX_POINTS = 64
"""The compiled simplicity proof is O(n²) (every pair of edges) and GEOS's validity test
O(n log n) with ~10 µs of fixed cost: measured here they cross near 64 points (60: 10.4
against 11.4 µs; 1,000: 2.7 against 0.67 ms), so longer rings go straight to GEOS."""


def _check_simple(boundary: list[Segment], holes: list[list[Segment]], field: str) -> None:
    """Self-intersection of the boundary and holes (tessellated only for this test)."""
    shell, parts = _polyline(boundary)
    points = shell.tolist()
    if not _three_apart(points) and len({(round(x, 12), round(y, 12)) for x, y in points}) < 3:
        raise PartDocumentError(field, "the loop is degenerate: it has fewer than three distinct points")
    # Three distinct vertices joined by lines are a triangle, simple whenever its area is
    # not zero, which load_part checked first: GEOS's validity test could only confirm it;
    # so for a polygon the compiled kernel proves simple (sign-certain orientations).
    simple = parts is None and (len(points) == 3 or (GEOMETRY is not None and len(points) <= SIMPLE_RING_MAX_POINTS
                                                     and GEOMETRY.simple_ring(points)))
    reason = "Valid Geometry" if simple else shapely.is_valid_reason(shapely.polygons(shell))
    if reason != "Valid Geometry":
        raise _invalid(reason, shell, parts, field)
    rings = []
    for i, hole in enumerate(holes):
        ring, hparts = _polyline(hole)
        r = shapely.is_valid_reason(Polygon(ring))
        if r != "Valid Geometry":
            raise _invalid(r, ring, hparts, f"holes[{i}]")
        rings.append(ring)
    if rings:
        reason = shapely.is_valid_reason(Polygon(shell, rings))
        if reason != "Valid Geometry":
            raise PartDocumentError("holes", f"holes must lie inside the boundary without touching: {reason}")


_ROUNDED_APART = 1e-11
_ROUNDED_APART_REL = 1e-15
"""Coordinates farther apart than _ROUNDED_APART plus _ROUNDED_APART_REL of their size
round to different 12-digit values: round(x, 12) moves x by at most 0.5e-12 and half an ulp."""


def _three_apart(points: list[list[float]]) -> bool:
    """Whether the first three points surely stay three after rounding to 12 digits."""
    if len(points) < 3:
        return False
    (ax, ay), (bx, by), (cx, cy) = points[:3]
    return _apart(ax, ay, bx, by) and _apart(bx, by, cx, cy) and _apart(ax, ay, cx, cy)


def _apart(ax: float, ay: float, bx: float, by: float) -> bool:
    """Points a and b surely distinct after rounding each coordinate to 12 digits."""
    return (abs(ax - bx) > _ROUNDED_APART + _ROUNDED_APART_REL * (abs(ax) + abs(bx))
            or abs(ay - by) > _ROUNDED_APART + _ROUNDED_APART_REL * (abs(ay) + abs(by)))


def _explain(reason: str, parts: list[FloatArray], field: str) -> str:
    m = re.search(r"\[([-\d.eE+]+) ([-\d.eE+]+)\]", reason)
    if not m:
        return f"invalid loop: {reason}"
    p = Point(float(m.group(1)), float(m.group(2)))
    dists = []
    for i, seg_pts in enumerate(parts):
        nxt = parts[(i + 1) % len(parts)][:1]
        dists.append((LineString(np.vstack([seg_pts, nxt])).distance(p), i))
    near = sorted(i for d, i in sorted(dists)[:2])
    kind = "self-intersecting" if "Self-intersection" in reason or "Ring" in reason else "invalid"
    return f"{kind} boundary near ({p.x:.6g}, {p.y:.6g}): segments {near[0]} and {near[1]} of {field}"
