"""Building blocks of the exact hull: convex pieces of a loop, candidate points on the
exact curves, and straight edges solved and verified against every piece.

Used by :mod:`algrasp.geometry.hull`; split out to keep each module readable.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from algrasp.errors import GeometryError
from algrasp.geometry.angles import TWO_PI
from algrasp.geometry.bank import IntArray, coefficient_stack, normal_angles, points
from algrasp.geometry.curves import FloatArray, Piece, horner_float, real_roots_in
from algrasp.geometry.segments import Line, Segment
from algrasp.geometry.tolerances import LENGTH_REL, PARAM_END, ROUNDING, ROUNDING_FINE, Tolerances

_SAMPLE_GRID = 33  # uniform parameters per piece before refining by turn
SLIDE_PARAM = 1e-6
"""A vertex contact slides this far (curve parameter) onto the adjacent curve; the edge
solver then finds the true tangency from there."""
OUTSIDE_REL = 1e-10
"""A hull edge is verified when no piece lies beyond it by more than this × the part's size."""
CUT_SPACING = 1e-4
"""A quadrant cut this close (curve parameter) to another cut is skipped (see _cuts)."""


# --------------------------------------------------------------------------- pieces


@dataclass(frozen=True, eq=False)
class Loop:
    """Convex pieces of a counter-clockwise loop and the vertices between them."""

    vertices: FloatArray  # (V, 2)
    pieces: tuple[Piece, ...]
    start_vertex: tuple[int, ...]
    end_vertex: tuple[int, ...]

    @cached_property
    def control_points(self) -> tuple[FloatArray, FloatArray]:
        """All pieces' control points stacked (M, 2) and the offset of each piece's first."""
        if not self.pieces:
            return np.zeros((0, 2)), np.zeros(0, dtype=int)
        sizes = [len(p.points) for p in self.pieces]
        return np.concatenate([p.points for p in self.pieces]), np.concatenate([[0], np.cumsum(sizes)[:-1]])

    @cached_property
    def vertex_list(self) -> list[tuple[float, float]]:
        """:attr:`vertices` as float pairs (for scalar work on the hull's corners)."""
        return [(x, y) for x, y in self.vertices.tolist()]

    @cached_property
    def coef(self) -> FloatArray:
        """Stacked coefficient rows (P, 7, L) of the pieces (:mod:`algrasp.geometry.bank`)."""
        return coefficient_stack(self.pieces)


def _convex_split(piece: Piece, size: float) -> list[Piece]:
    """Sub-pieces of ``piece`` that turn left, each with a tangent turn < 90°.

    Cuts at the roots of the curvature polynomial (inflections) and of the tangent's
    coordinates (quadrant changes); the curvature sign of each part is read from the
    parent's polynomial at the part's middle, so only kept parts are built. Scalar
    work is in plain floats: per-call numpy overhead would dominate these small degrees.
    """
    K = piece.curvature_list
    _, _, W, TX, TY = piece.lists
    inflections = [c for c in real_roots_in(K, 0.0, 1.0) if PARAM_END < c < 1.0 - PARAM_END]
    # Quadrant cuts only bound the turn of a piece; one a hair from another cut would
    # leave a sliver whose tangent is lost to cancellation, so those are skipped.
    edges = sorted({0.0, 1.0, *inflections})
    for c in sorted(real_roots_in(TX, 0.0, 1.0) + real_roots_in(TY, 0.0, 1.0)):
        if min(abs(c - e) for e in edges) > CUT_SPACING:
            edges = sorted([*edges, c])
    kept = []
    for a, b in zip(edges[:-1], edges[1:]):
        m = 0.5 * (a + b)
        speed = math.hypot(horner_float(TX, m), horner_float(TY, m))
        if speed == 0.0:
            continue
        kappa = horner_float(K, m) * horner_float(W, m) ** 2 / speed**3
        if kappa * size > LENGTH_REL:  # left turn; straight or right-turning parts never touch the hull
            kept.append(piece.restrict(a, b))
    return kept


def build_loop(boundary: list[Segment], size: float) -> Loop:
    verts: list[tuple[float, float]] = []
    pieces: list[Piece] = []
    starts: list[int] = []
    ends: list[int] = []
    if all(isinstance(seg, Line) for seg in boundary):  # polygons: the vertices are the starts
        return Loop(np.array([seg.start for seg in boundary]), (), (), ())
    close = ROUNDING * size

    def vertex(p: FloatArray | tuple[float, float]) -> int:
        # Consecutive copies of one point are one vertex, so pieces link up.
        if verts and math.hypot(verts[-1][0] - p[0], verts[-1][1] - p[1]) <= close:
            return len(verts) - 1
        if verts and math.hypot(verts[0][0] - p[0], verts[0][1] - p[1]) <= close:
            return 0
        verts.append((float(p[0]), float(p[1])))
        return len(verts) - 1

    for i, seg in enumerate(boundary):
        vertex(seg.start)
        for raw in seg.pieces(i):
            for p in _convex_split(raw, size):
                # A Bezier piece interpolates its end control points (exact).
                starts.append(vertex(p.points[0]))
                ends.append(vertex(p.points[-1]))
                pieces.append(p)
    return Loop(np.array(verts), tuple(pieces), tuple(starts), tuple(ends))


