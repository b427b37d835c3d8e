"""The faces of a drawing's arrangement (`algrasp.io.cad.arrange` builds the edges): every
half-edge walked once with the face on its left, so bounded faces run counter-clockwise;
each face becomes a loop of exact segments, with consecutive pieces of one entity merged
back into it, every vertex placed once (two lines meeting over a gap extended to their
corner) and arcs left exact (a bridging line where two arcs miss by a hair).
O(E log E) for E edges.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from algrasp.io.cad.chain import Segment, _bridge, point_at, reverse, ring
from algrasp.io.cad.split import is_closed_curve, leaving_angle, sub, t_range

KERF_AREA_REL = 0.01
"""A face touching the others only at vertices, with less than this share of the largest
face's area, is a kerf loop or overshoot of the outline, not a part."""
CORNER_REACH = 4.0
"""Two lines meeting over a gap are extended to their corner when it lies within this
many gap widths of their ends (else they meet at the gap's middle)."""
PARALLEL_SIN = 1e-3
"""Lines whose directions' sine is below this are parallel: they have no corner."""


@dataclass(frozen=True)
class Edge:
    """A piece of the arrangement: ``segment`` runs from vertex u to v and is the part
    [t0, t1] of piece ``piece``'s segment."""

    segment: Segment
    u: int
    v: int
    piece: int
    t0: float
    t1: float


@dataclass
class Arrangement:
    """The bounded faces (loops of exact segments, counter-clockwise, each segment with
    its ``_layer``), the connected component of each face, each component's outer
    boundary, and what was set aside or repaired (messages)."""

    faces: list[list[Segment]]
    component: list[int]
    outer: dict[int, list[Segment]]
    open_chains: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    chords: set[int] = field(default_factory=set)
    """Edges (indices into the edges given) with a bounded face on both sides."""
    neighbours: dict[int, set[int]] = field(default_factory=dict)
    """The faces (indices into ``faces``) sharing an edge with each face."""


class Union:
    def __init__(self, n: int) -> None:
        self.parent = list(range(n))

    def add(self) -> int:
        self.parent.append(len(self.parent))
        return len(self.parent) - 1

    def find(self, i: int) -> int:
        while self.parent[i] != i:
            self.parent[i] = self.parent[self.parent[i]]
            i = self.parent[i]
        return i

    def join(self, a: int, b: int) -> None:
        self.parent[self.find(a)] = self.find(b)


def faces(edges: list[Edge], segs: list[Segment]) -> Arrangement:
    """Walk every half-edge once; faces with positive area are the bounded ones."""
    out_at: dict[int, list[tuple[float, int]]] = {}
    for k, e in enumerate(edges):
        out_at.setdefault(e.u, []).append((leaving_angle(e.segment, False), 2 * k))
        out_at.setdefault(e.v, []).append((leaving_angle(e.segment, True), 2 * k + 1))
    order = {x: [h for _, h in sorted(hs)] for x, hs in out_at.items()}
    slot = {h: (x, i) for x, hs in order.items() for i, h in enumerate(hs)}
    face_of = [-1] * (2 * len(edges))
    walks: list[list[int]] = []
    for h0 in range(2 * len(edges)):
        if face_of[h0] >= 0:
            continue
        walk, h = [], h0
        while face_of[h] < 0:
            face_of[h] = len(walks)
            walk.append(h)
            x, i = slot[h ^ 1]  # the twin leaves the vertex this half-edge arrives at
            h = order[x][i - 1]  # the next one clockwise: the face stays on the left
        walks.append(walk)
    return _collect(walks, face_of, edges, segs)


Part = tuple[Segment, int, float, float, int, int]
"""A directed edge of a face: segment, piece, t0, t1, from-vertex, to-vertex."""


def _directed(e: Edge, h: int) -> Part:
    if h % 2 == 0:
        return e.segment, e.piece, e.t0, e.t1, e.u, e.v
    return reverse(e.segment), e.piece, e.t1, e.t0, e.v, e.u


def _positions(edges: list[Edge]) -> dict[int, np.ndarray]:
    """Where each vertex is: on an arc's or ellipse's exact end if one meets there; where
    two lines meeting over a gap cross, if near; else the mean of the ends."""
    ends: dict[int, list[tuple[Segment, bool]]] = {}
    for e in edges:
        ends.setdefault(e.u, []).append((e.segment, False))
        ends.setdefault(e.v, []).append((e.segment, True))
    out = {}
    for x, inc in ends.items():
        pts = np.array([point_at(sg, end) for sg, end in inc])
        exact = [p for (sg, _), p in zip(inc, pts) if sg["type"] in ("arc", "ellipse_arc")]
        spread = float(np.max(np.ptp(pts, axis=0)))
        if exact:
            out[x] = exact[0]
        elif spread == 0.0:
            out[x] = pts[0]
        else:
            corner = _corner(inc) if len(inc) == 2 else None
            ok = corner is not None and float(np.max(np.linalg.norm(pts - corner, axis=1))) <= CORNER_REACH * spread
            out[x] = corner if ok and corner is not None else pts.mean(axis=0)
    return out


def _corner(inc: list[tuple[Segment, bool]]) -> np.ndarray | None:
    """Where the lines through two line segments cross (None: not two lines, or parallel)."""
    if any(sg["type"] != "line" for sg, _ in inc):
        return None
    (a, _), (b, _) = inc
    p, r = np.asarray(a["start"], float), np.subtract(a["end"], a["start"])
    q, s = np.asarray(b["start"], float), np.subtract(b["end"], b["start"])
    den = float(r[0] * s[1] - r[1] * s[0])
    if abs(den) <= PARALLEL_SIN * float(np.linalg.norm(r) * np.linalg.norm(s)):
        return None
    t = float((q - p)[0] * s[1] - (q - p)[1] * s[0]) / den
    return np.asarray(p + t * r)


