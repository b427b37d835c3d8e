"""Exact convex hull of a curved loop, as features ordered by outward-normal angle ψ.

The hull boundary is made of pieces of the original curves, vertices (corners) and
straight edges (segments of the boundary or bitangents). It is stored as the Gauss
map: a cyclic list of :class:`HullFeature` whose normal ranges ``[psi0, psi1]`` tile
S¹; straight edges are the breakpoints between consecutive features.

Method (n pieces, m hull features): the curves are split at inflections and at
quadrant changes of the tangent into convex pieces; points *on* the exact curves
(vertices and samples) locate the combinatorial hull (monotone chain, O(N log N)); every
straight edge is then solved exactly — vertex–curve tangents as polynomial roots,
curve–curve bitangents by Newton on the curve equations — and verified against every
piece (control-polygon bound, then the exact extreme point from a polynomial root).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TypeVar

import numpy as np

from algrasp.compiled import GEOMETRY
from algrasp.errors import GeometryError
from algrasp.geometry.angles import TWO_PI, to_deg
from algrasp.geometry.bank import FeatureTable, unit_vectors
from algrasp.geometry.curves import FloatArray, Piece
from algrasp.geometry.gauss import HullFeature
from algrasp.geometry.hull_loop import (
    Candidates,
    Contact,
    Loop,
    build_loop,
    candidate_points,
    contact_xy,
    verified_edge,
)
from algrasp.geometry.segments import Line, Segment, gauss_legendre_01
from algrasp.geometry.tolerances import HULL_TURN_RAD, ROUNDING, Tolerances


def unit(psi: FloatArray | float) -> FloatArray:
    """Unit vectors (cos ψ, sin ψ), shape (..., 2)."""
    if np.ndim(psi) == 0:
        return np.array([np.cos(psi), np.sin(psi)])
    return unit_vectors(np.asarray(psi, dtype=float))


@dataclass(frozen=True, eq=False)
class ConvexHull:
    """The exact hull: features sorted by ``psi0``, covering ``[psi0_first, +2π)``.

    Attributes:
        features: the Gauss-map features (read-only tuple).
        edges: straight edges as ((ax, ay), (bx, by)), counter-clockwise.
        perimeter: exact perimeter (edges + arc lengths; unit).
        table: the features as arrays, for vectorised support points.
    """

    features: tuple[HullFeature, ...]
    edges: tuple[tuple[tuple[float, float], tuple[float, float]], ...]
    perimeter: float
    table: FeatureTable

    @property
    def breakpoints(self) -> FloatArray:
        """Normal angles where the feature changes (the psi0 of each feature)."""
        return self.table.breakpoints

    def support(self, psi: float) -> float:
        """Support function h(ψ) = max over the part of ⟨p, u(ψ)⟩ (unit)."""
        return float(self.support_many(np.array([psi]))[0])

    def support_points(self, psi: FloatArray) -> FloatArray:
        """Support points for an array of normals ψ (shape (m,) → (m, 2)), in one
        vectorised pass over all features; O(m (log n + L))."""
        idx, x = self.table.feature_index(np.asarray(psi, dtype=float))
        return self.table.points(idx, x)

    def feature_points(self, i: int, psi: FloatArray) -> FloatArray:
        """Support points (m, 2) of feature ``i`` for normals ψ (m,) in its range."""
        psi = np.asarray(psi, dtype=float)
        return self.table.points(np.full(psi.shape, i, dtype=np.intp), psi)

    def support_many(self, psi: FloatArray) -> FloatArray:
        """h(ψ) for an array of normals, vectorised per feature; O(m log n)."""
        return self.table.support_of(psi)

    def inside_margin(self, p: FloatArray) -> float:
        """min over ψ of h(ψ) − ⟨p, u(ψ)⟩ at every feature end and 2,048 normals.

        Positive when ``p`` is inside the hull (a validity check; the radius function
        later finds the exact minimum).
        """
        psis = np.concatenate([self.breakpoints, np.linspace(0.0, TWO_PI, 2048, endpoint=False)])
        return float(np.min(self.support_many(psis) - unit(psis) @ p))

    def outline(self, step_rad: float = 0.02) -> FloatArray:
        """A closed polyline of the hull boundary for drawings only; shape (N, 2)."""
        pts = []
        for i, f in enumerate(self.features):
            n = 1 if f.kind == "point" else max(2, int(np.ceil((f.psi1 - f.psi0) / step_rad)) + 1)
            pts.append(self.feature_points(i, np.linspace(f.psi0, f.psi1, n)))
        out = np.concatenate(pts)
        return np.vstack([out, out[:1]])


# --------------------------------------------------------------------------- the walk

@dataclass(frozen=True, slots=True)
class EdgeElement:
    """A straight edge of the hull from ``a`` to ``b`` (counter-clockwise)."""

    a: tuple[float, float]
    b: tuple[float, float]


@dataclass(frozen=True, slots=True)
class CurveElement:
    """Piece ``piece`` of the loop between parameters ``s`` and ``e``."""

    piece: int
    s: float
    e: float


@dataclass(frozen=True, slots=True)
class PointElement:
    """A corner of the hull at ``xy``."""

    xy: tuple[float, float]


Element = EdgeElement | CurveElement | PointElement
"""One element of the hull boundary, in counter-clockwise order."""
Edges = tuple[tuple[tuple[float, float], tuple[float, float]], ...]
"""Straight hull edges ((ax, ay), (bx, by)), counter-clockwise."""
_T = TypeVar("_T")


def _link(ma: list[tuple[int, int]], mb: list[tuple[int, int]]) -> int | None:
    """Piece joining consecutive hull points along the curve, or None for a straight edge."""
    for pa, ja in ma:
        for pb, jb in mb:
            if pa == pb and jb > ja:
                return pa
    return None


def _dedupe(path: list[int]) -> list[int]:
    out: list[int] = []
    for p in path:
        if not out or out[-1] != p:
            out.append(p)
    return out


def _stretch(loop: Loop, path: list[int], cin: Contact, cout: Contact) -> list[Element]:
    """Elements from the end contact of one edge to the start contact of the next."""
    path = _dedupe(path)
    if cin.piece is not None and (not path or path[0] != cin.piece):
        path.insert(0, cin.piece)
    if cout.piece is not None and (not path or path[-1] != cout.piece):
        path.append(cout.piece)
    if not path:  # then cin is a vertex
        return [PointElement(contact_xy(loop, cin))]
    elems: list[Element] = []
    if cin.vertex is not None:
        elems.append(PointElement(loop.vertex_list[cin.vertex]))
    for idx, pid in enumerate(path):
        if idx > 0:
            elems.append(PointElement(loop.vertex_list[loop.start_vertex[pid]]))
        s = cin.t if idx == 0 and cin.piece == pid else 0.0
        e = cout.t if idx == len(path) - 1 and cout.piece == pid else 1.0
        elems.append(CurveElement(pid, s, e))
    if cout.vertex is not None:
        elems.append(PointElement(loop.vertex_list[cout.vertex]))
    return elems


def _elements(loop: Loop, order: list[int], links: list[int | None], cand: Candidates, size: float) -> list[Element]:
    h = len(order)
    edge_at = [i for i in range(h) if links[i] is None]
    if not edge_at:
        path = _dedupe([pid for pid in links if pid is not None])
        if len(path) > 1 and path[0] == path[-1]:
            path.pop()
        start = Contact(vertex=loop.start_vertex[path[0]])
        return _stretch(loop, path, start, start)[1:]
    solved = []
    for i in edge_at:
        a, b = cand.contact(order[i]), cand.contact(order[(i + 1) % h])
        solved.append(verified_edge(loop, a, b, size) if loop.pieces else (a, b))
    elems: list[Element] = []
    for k, i in enumerate(edge_at):
        nxt = edge_at[(k + 1) % len(edge_at)]
        span = range(i + 1, nxt if nxt > i else nxt + h)
        path = [pid for j in span if (pid := links[j % h]) is not None]  # none is: edges end a span
        cout = solved[(k + 1) % len(edge_at)][0]
        elems.extend(_stretch(loop, path, solved[k][1], cout))
        elems.append(EdgeElement(contact_xy(loop, cout), contact_xy(loop, solved[(k + 1) % len(edge_at)][1])))
    return elems


def _polygon_features(xy: list[tuple[float, float]], order: list[int], tol: Tolerances) -> tuple[list[HullFeature], Edges]:
    """:func:`_features` and the edges of a polygon's hull (vertices ``xy``, hull corners
    ``order``; every hull point a vertex, every link an edge) without elements: from the
    corner after the first, each corner then its edge. O(h)."""
    h = len(order)
    corners = [xy[order[(k + 1) % h]] for k in range(h)]
    edges = tuple((a, corners[(k + 1) % h]) for k, a in enumerate(corners))
    ranges = _corner_ranges if GEOMETRY is None else GEOMETRY.corner_ranges  # compiled: the same floats
    kept, last = ranges(corners, tol.sliver_rad)
    return [HullFeature.point(a, e, (float(c[0]), float(c[1]))) for c, a, e in _tiled(kept, last)], edges


def _corner_ranges(corners: list[tuple[float, float]], sliver: float) -> tuple[list[tuple[tuple[float, float], float]], float]:
    """The corners kept as features (wider than ``sliver`` in normals), each with its first
    normal, and the last one's end: :func:`_features`'s walk over corner k (normals from
    the edge before to its own) then its edge, the same float operations in the same order."""
    h = len(corners)
    psis = [math.atan2(a[0] - b[0], b[1] - a[1]) for a, b in zip(corners, [*corners[1:], corners[0]])]
    kept: list[tuple[tuple[float, float], float]] = []
    level = last = psis[-1]
    for k in range(h):
        psi = psis[k]
        a = level + max((psis[k - 1] - level + math.pi) % TWO_PI - math.pi, 0.0)  # the corner
        b = a + max((psi - a + math.pi) % TWO_PI - math.pi, 0.0)
        if b - a > sliver:
            kept.append((corners[k], a))
            last = b
        a = b + max((psi - b + math.pi) % TWO_PI - math.pi, 0.0)  # its edge
        level = a + max((psi - a + math.pi) % TWO_PI - math.pi, 0.0)
    return kept, last


def _own_normals(loop: Loop, el: Element) -> tuple[float, float] | None:
    """Normal range (ψ₀, ψ₁) of an edge (its normal) or a curve (its end normals); None for a point."""
    if isinstance(el, EdgeElement):
        psi = math.atan2(el.a[0] - el.b[0], el.b[1] - el.a[1])
        return psi, psi
    if isinstance(el, CurveElement):
        p = loop.pieces[el.piece]
        return float(p.normal_angle(el.s)), float(p.normal_angle(el.e))
    return None


def _element_normals(loop: Loop, elems: list[Element]) -> list[tuple[float, float]]:
    """Normal range (ψ₀, ψ₁) of each element: an edge's normal, a curve's end normals;
    a point spans from the element before it to the one after (cyclically). O(m)."""
    raw = [_own_normals(loop, el) for el in elems]
    ranges = [r for r in raw if r is not None]
    before: list[tuple[float, float]] = []  # the nearest range before each element
    last = ranges[-1]
    for r in raw:
        before.append(last)
        last = r or last
    out: list[tuple[float, float]] = [(0.0, 0.0)] * len(raw)
    after = ranges[0]  # the nearest range after, walking back
    for i in range(len(raw) - 1, -1, -1):
        r = raw[i]
        out[i] = r if r is not None else (before[i][1], after[0])
        after = r or after
    return out


def _feature(el: PointElement | CurveElement, a: float, b: float, pieces: tuple[Piece, ...]) -> HullFeature:
    """The feature of element ``el`` over the normals [a, b]."""
    if isinstance(el, PointElement):
        return HullFeature.point(a, b, (float(el.xy[0]), float(el.xy[1])))
    p = pieces[el.piece]
    if p.circle is not None:
        return HullFeature("circle", a, b, (p.circle[0], p.circle[1]), p.circle[2], p, el.s, el.e)
    return HullFeature("curve", a, b, (0.0, 0.0), 0.0, p, el.s, el.e)


def _features(loop: Loop, elems: list[Element], tol: Tolerances) -> list[HullFeature]:
    normals = _element_normals(loop, elems)
    kept: list[tuple[PointElement | CurveElement, float]] = []  # the elements with features, and their first normals
    level = last = normals[0][0]
    for el, (a, b) in zip(elems, normals):
        # Around a convex loop the normal only advances, by less than π at a corner; a
        # small apparent step back is a contact resolved within the length tolerance
        # on the wrong side of a curve's end, and is clamped.
        a = level + max((a - level + math.pi) % TWO_PI - math.pi, 0.0)
        b = a + max((b - a + math.pi) % TWO_PI - math.pi, 0.0)
        level = b
        if isinstance(el, EdgeElement) or b - a <= tol.sliver_rad:
            continue
        kept.append((el, a))
        last = b
    return [_feature(el, a, e, loop.pieces) for el, a, e in _tiled(kept, last)]


def _tiled(kept: list[tuple[_T, float]], last: float) -> list[tuple[_T, float, float]]:
    """The kept elements with their normal ranges tiling S¹ exactly (each ends where the
    next begins), given each one's first normal and the last one's end ``last``."""
    total = last - kept[0][1]
    if abs(total - TWO_PI) > HULL_TURN_RAD:
        raise GeometryError(f"hull normals cover {to_deg(total):.6f}° instead of 360°")
    ends = [a for _, a in kept[1:]] + [kept[0][1] + TWO_PI]
    return [(el, a, e) for (el, a), e in zip(kept, ends)]


def hull_order(pts: FloatArray | list[tuple[float, float]]) -> list[int]:
    """Indices of the corners of the convex hull of ``pts`` (N, 2), counter-clockwise,
    collinear (to rounding) and repeated points left out (Andrew's monotone chain,
    O(N log N)). It only locates the hull: the exact hull is verified against the curves
    afterwards. Written here rather than importing scipy.spatial's qhull, whose import
    alone cost the CLI 0.4 s."""
    xy = pts.tolist() if isinstance(pts, np.ndarray) else pts
    if GEOMETRY is not None:  # compiled: the same order (math.hypot where libm's products are too close to call)
        return GEOMETRY.hull_order(xy)  # type: ignore[no-any-return]
    idx = sorted(range(len(xy)), key=xy.__getitem__)  # by x, then y

    def chain(order: list[int]) -> list[int]:
        out: list[int] = []
        for i in order:
            while len(out) >= 2:
                (ax, ay), (bx, by), (cx, cy) = xy[out[-2]], xy[out[-1]], xy[i]
                # A left turn beyond rounding (sine of the turn > ROUNDING) keeps b.
                scale = math.hypot(bx - ax, by - ay) * math.hypot(cx - ax, cy - ay)
                if (bx - ax) * (cy - ay) - (by - ay) * (cx - ax) > ROUNDING * scale:
                    break
                out.pop()
            out.append(i)
        return out[:-1]

    return chain(idx) + chain(idx[::-1])


def exact_hull(boundary: list[Segment], size: float, tol: Tolerances) -> ConvexHull:
    """Exact convex hull of a counter-clockwise loop of segments.

    Complexity: O(N log N) for N located points (vertices plus ~10 samples per convex
    piece), plus O(E·n) for verifying E straight edges against n pieces.
    """
    if all(isinstance(seg, Line) for seg in boundary):  # a polygon: its candidates are its vertices
        xy = [(float(seg.start[0]), float(seg.start[1])) for seg in boundary]
        order = _corners(xy, len(xy))
        feats, edges = _polygon_features(xy, order, tol)
        return _hull(feats, edges)
    loop = build_loop(boundary, size)
    if not loop.pieces:  # no piece turns (straight Beziers): the vertices alone, as a polygon's
        return _hull(*_polygon_features(loop.vertex_list, _corners(loop.vertices, len(loop.vertices)), tol))
    cand = candidate_points(loop, tol)
    order = _corners(cand.points, len(cand.points))
    h = len(order)
    links = [_link(cand.members(order[i]), cand.members(order[(i + 1) % h])) for i in range(h)]
    elems = _elements(loop, order, links, cand, size)
    return _hull(_features(loop, elems, tol), tuple((e.a, e.b) for e in elems if isinstance(e, EdgeElement)))


def _corners(located: FloatArray | list[tuple[float, float]], count: int) -> list[int]:
    """:func:`hull_order` of the located points, refused when degenerate."""
    order = hull_order(located)
    if len(order) < 3:  # a cusp or a sliver drawn as a curve
        raise GeometryError(f"boundary: the convex hull is degenerate ({count} candidate points): is the part "
                            "a sliver or a curve with a cusp?")
    return order


def _hull(feats: list[HullFeature], edges: Edges) -> ConvexHull:
    """The hull of its features and straight edges: their table and exact perimeter."""
    table = FeatureTable.build(feats)
    perimeter = math.fsum(math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in edges)
    perimeter += sum(f.radius * (f.psi1 - f.psi0) for f in feats if f.kind == "circle")
    if any(f.kind == "curve" for f in feats):
        # Composite Gauss-Legendre (8 panels × 24 nodes) converges to rounding on these arcs.
        perimeter += float(np.sum(table.curve_lengths(*gauss_legendre_01(24, 8))))
    return ConvexHull(tuple(feats), edges, perimeter, table)