def _samples(coef: FloatArray, max_turn: float) -> tuple[IntArray, FloatArray]:
    """Interior parameters of all pieces (stacked rows ``coef``, (P, 7, L)) with a tangent
    turn of about ≤ max_turn between them: 33 uniform parameters per piece, then each
    cell that turns more is subdivided evenly (the normal is monotone on a piece, so the
    turn per cell is known). One batch for all pieces.

    Returns (piece index, parameter) of every sample, grouped by piece in order.
    """
    u = np.linspace(0.0, 1.0, _SAMPLE_GRID)
    ang = normal_angles(coef, np.broadcast_to(u, (coef.shape[0], u.size)))
    turn = np.diff(np.unwrap(ang, axis=1), axis=1)
    k = np.maximum(np.ceil(np.abs(turn) / max_turn).astype(int), 1).ravel()
    cell = np.repeat(np.arange(k.size), k)
    j = np.arange(cell.size) - np.repeat(np.cumsum(k) - k, k)
    c = cell % (_SAMPLE_GRID - 1)
    t = u[c] + (u[c + 1] - u[c]) * j / k[cell]
    interior = (c > 0) | (j > 0)  # each piece's t = 0 is its start vertex
    return cell[interior] // (_SAMPLE_GRID - 1), t[interior]


# --------------------------------------------------------------------------- contacts

Contact = tuple[int, int, float]  # (vertex id or -1, piece id or -1, parameter)


def contact_xy(loop: Loop, c: Contact) -> tuple[float, float]:
    """The point of contact ``c``: a vertex, or a piece at its parameter."""
    if c[0] >= 0:
        return loop.vertex_list[c[0]]
    x, y = loop.pieces[c[1]].point(c[2]).tolist()
    return x, y


def contact_point(loop: Loop, c: Contact) -> FloatArray:
    """:func:`contact_xy` as an array (2,)."""
    return np.array(contact_xy(loop, c))


def _vertex_tangent(loop: Loop, a: FloatArray, pid: int, t_guess: float, size: float) -> float | None:
    p = loop.pieces[pid]
    roots = [t for t in real_roots_in(p.tangent_from_point_poly(a), 0.0, 1.0)
             if np.hypot(*(p.point(t) - a)) > LENGTH_REL * size]
    if not roots:
        return None
    return min(roots, key=lambda t: abs(t - t_guess))


def _frame(p: Piece, t: float) -> tuple[float, float, float, float, float, float, float]:
    """Point (x, y), tangent numerator (tx, ty), its derivative and W at t, in floats."""
    X, Y, W, _, _ = p.lists
    TX, TY, dTX, dTY = p.tangent_lists
    w = horner_float(W, t)
    return (horner_float(X, t) / w, horner_float(Y, t) / w, horner_float(TX, t), horner_float(TY, t),
            horner_float(dTX, t), horner_float(dTY, t), w)


def _bitangent(loop: Loop, fa: int, sa: float, fb: int, sb: float) -> tuple[float, float] | None:
    """Parameters (s, t) of the line touching pieces fa and fb: Newton on the 2×2
    system cross(T_a(s), e) = cross(T_b(t), e) = 0, e = B(t) − A(s), with the exact
    Jacobian (a point moves along its tangent T/W², so d e/ds = −T_a/W_a²)."""
    pa, pb = loop.pieces[fa], loop.pieces[fb]
    s, t = sa, sb
    for _ in range(40):
        ax, ay, tax, tay, dax, day, wa = _frame(pa, s)
        bx, by, tbx, tby, dbx, dby, wb = _frame(pb, t)
        ex, ey = bx - ax, by - ay
        f1, f2 = tax * ey - tay * ex, tbx * ey - tby * ex
        j11, j12 = dax * ey - day * ex, (tax * tby - tay * tbx) / (wb * wb)
        j21, j22 = -(tbx * tay - tby * tax) / (wa * wa), dbx * ey - dby * ex
        det = j11 * j22 - j12 * j21
        if det == 0.0 or not math.isfinite(det):
            break
        ds, dt = (f1 * j22 - f2 * j12) / det, (j11 * f2 - j21 * f1) / det
        s, t = s - ds, t - dt
        if abs(ds) + abs(dt) < ROUNDING_FINE:
            break
    # Judge the residual with unit tangents, as the hull's length tolerance does.
    if math.isfinite(s) and math.isfinite(t):
        ax, ay, tax, tay, _, _, _ = _frame(pa, s)
        bx, by, tbx, tby, _, _, _ = _frame(pb, t)
        ex, ey = bx - ax, by - ay
        r1 = abs(tax * ey - tay * ex) / math.hypot(tax, tay)
        r2 = abs(tbx * ey - tby * ex) / math.hypot(tbx, tby)
        if max(r1, r2) <= ROUNDING:
            return s, t
    return _alternating_bitangent(loop, fa, sa, fb, sb)