def _placed(seg: Segment, a: np.ndarray, b: np.ndarray) -> Segment:
    """A line or Bezier with its ends on the vertices; arcs stay exact."""
    if seg["type"] == "line":
        return {**seg, "start": [float(a[0]), float(a[1])], "end": [float(b[0]), float(b[1])]}
    if seg["type"] == "bezier":
        return {**seg, "points": [[float(a[0]), float(a[1])], *seg["points"][1:-1], [float(b[0]), float(b[1])]]}
    return seg


def _collect(walks: list[list[int]], face_of: list[int], edges: list[Edge], segs: list[Segment]) -> Arrangement:
    comp = Union(0)
    index: dict[int, int] = {}
    for e in edges:
        for x in (e.u, e.v):
            index.setdefault(x, comp.add())
        comp.join(index[e.u], index[e.v])
    directed = [[_directed(edges[h // 2], h) for h in w] for w in walks]
    area = [_signed_area([d[0] for d in parts]) for parts in directed]  # before _loop turns it the drawn way
    pos = _positions(edges)
    loops = [_loop(parts, segs, pos) for parts in directed]
    bounded = [f for f in range(len(walks)) if area[f] > 0.0]
    kerf = _kerf_faces(bounded, walks, face_of, area, edges, comp, index)
    out = Arrangement([], [], {})
    outer_area: dict[int, float] = {}
    slot: dict[int, int] = {}
    for f in range(len(walks)):
        c = comp.find(index[edges[walks[f][0] // 2].u])
        if f in kerf:
            continue
        if area[f] > 0.0:
            slot[f] = len(out.faces)
            out.faces.append(loops[f])
            out.component.append(c)
        elif c not in out.outer or area[f] < outer_area[c]:
            out.outer[c], outer_area[c] = loops[f], area[f]
    if kerf:
        out.notes.append(f"{len(kerf)} kerf loop(s) or overshoot(s) touching an outline at a point dropped")
    inner = {f for f in bounded if f not in kerf}
    out.chords = {k for k in range(len(edges)) if face_of[2 * k] in inner and face_of[2 * k + 1] in inner}
    for k in out.chords:
        a, b = face_of[2 * k], face_of[2 * k + 1]
        if a != b:
            out.neighbours.setdefault(slot[a], set()).add(slot[b])
            out.neighbours.setdefault(slot[b], set()).add(slot[a])
    return out


def _kerf_faces(bounded: list[int], walks: list[list[int]], face_of: list[int], area: list[float], edges: list[Edge],
                comp: Union, index: dict[int, int]) -> set[int]:
    """Bounded faces sharing no edge with another bounded face, in a component whose
    largest face is over 1/KERF_AREA_REL times larger."""
    bset = set(bounded)
    largest: dict[int, float] = {}
    comp_of = {f: comp.find(index[edges[walks[f][0] // 2].u]) for f in bounded}
    for f in bounded:
        largest[comp_of[f]] = max(largest.get(comp_of[f], 0.0), area[f])
    out = set()
    for f in bounded:
        shares = any(face_of[h ^ 1] in bset for h in walks[f])
        if not shares and area[f] < KERF_AREA_REL * largest[comp_of[f]]:
            out.add(f)
    return out


def _loop(parts: list[Part], segs: list[Segment], pos: dict[int, np.ndarray]) -> list[Segment]:
    """The face's segments: consecutive pieces of one entity merged back into it, started
    at the first-drawn entity and run the way it was drawn, ends on their vertices."""
    merged: list[Part] = []
    for seg, piece, t0, t1, u, v in parts:
        if merged and merged[-1][1] == piece and merged[-1][3] == t0 and not is_closed_curve(segs[piece]):
            _, _, s0, _, u, _ = merged.pop()
            seg, t0 = _whole_or_sub(segs[piece], s0, t1), s0
        merged.append((seg, piece, t0, t1, u, v))
    if len(merged) > 1 and merged[0][1] == merged[-1][1] and merged[-1][3] == merged[0][2]:
        _, piece, t0, _, u, _ = merged.pop()
        first = merged[0]
        merged[0] = (_whole_or_sub(segs[piece], t0, first[3]), piece, t0, first[3], u, first[5])
    k = min(range(len(merged)), key=lambda i: (merged[i][1], min(merged[i][2], merged[i][3])))
    a, b = t_range(segs[merged[k][1]])
    if (merged[k][3] - merged[k][2]) * (b - a) < 0:  # run the way the first-drawn entity was drawn…
        merged = [(reverse(sg), pc, t1, t0, v, u) for sg, pc, t0, t1, u, v in merged[::-1]]
        k = len(merged) - 1 - k
    merged = merged[k:] + merged[:k]  # …from its start: the same file gives the same document
    placed = [_placed(sg, pos[u], pos[v]) for sg, _, _, _, u, v in merged]
    loop = [placed[0]]
    for seg in placed[1:]:
        end = point_at(loop[-1], True)
        loop += [*_bridge(end, point_at(seg, False), seg), seg]
    return [*loop, *_bridge(point_at(loop[-1], True), point_at(loop[0], False), loop[0])]


def _whole_or_sub(s: Segment, t0: float, t1: float) -> Segment:
    a, b = t_range(s)
    if (t0, t1) == (a, b):
        return s
    if (t0, t1) == (b, a):
        return reverse(s)
    return sub(s, t0, t1)


def _signed_area(loop: list[Segment]) -> float:
    p = ring(loop)
    x, y = p[:, 0], p[:, 1]
    return float(0.5 * (np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))
