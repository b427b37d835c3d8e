"""Building blocks of the exact hull: convex pieces of a loop, candidate points on the
exact curves, and straight edges solved and verified against every piece.

Used by :mod:`algrasp.geometry.hull`; split out to keep each module readable.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from algrasp.errors import GeometryError
from algrasp.geometry.angles import TWO_PI
from algrasp.geometry.bank import IntArray, coefficient_stack, normal_angles, points
from algrasp.geometry.curves import FloatArray, Piece, horner_float, real_roots_in
from algrasp.geometry.lazy import cached_property
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


@dataclass(frozen=True, slots=True)
class Contact:
    """Where a hull edge touches the loop: vertex ``vertex`` of the loop, or piece
    ``piece`` at parameter ``t`` (exactly one of ``vertex`` and ``piece`` is set)."""

    vertex: int | None = None
    piece: int | None = None
    t: float = 0.0

    @property
    def piece_id(self) -> int:
        """:attr:`piece`, for a contact on a piece."""
        if self.piece is None:
            raise ValueError(f"{self} is not on a piece")
        return self.piece


def contact_xy(loop: Loop, c: Contact) -> tuple[float, float]:
    """The point of contact ``c``: a vertex, or a piece at its parameter."""
    if c.vertex is not None:
        return loop.vertex_list[c.vertex]
    x, y = loop.pieces[c.piece_id].point(c.t).tolist()
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


class _Frame(NamedTuple):
    """A piece at one parameter, in floats: point, tangent numerator T, its derivative T′, weight W."""

    x: float
    y: float
    tx: float
    ty: float
    dtx: float
    dty: float
    w: float


def _frame(p: Piece, t: float) -> _Frame:
    """The :class:`_Frame` of piece ``p`` at ``t``."""
    X, Y, W, _, _ = p.lists
    TX, TY, dTX, dTY = p.tangent_lists
    w = horner_float(W, t)
    return _Frame(horner_float(X, t) / w, horner_float(Y, t) / w, horner_float(TX, t), horner_float(TY, t),
                  horner_float(dTX, t), horner_float(dTY, t), w)


def _newton_step(a: _Frame, b: _Frame) -> tuple[float, float] | None:
    """The Newton step (ds, dt) of :func:`_bitangent` at frames a, b; None when singular."""
    ex, ey = b.x - a.x, b.y - a.y
    f1, f2 = a.tx * ey - a.ty * ex, b.tx * ey - b.ty * ex
    j11, j12 = a.dtx * ey - a.dty * ex, (a.tx * b.ty - a.ty * b.tx) / (b.w * b.w)
    j21, j22 = -(b.tx * a.ty - b.ty * a.tx) / (a.w * a.w), b.dtx * ey - b.dty * ex
    det = j11 * j22 - j12 * j21
    if det == 0.0 or not math.isfinite(det):
        return None
    return (f1 * j22 - f2 * j12) / det, (j11 * f2 - j21 * f1) / det


def _tangent_residual(a: _Frame, b: _Frame) -> float:
    """How far the line a→b is from tangent to both pieces, with unit tangents (as the length tolerance)."""
    ex, ey = b.x - a.x, b.y - a.y
    r1 = abs(a.tx * ey - a.ty * ex) / math.hypot(a.tx, a.ty)
    r2 = abs(b.tx * ey - b.ty * ex) / math.hypot(b.tx, b.ty)
    return max(r1, r2)


def _bitangent(loop: Loop, fa: int, sa: float, fb: int, sb: float) -> tuple[float, float] | None:
    """Parameters (s, t) of the line touching pieces fa and fb: Newton on the 2×2
    system cross(T_a(s), e) = cross(T_b(t), e) = 0, e = B(t) − A(s), with the exact
    Jacobian (a point moves along its tangent T/W², so d e/ds = −T_a/W_a²)."""
    pa, pb = loop.pieces[fa], loop.pieces[fb]
    s, t = sa, sb
    for _ in range(40):
        step = _newton_step(_frame(pa, s), _frame(pb, t))
        if step is None:
            break
        ds, dt = step
        s, t = s - ds, t - dt
        if abs(ds) + abs(dt) < ROUNDING_FINE:
            break
    if math.isfinite(s) and math.isfinite(t) and _tangent_residual(_frame(pa, s), _frame(pb, t)) <= ROUNDING:
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
    if c.piece is None:
        return c
    if c.t <= ROUNDING:
        return Contact(vertex=loop.start_vertex[c.piece])
    if c.t >= 1.0 - ROUNDING:
        return Contact(vertex=loop.end_vertex[c.piece])
    return c


def _tangent_from(loop: Loop, v: int, c: Contact, size: float) -> Contact:
    """Contact on ``c``'s piece of the tangent from vertex ``v`` (or the nearest end of the piece)."""
    t = _vertex_tangent(loop, loop.vertices[v], c.piece_id, c.t, size)
    return _snap(loop, Contact(piece=c.piece_id, t=t if t is not None else float(round(c.t))))