def _alternating_bitangent(loop: Loop, fa: int, sa: float, fb: int, sb: float) -> tuple[float, float] | None:
    """Bitangent by alternating tangents from a point (each a polynomial root): slower
    than Newton but robust when the two curves nearly share a tangent line."""
    pa, pb = loop.pieces[fa], loop.pieces[fb]
    for _ in range(200):
        rb = [t for t in real_roots_in(pb.tangent_from_point_poly(pa.point(sa)), 0.0, 1.0)]
        ra = [t for t in real_roots_in(pa.tangent_from_point_poly(pb.point(sb)), 0.0, 1.0)]
        if not ra or not rb:
            return None
        na, nb = min(ra, key=lambda t: abs(t - sa)), min(rb, key=lambda t: abs(t - sb))
        if abs(na - sa) + abs(nb - sb) < ROUNDING_FINE:
            return na, nb
        sa, sb = na, nb
    return sa, sb


def _snap(loop: Loop, c: Contact) -> Contact:
    """A contact at a piece end becomes the vertex there."""
    if c[0] >= 0:
        return c
    if c[2] <= ROUNDING:
        return (loop.start_vertex[c[1]], -1, 0.0)
    if c[2] >= 1.0 - ROUNDING:
        return (loop.end_vertex[c[1]], -1, 0.0)
    return c


def _solve_edge(loop: Loop, a: Contact, b: Contact, size: float) -> tuple[Contact, Contact]:
    """Exact tangent contacts of the straight edge from near ``a`` to near ``b``."""
    if a[0] < 0 and b[0] < 0:
        st = _bitangent(loop, a[1], a[2], b[1], b[2])
        if st is not None and -PARAM_END <= st[0] <= 1 + PARAM_END and -PARAM_END <= st[1] <= 1 + PARAM_END:
            return _snap(loop, (-1, a[1], min(max(st[0], 0.0), 1.0))), _snap(loop, (-1, b[1], min(max(st[1], 0.0), 1.0)))
        a = _snap(loop, (-1, a[1], float(np.clip(round(a[2]), 0, 1))))
    if a[0] >= 0 and b[0] < 0:
        t = _vertex_tangent(loop, loop.vertices[a[0]], b[1], b[2], size)
        return a, _snap(loop, (-1, b[1], t)) if t is not None else _snap(loop, (-1, b[1], float(round(b[2]))))
    if a[0] < 0 and b[0] >= 0:
        t = _vertex_tangent(loop, loop.vertices[b[0]], a[1], a[2], size)
        return (_snap(loop, (-1, a[1], t)) if t is not None else _snap(loop, (-1, a[1], float(round(a[2]))))), b
    return a, b


def _worst_outside(loop: Loop, a: FloatArray, b: FloatArray) -> tuple[float, Contact]:
    """Largest distance of any vertex or piece beyond the line a→b, and where."""
    e = b - a
    n = np.array([e[1], -e[0]]) / np.hypot(*e)
    dv = (loop.vertices - a) @ n
    iv = int(np.argmax(dv))
    worst, where = float(dv[iv]), (iv, -1, 0.0)
    cps, offsets = loop.control_points
    if not len(cps):
        return worst, where
    bound = np.maximum.reduceat((cps - a) @ n, offsets.astype(np.intp))
    for k in np.nonzero(bound > worst)[0]:
        # Only pieces whose control polygon (which bounds the curve: positive weights)
        # reaches past the current worst need their exact extreme point.
        p = loop.pieces[int(k)]
        t = p.support_param(n)
        val = float((p.point(t) - a) @ n)
        if val > worst:
            worst, where = val, (-1, int(k), t)
    return worst, where


