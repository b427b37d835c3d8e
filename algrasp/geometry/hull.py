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
from typing import Any

import numpy as np

from algrasp.errors import GeometryError
from algrasp.geometry.angles import TWO_PI, to_deg
from algrasp.geometry.bank import FeatureTable, unit_vectors
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.gauss import HullFeature
from algrasp.geometry.hull_loop import (
    Contact,
    Loop,
    build_loop,
    candidate_points,
    contact_xy,
    verified_edge,
)
from algrasp.geometry.segments import Segment, gauss_legendre_01
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
        idx, x = self.table.feature_index(np.asarray(psi, dtype=float))
        return self.table.support(idx, x)

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

_Element = tuple[Any, ...]  # ("edge", a, b) | ("curve", pid, s, e) | ("point", (x, y))


def _link(ma: list[tuple[int, int]], mb: list[tuple[int, int]]) -> int:
    """Piece joining consecutive hull points along the curve, or -1 for a straight edge."""
    for pa, ja in ma:
        for pb, jb in mb:
            if pa == pb and jb > ja:
                return pa
    return -1


def _dedupe(path: list[int]) -> list[int]:
    out: list[int] = []
    for p in path:
        if not out or out[-1] != p:
            out.append(p)
    return out


def _stretch(loop: Loop, path: list[int], cin: Contact, cout: Contact) -> list[_Element]:
    """Elements from the end contact of one edge to the start contact of the next."""
    path = _dedupe(path)
    if cin[1] >= 0 and (not path or path[0] != cin[1]):
        path.insert(0, cin[1])
    if cout[1] >= 0 and (not path or path[-1] != cout[1]):
        path.append(cout[1])
    if not path:
        return [("point", loop.vertex_list[cin[0]])]
    elems: list[_Element] = []
    if cin[0] >= 0:
        elems.append(("point", loop.vertex_list[cin[0]]))
    for idx, pid in enumerate(path):
        if idx > 0:
            elems.append(("point", loop.vertex_list[loop.start_vertex[pid]]))
        s = cin[2] if idx == 0 and cin[1] == pid else 0.0
        e = cout[2] if idx == len(path) - 1 and cout[1] == pid else 1.0
        elems.append(("curve", pid, s, e))
    if cout[0] >= 0:
        elems.append(("point", loop.vertex_list[cout[0]]))
    return elems


def _elements(loop: Loop, order: list[int], links: list[int], contacts: list[Contact], size: float) -> list[_Element]:
    h = len(order)
    edge_at = [i for i in range(h) if links[i] < 0]
    if not edge_at:
        path = _dedupe([links[i] for i in range(h)])
        if len(path) > 1 and path[0] == path[-1]:
            path.pop()
        return _stretch(loop, path, (loop.start_vertex[path[0]], -1, 0.0), (loop.start_vertex[path[0]], -1, 0.0))[1:]
    solved = []
    for i in edge_at:
        a, b = contacts[order[i]], contacts[order[(i + 1) % h]]
        solved.append(verified_edge(loop, a, b, size) if loop.pieces else (a, b))
    elems: list[_Element] = []
    for k, i in enumerate(edge_at):
        nxt = edge_at[(k + 1) % len(edge_at)]
        span = range(i + 1, nxt if nxt > i else nxt + h)
        path = [links[j % h] for j in span]
        cout = solved[(k + 1) % len(edge_at)][0]
        elems.extend(_stretch(loop, path, solved[k][1], cout))
        elems.append(("edge", contact_xy(loop, cout), contact_xy(loop, solved[(k + 1) % len(edge_at)][1])))
    return elems


def _element_normals(loop: Loop, elems: list[_Element]) -> list[tuple[float, float]]:
    """Normal range (ψ₀, ψ₁) of each element: an edge's normal, a curve's end normals;
    a point spans from the element before it to the one after (cyclically). O(m)."""
    raw: list[tuple[float, float] | None] = []
    for el in elems:
        if el[0] == "edge":
            psi = math.atan2(el[1][0] - el[2][0], el[2][1] - el[1][1])
            raw.append((psi, psi))
        elif el[0] == "curve":
            p = loop.pieces[el[1]]
            raw.append((float(p.normal_angle(el[2])), float(p.normal_angle(el[3]))))
        else:
            raw.append(None)
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


def _features(loop: Loop, elems: list[_Element], tol: Tolerances) -> list[HullFeature]:
    normals = _element_normals(loop, elems)
    specs: list[tuple[Any, ...]] = []  # HullFeature's fields, psi1 still the element's own
    level = normals[0][0]
    for el, (a, b) in zip(elems, normals):
        # Around a convex loop the normal only advances, by less than π at a corner; a
        # small apparent step back is a contact resolved within the length tolerance
        # on the wrong side of a curve's end, and is clamped.
        a = level + max((a - level + math.pi) % TWO_PI - math.pi, 0.0)
        b = a + max((b - a + math.pi) % TWO_PI - math.pi, 0.0)
        level = b
        if el[0] == "edge" or b - a <= tol.sliver_rad:
            continue
        if el[0] == "point":
            specs.append(("point", a, b, (float(el[1][0]), float(el[1][1])), 0.0, None, 0.0, 1.0))
            continue
        p = loop.pieces[el[1]]
        if p.circle is not None:
            specs.append(("circle", a, b, (p.circle[0], p.circle[1]), p.circle[2], p, el[2], el[3]))
        else:
            specs.append(("curve", a, b, (0.0, 0.0), 0.0, p, el[2], el[3]))
    total = specs[-1][2] - specs[0][1]
    if abs(total - TWO_PI) > HULL_TURN_RAD:
        raise GeometryError(f"hull normals cover {to_deg(total):.6f}° instead of 360°")
    # Tile S¹ exactly: each range ends where the next begins.
    ends = [f[1] for f in specs[1:]] + [specs[0][1] + TWO_PI]
    return [HullFeature(k, a, e, c, r, p, s0, s1) for (k, a, _, c, r, p, s0, s1), e in zip(specs, ends)]


def hull_order(pts: FloatArray) -> list[int]:
    """Indices of the corners of the convex hull of ``pts`` (N, 2), counter-clockwise,
    collinear (to rounding) and repeated points left out (Andrew's monotone chain,
    O(N log N)). It only locates the hull: the exact hull is verified against the curves
    afterwards. Written here rather than importing scipy.spatial's qhull, whose import
    alone cost the CLI 0.4 s."""
    xy = pts.tolist()
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
    loop = build_loop(boundary, size)
    pts, members, contacts = candidate_points(loop, tol)
    order = hull_order(pts)
    if len(order) < 3:  # a cusp or a sliver drawn as a curve
        raise GeometryError(f"boundary: the convex hull is degenerate ({len(pts)} candidate points): is the part "
                            "a sliver or a curve with a cusp?")
    h = len(order)
    links = [_link(members[order[i]], members[order[(i + 1) % h]]) for i in range(h)]
    elems = _elements(loop, order, links, contacts, size)
    feats = _features(loop, elems, tol)
    edges = tuple((e[1], e[2]) for e in elems if e[0] == "edge")
    table = FeatureTable.build(feats)
    perimeter = math.fsum(math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in edges)
    perimeter += sum(f.radius * (f.psi1 - f.psi0) for f in feats if f.kind == "circle")
    if any(f.kind == "curve" for f in feats):
        # Composite Gauss-Legendre (8 panels × 24 nodes) converges to rounding on these arcs.
        perimeter += float(np.sum(table.curve_lengths(*gauss_legendre_01(24, 8))))
    return ConvexHull(tuple(feats), edges, perimeter, table)  # type: ignore[arg-type]