def _solve_edge(loop: Loop, a: Contact, b: Contact, size: float) -> tuple[Contact, Contact]:
    """Exact tangent contacts of the straight edge from near ``a`` to near ``b``."""
    if a.piece is not None and b.piece is not None:
        st = _bitangent(loop, a.piece, a.t, b.piece, b.t)
        if st is not None and -PARAM_END <= st[0] <= 1 + PARAM_END and -PARAM_END <= st[1] <= 1 + PARAM_END:
            s, t = (min(max(x, 0.0), 1.0) for x in st)
            return _snap(loop, Contact(piece=a.piece, t=s)), _snap(loop, Contact(piece=b.piece, t=t))
        a = _snap(loop, Contact(piece=a.piece, t=float(np.clip(round(a.t), 0, 1))))
    if a.vertex is not None and b.vertex is None:
        return a, _tangent_from(loop, a.vertex, b, size)
    if a.vertex is None and b.vertex is not None:
        return _tangent_from(loop, b.vertex, a, size), b
    return a, b


def _worst_outside(loop: Loop, a: FloatArray, b: FloatArray) -> tuple[float, Contact]:
    """Largest distance of any vertex or piece beyond the line a→b, and where."""
    e = b - a
    n = np.array([e[1], -e[0]]) / np.hypot(*e)
    dv = (loop.vertices - a) @ n
    iv = int(np.argmax(dv))
    worst, where = float(dv[iv]), Contact(vertex=iv)
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
            worst, where = val, Contact(piece=int(k), t=t)
    return worst, where


def _slide(loop: Loop, a: Contact, b: Contact, psi_edge: float) -> tuple[Contact, Contact] | None:
    """Move a vertex contact onto the curve ending (starting) there when the edge would
    turn back against that curve's end tangent — the true tangency is just inside it."""
    if a.vertex is not None:
        for k, v in enumerate(loop.end_vertex):
            if v == a.vertex and _ahead(float(loop.pieces[k].normal_angle(1.0)), psi_edge):
                return Contact(piece=k, t=1.0 - SLIDE_PARAM), b
    if b.vertex is not None:
        for k, v in enumerate(loop.start_vertex):
            if v == b.vertex and _ahead(psi_edge, float(loop.pieces[k].normal_angle(0.0))):
                return a, Contact(piece=k, t=SLIDE_PARAM)
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


@dataclass(frozen=True, eq=False)
class Candidates:
    """Exact curve points that locate the hull (:func:`candidate_points`): the loop's
    vertices, then samples of every piece. Only hull points are ever asked for their
    memberships and contacts, so those are built on demand."""

    points: FloatArray  # (N, 2)
    n_v: int  # the first n_v points are the vertices
    vmembers: list[list[tuple[int, int]]]  # (piece, sample index) pairs of each vertex
    owner: IntArray  # (N,) piece of each sample (-1 at the vertices)
    index: IntArray  # (N,) index of each sample along its piece
    param: FloatArray  # (N,) parameter of each sample

    def members(self, k: int) -> list[tuple[int, int]]:
        """(piece, sample index) pairs of point k, which link consecutive hull points along a piece."""
        return self.vmembers[k] if k < self.n_v else [(int(self.owner[k]), int(self.index[k]))]

    def contact(self, k: int) -> Contact:
        """The initial contact of point k."""
        return Contact(vertex=int(k)) if k < self.n_v else Contact(piece=int(self.owner[k]), t=float(self.param[k]))


def candidate_points(loop: Loop, tol: Tolerances) -> Candidates:
    """The :class:`Candidates` of ``loop``: its vertices, then samples of every piece."""
    n_v = len(loop.vertices)
    vmembers: list[list[tuple[int, int]]] = [[] for _ in range(n_v)]
    if not loop.pieces:
        empty = np.zeros(0, dtype=int)
        return Candidates(loop.vertices, n_v, vmembers, empty, empty, np.zeros(0))
    owner, param = _samples(loop.coef, tol.hull_sample_turn_rad)
    counts = np.bincount(owner, minlength=len(loop.pieces))
    j = np.arange(owner.size) - np.repeat(np.cumsum(counts) - counts, counts) + 1
    for k, n in enumerate(counts.tolist()):
        vmembers[loop.start_vertex[k]].append((k, 0))
        vmembers[loop.end_vertex[k]].append((k, n + 1))
    pts = points(loop.coef, owner, param)
    return Candidates(np.concatenate([loop.vertices, pts]), n_v, vmembers, np.concatenate([np.full(n_v, -1), owner]),
                      np.concatenate([np.zeros(n_v, dtype=int), j]), np.concatenate([np.zeros(n_v), param]))