def _slide(loop: Loop, a: Contact, b: Contact, psi_edge: float) -> tuple[Contact, Contact] | None:
    """Move a vertex contact onto the curve ending (starting) there when the edge would
    turn back against that curve's end tangent — the true tangency is just inside it."""
    if a[0] >= 0:
        for k, v in enumerate(loop.end_vertex):
            if v == a[0] and _ahead(float(loop.pieces[k].normal_angle(1.0)), psi_edge):
                return (-1, k, 1.0 - SLIDE_PARAM), b
    if b[0] >= 0:
        for k, v in enumerate(loop.start_vertex):
            if v == b[0] and _ahead(psi_edge, float(loop.pieces[k].normal_angle(0.0))):
                return a, (-1, k, SLIDE_PARAM)
    return None


def _ahead(psi: float, other: float) -> bool:
    """Whether normal ψ lies strictly past ``other`` (counter-clockwise, within π)."""
    return (psi - other + np.pi) % TWO_PI - np.pi > ROUNDING


def verified_edge(loop: Loop, a: Contact, b: Contact, size: float) -> tuple[Contact, Contact]:
    """Solve the edge near contacts a, b and verify that no piece lies beyond it (within
    ``OUTSIDE_REL`` of the part's size); a contact at a vertex slides onto an adjacent curve when
    the edge would turn back against that curve's end tangent."""
    verified: tuple[Contact, Contact] | None = None
    for _ in range(12):
        a, b = _solve_edge(loop, a, b, size)
        pa, pb = contact_point(loop, a), contact_point(loop, b)
        worst, where = _worst_outside(loop, pa, pb)
        if worst <= OUTSIDE_REL * size:
            verified = (a, b)
            d = pb - pa
            slid = _slide(loop, a, b, float(np.arctan2(-d[0], d[1])))
            if slid is None:
                return a, b
            a, b = slid
            continue
        x = contact_point(loop, where)
        along = float((x - pa) @ (pb - pa)) / float((pb - pa) @ (pb - pa))
        if along < 0.5:
            a = where
        else:
            b = where
    if verified is not None:
        # Sliding never settled (two curves nearly share a tangent); the edge is within
        # the length tolerance of the hull and the normals are clamped when assembled.
        return verified
    raise GeometryError(f"could not resolve a hull edge near ({pa[0]:.6g}, {pa[1]:.6g})")


def candidate_points(loop: Loop, tol: Tolerances) -> tuple[FloatArray, list[list[tuple[int, int]]], list[Contact]]:
    """Exact curve points to locate the hull: vertices, then samples of every piece.

    Returns the points (N, 2), for each the (piece, sample index) memberships that
    link consecutive hull points along a piece, and the initial contact of each.
    Memberships and contacts are lazy sequences: only hull points are ever asked.
    """
    n_v = len(loop.vertices)
    vmembers: list[list[tuple[int, int]]] = [[] for _ in range(n_v)]
    if not loop.pieces:
        empty = np.zeros(0, dtype=int)
        return loop.vertices, _Members(n_v, vmembers, empty, empty), _Contacts(n_v, empty, np.zeros(0))  # type: ignore[return-value]
    owner, param = _samples(loop.coef, tol.hull_sample_turn_rad)
    counts = np.bincount(owner, minlength=len(loop.pieces))
    j = np.arange(owner.size) - np.repeat(np.cumsum(counts) - counts, counts) + 1
    for k, n in enumerate(counts.tolist()):
        vmembers[loop.start_vertex[k]].append((k, 0))
        vmembers[loop.end_vertex[k]].append((k, n + 1))
    pts = points(loop.coef, owner, param)
    owner = np.concatenate([np.full(n_v, -1), owner])
    return (np.concatenate([loop.vertices, pts]), _Members(n_v, vmembers, owner, np.concatenate([np.zeros(n_v, dtype=int), j])),  # type: ignore[return-value]
            _Contacts(n_v, owner, np.concatenate([np.zeros(n_v), param])))


class _Members:
    """members[k]: (piece, sample index) pairs of candidate point k."""

    def __init__(self, n_v: int, vmembers: list[list[tuple[int, int]]], owner: IntArray, j: IntArray) -> None:
        self.n_v, self.vmembers, self.owner, self.j = n_v, vmembers, owner, j

    def __getitem__(self, k: int) -> list[tuple[int, int]]:
        return self.vmembers[k] if k < self.n_v else [(int(self.owner[k]), int(self.j[k]))]


class _Contacts:
    """contacts[k]: the initial contact of candidate point k."""

    def __init__(self, n_v: int, owner: IntArray, param: FloatArray) -> None:
        self.n_v, self.owner, self.param = n_v, owner, param

    def __getitem__(self, k: int) -> Contact:
        return (int(k), -1, 0.0) if k < self.n_v else (-1, int(self.owner[k]), float(self.param[k]))


