"""A drawing's entities as a planar arrangement, and its faces as closed loops.

Nesting software and draughtsmen share lines: two parts cut along one common line, a
title block drawn onto its frame, a rectangle's side overlapping its neighbour's. A walk
that uses each entity once closes at most one of the parts meeting there; faces of an
arrangement close all of them. The steps, each O(n log n) in the entities (KD-trees and a
shapely STRtree), and every curve kept exact (`algrasp.io.cad.split`):

1. ends closer than the join tolerance are one vertex;
2. an end lying on another entity's interior splits that entity there (T-junctions,
   shared and overlapping stretches); crossings are split only between cut lines across
   (both ends on other entities: a sheet cut into a grid) — centre lines and marks cross
   outlines everywhere, and crossing outlines are parts drawn over each other;
3. duplicated and near-duplicated entities (start, middle and end points within
   tolerance: two half-circles on the same ends are different entities) are merged;
4. free ends are joined over small gaps judged locally: a gap up to ``GAP_CHAIN_REL`` of
   the length of the chains meeting there (outlines 0.035 mm short of closing close; a
   dimension line 0.6 mm off its outline does not);
5. chains with a free end are set aside (centre, construction, dimension lines);
6. the bounded faces, walked with the face on the left (counter-clockwise), are the
   loops; a tiny face touching the rest only at a vertex is a kerf loop and dropped.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from algrasp.geometry.tolerances import DEFAULT_TOLERANCES
from algrasp.io.cad.chain import Piece, Segment, point_at, samples
from algrasp.io.cad.faces import Arrangement, Edge, Union, faces
from algrasp.io.cad.gaps import close_gaps, snap_to_corners
from algrasp.io.cad.split import at, is_closed_curve, length, midpoint, project, sub, t_range

JOIN_REL = 1e-6
"""Ends closer than this share of the drawing's size are one point (CAD programs write
coordinates to 6–16 digits)."""
GAP_CHAIN_REL = 2e-3
"""A free end joins another free end (or an entity it stops short of) over a gap up to
this share of the shorter chain meeting there: 0.035 mm on a 20 mm outline."""
GAP_MAX_REL = 2e-3
"""…and never over more than this share of the drawing's size."""
DUP_REL = 1e-3
"""Entities whose start, middle and end points lie within this share of their length of
another's are the same entity drawn twice (concentric circles 0.009 mm apart on a 6 mm
hole)."""
SAMPLE_SLACK_REL = 1e-4
"""How far (share of the drawing's size) a sampled curve may lie from the exact one: the
STRtree is queried this much wider, the exact distance decides."""


def _canonical(s: Segment) -> Segment:
    """A full circle or ellipse starts at parameter 0 and runs counter-clockwise, so two
    copies drawn from different start angles are recognised as one."""
    if is_closed_curve(s):
        return {**s, "start_deg": 0.0, "end_deg": 360.0}
    return s


def arrange(pieces: Sequence[Piece], size: float, tolerance: float | None = None) -> Arrangement:
    """The arrangement's faces (see module docs). ``tolerance`` (drawing units) replaces
    both the join tolerance and the local gap rule when given."""
    segs = [{**_canonical(p.segment), "_layer": p.layer} for p in pieces]
    origins = [p.origin for p in pieces]
    tight = tolerance if tolerance is not None else JOIN_REL * size
    ends = np.array([point_at(s, e) for s in segs for e in (False, True)]).reshape(-1, 2)
    uf = Union(len(ends))
    _join_close(ends, tight, uf)
    allowance = _allowances(segs, ends, uf, tight, size, tolerance is not None, [p.reach for p in pieces])
    edges, notes = _split_at_ends(segs, ends, allowance, tight, size, uf)
    edges, dup_notes = _deduplicate(edges, tight, uf, segs)
    notes += dup_notes
    notes += close_gaps(edges, ends, allowance, uf)
    edges = [Edge(e.segment, uf.find(e.u), uf.find(e.v), e.piece, e.t0, e.t1) for e in edges]
    edges, degenerate = _without_degenerate(edges, size)
    out, open_chains = _faces_without_strays(edges, segs, origins, allowance)
    if degenerate:
        out.notes.append(f"{degenerate} degenerate loop(s) set aside (no area: a segment shorter than the join "
                         "tolerance closes on itself)")
    out.notes[:0] = notes
    out.open_chains = open_chains
    return out


def _faces_without_strays(edges: list[Edge], segs: list[Segment], origins: list[str],
                          allowance: np.ndarray) -> tuple[Arrangement, list[str]]:
    """Faces after open chains are pruned. An open chain that runs through two points of
    an outline (a construction line snapped to its corners) would be left as a chord
    cutting the part in two: chords of entities that lost a dangling piece are removed
    too, and the faces walked again."""
    kept, open_chains = _prune(edges, origins, allowance)
    out = faces(kept, segs)
    alive = {id(e) for e in kept}
    pruned = {e.piece for e in edges if id(e) not in alive}
    stray = {k for k in out.chords if kept[k].piece in pruned}
    if not stray:
        return out, open_chains
    rest, more = _prune([e for k, e in enumerate(kept) if k not in stray], origins, allowance)
    out = faces(rest, segs)
    out.notes.append(f"{len(stray)} stray stretch(es) of open lines across parts set aside")
    return out, open_chains + more


def _join_close(ends: np.ndarray, tol: float, uf: Union) -> None:
    from scipy.spatial import cKDTree

    for a, b in cKDTree(ends).query_pairs(tol):
        uf.join(int(a), int(b))


def _chain_lengths(segs: list[Segment], uf: Union, n_ends: int) -> dict[int, float]:
    """Total length of each tight-joined chain, keyed by the root of any of its ends."""
    comp = Union(n_ends)
    for i in range(len(segs)):
        comp.join(uf.find(2 * i), uf.find(2 * i + 1))
    total: dict[int, float] = {}
    for i, s in enumerate(segs):
        r = comp.find(uf.find(2 * i))
        total[r] = total.get(r, 0.0) + length(s)
    return {e: total[comp.find(uf.find(e))] for e in range(n_ends)}


def _allowances(segs: list[Segment], ends: np.ndarray, uf: Union, tight: float, size: float,
                fixed: bool, reach: Sequence[float]) -> np.ndarray:
    """How far each end may reach: the join tolerance, or for a free end (no other end at
    its point) the local gap allowance of its chain, or half its drawn stroke's width when
    that is more (an SVG whose 0.13 mm strokes overlap across a 0.017 mm gap shows the
    outline closed, and a laser's kerf closes it); never more than ``GAP_MAX_REL``."""
    out = np.full(len(ends), tight)
    if fixed:
        return out
    degree: dict[int, int] = {}
    for e in range(len(ends)):
        degree[uf.find(e)] = degree.get(uf.find(e), 0) + 1
    chain_len = _chain_lengths(segs, uf, len(ends))
    for e in range(len(ends)):
        if degree[uf.find(e)] == 1 and not is_closed_curve(segs[e // 2]):
            out[e] = max(tight, min(max(GAP_CHAIN_REL * chain_len[e], reach[e // 2]), GAP_MAX_REL * size))
    return out


def _split_at_ends(segs: list[Segment], ends: np.ndarray, allowance: np.ndarray, tight: float, size: float,
                   uf: Union) -> tuple[list[Edge], list[str]]:
    """Every entity split where another entity's end lies on its interior (within that
    end's allowance); the split point becomes one vertex with that end."""
    import shapely
    from shapely.strtree import STRtree

    lines = [shapely.LineString(samples(s)) if len(samples(s)) >= 2 else shapely.Point(point_at(s, False))
             for s in segs]
    tree = STRtree(lines)
    pts = shapely.points(ends)
    hits = tree.query(pts, predicate="dwithin", distance=allowance + SAMPLE_SLACK_REL * size)
    snapped = snap_to_corners(ends, allowance, tight, uf, hits[0], hits[1])
    cuts: dict[int, list[tuple[float, int]]] = {}
    for e, j, t, dist in _on_interiors(segs, ends, allowance, tight, hits[0], hits[1]):
        if dist <= allowance[e]:
            cuts.setdefault(j, []).append((t, e))
    n = sum(len(v) for v in cuts.values())
    crossings = _crossings(segs, lines, tree, _attached(segs, cuts), tight, uf, cuts)
    edges: list[Edge] = []
    for i, s in enumerate(segs):
        edges += _cut(s, i, sorted(cuts.get(i, [])), uf)
    notes = [f"{n} entity end(s) lie on another entity (shared or common cut lines): split there"] if n else []
    if snapped:
        notes.append(f"{snapped} free end(s) joined to a corner of another outline they stop short of")
    if crossings:
        notes.append(f"{crossings} crossing(s) of cut lines attached at both ends (a cut grid): split there")
    return edges, notes


def _on_interiors(segs: list[Segment], ends: np.ndarray, allowance: np.ndarray, tight: float, end_of: np.ndarray,
                  seg_of: np.ndarray) -> list[tuple[int, int, float, float]]:
    """(end, entity, parameter, distance) for each end-entity pair found near each other,
    but for an end of the entity itself, of a closed curve (a circle's "ends" are only
    where its parameter starts) or at the entity's own ends (a joint, the common case).
    Lines are projected at once (numpy; ``ends`` holds each entity's start and end at 2i,
    2i + 1), other curves one by one. O(pairs)."""
    keep = (end_of // 2 != seg_of) & ~np.array([is_closed_curve(segs[i]) for i in range(len(segs))], bool)[end_of // 2]
    e, j = end_of[keep], seg_of[keep]
    q, a, b = ends[e], ends[2 * j], ends[2 * j + 1]
    joint = np.minimum(np.linalg.norm(q - a, axis=1), np.linalg.norm(q - b, axis=1)) <= np.maximum(tight, allowance[e])
    e, j, q, a, b = e[~joint], j[~joint], q[~joint], a[~joint], b[~joint]
    line = np.array([segs[k]["type"] == "line" for k in j.tolist()], bool)
    v = b - a
    t = np.clip(np.einsum("ij,ij->i", q - a, v) / np.maximum(np.einsum("ij,ij->i", v, v), np.finfo(float).tiny), 0, 1)
    dist = np.linalg.norm(a + t[:, None] * v - q, axis=1)
    out = [(int(e[k]), int(j[k]), float(t[k]), float(dist[k])) for k in np.flatnonzero(line)]
    return out + [(int(e[k]), int(j[k]), *project(segs[int(j[k])], q[k])) for k in np.flatnonzero(~line)]


def _attached(segs: list[Segment], cuts: dict[int, list[tuple[float, int]]]) -> list[int]:
    """The entities both of whose ends lie on other entities' interiors: cut lines across
    a sheet (a grid of parts cut by full-length lines)."""
    on_other = {e for v in cuts.values() for _, e in v}
    return [i for i in range(len(segs)) if 2 * i in on_other and 2 * i + 1 in on_other]


def _crossings(segs: list[Segment], lines: list[Any], tree: Any, attached: list[int], tight: float, uf: Union,
               cuts: dict[int, list[tuple[float, int]]]) -> int:
    """Split pairs of cut lines across (both ends on other entities) where they cross, at
    one new vertex. Other crossings are not split: in a drawing for cutting, centre marks,
    centre and dimension lines cross outlines, and two outlines crossing are parts drawn
    over each other (said as overlapping loops), not a cut."""
    ok = set(attached)
    n = 0
    if len(ok) < 2:
        return 0
    hits = tree.query([lines[i] for i in attached], predicate="crosses")
    for a, j in zip(hits[0].tolist(), hits[1].tolist()):
        i = attached[a]
        if j <= i or j not in ok:
            continue
        for x in _points(lines[i].intersection(lines[j])):
            ti, di = project(segs[i], x)
            tj, dj = project(segs[j], x)
            if any(np.linalg.norm(at(segs[k], t) - point_at(segs[k], e)) <= tight
                   for k, t in ((i, ti), (j, tj)) for e in (False, True)):
                continue  # at an end: a T or a corner, already joined
            v = uf.add()
            cuts.setdefault(i, []).append((ti, v))
            cuts.setdefault(j, []).append((tj, v))
            n += 1
    return n


def _points(geom: Any) -> list[np.ndarray]:
    parts = getattr(geom, "geoms", [geom])
    return [np.array([g.x, g.y]) for g in parts if g.geom_type == "Point"]


def _cut(s: Segment, i: int, cuts: list[tuple[float, int]], uf: Union) -> list[Edge]:
    t_start, t_end = t_range(s)
    if t_start > t_end:  # parameters run downwards (a clockwise arc): cut in that order
        cuts = cuts[::-1]
    out, t0, u = [], t_start, 2 * i
    for t, e in cuts:
        if t == t0:
            uf.join(e, u)
            continue
        v = uf.add()
        uf.join(v, e)
        out.append(Edge(sub(s, t0, t) if (t0, t) != (t_start, t_end) else s, u, v, i, t0, t))
        t0, u = t, v
    out.append(Edge(s if t0 == t_start else sub(s, t0, t_end), u, 2 * i + 1, i, t0, t_end))
    return out


def _signature(s: Segment) -> np.ndarray:
    return np.concatenate([point_at(s, False), midpoint(s), point_at(s, True)])


def _deduplicate(edges: list[Edge], tight: float, uf: Union, segs_of: list[Segment]) -> tuple[list[Edge], list[str]]:
    """Drop edges whose start, middle and end lie within tolerance of another edge's
    (either direction); their ends are joined to the kept one's. A whole entity is kept
    over a stretch of a longer one (a diagonal over the stretch of a line running on),
    else the first drawn."""
    from scipy.spatial import cKDTree

    if len(edges) < 2:
        return edges, []
    sig = np.array([_signature(e.segment) for e in edges])
    flipped = sig[:, [4, 5, 2, 3, 0, 1]]
    radius = np.array([max(tight, DUP_REL * length(e.segment)) for e in edges])
    tree = cKDTree(sig)
    drop: set[int] = set()
    exact = near = 0
    whole = [(e.t0, e.t1) == t_range(segs_of[e.piece]) for e in edges] if segs_of else [True] * len(edges)
    rank = {k: r for r, k in enumerate(sorted(range(len(edges)), key=lambda k: (not whole[k], k)))}
    for k in sorted(range(len(edges)), key=rank.__getitem__):
        if k in drop:
            continue
        for same, vec in ((True, sig[k]), (False, flipped[k])):
            for j in tree.query_ball_point(vec, radius[k]):
                if rank[j] <= rank[k] or j in drop:
                    continue
                drop.add(j)
                gap = float(np.max(np.abs(sig[j] - vec)))
                exact, near = (exact + 1, near) if gap <= tight else (exact, near + 1)
                a, b = (edges[j].u, edges[j].v) if same else (edges[j].v, edges[j].u)
                uf.join(a, edges[k].u)
                uf.join(b, edges[k].v)
    notes = []
    if exact:
        notes.append(f"{exact} duplicated entit{'y' if exact == 1 else 'ies'} dropped")
    if near:
        notes.append(f"{near} near-duplicate entit{'y' if near == 1 else 'ies'} merged (drawn twice, a hair apart)")
    return [e for k, e in enumerate(edges) if k not in drop], notes


def _without_degenerate(edges: list[Edge], size: float) -> tuple[list[Edge], int]:
    """Self-loops that bound no area (a short segment whose ends joined: a fillet arc of
    1e-6° that Maker.js writes between two lines) are dropped; no area is under the
    zero-area tolerance of the drawing's size², not exactly zero (a sliver of 1e-20 mm²
    kept as a loop of its own turned the walk round at its vertex)."""
    from shapely.geometry import Polygon

    kept, dropped = [], 0
    least = DEFAULT_TOLERANCES.zero_area_rel * size * size
    for e in edges:
        if e.u == e.v and not (len(pts := samples(e.segment)) >= 4 and Polygon(pts).area > least):
            dropped += 1
            continue
        kept.append(e)
    return kept, dropped


def _prune(edges: list[Edge], origins: list[str], allowance: np.ndarray) -> tuple[list[Edge], list[str]]:
    """Remove chains that end in a free end, repeatedly; each group of removed edges is one
    open chain, described like an open contour."""
    alive = set(range(len(edges)))
    at: dict[int, list[int]] = {}  # a self-loop is listed twice: it gives its vertex degree 2
    for k, e in enumerate(edges):
        at.setdefault(e.u, []).append(k)
        at.setdefault(e.v, []).append(k)
    stack = [x for x, ks in at.items() if len(ks) == 1]
    removed: list[int] = []
    while stack:
        x = stack.pop()
        if len(at[x]) != 1:
            continue
        k = at[x].pop()
        alive.discard(k)
        removed.append(k)
        other = edges[k].v if edges[k].u == x else edges[k].u
        at[other].remove(k)
        if len(at[other]) == 1:
            stack.append(other)
    return [edges[k] for k in sorted(alive)], _open_messages([edges[k] for k in removed], origins, allowance)


def _open_messages(removed: list[Edge], origins: list[str], allowance: np.ndarray) -> list[str]:
    groups = Union(0)
    index: dict[int, int] = {}
    for e in removed:
        for x in (e.u, e.v):
            if x not in index:
                index[x] = groups.add()
        groups.join(index[e.u], index[e.v])
    chains: dict[int, list[Edge]] = {}
    for e in removed:
        chains.setdefault(groups.find(index[e.u]), []).append(e)
    return [_open_message(chain_edges, origins, allowance) for chain_edges in chains.values()]


def _open_message(chain_edges: list[Edge], origins: list[str], allowance: np.ndarray) -> str:
    """Where an open chain ends and how far its free ends are apart."""
    seen: dict[int, list[np.ndarray]] = {}
    for e in chain_edges:
        seen.setdefault(e.u, []).append(point_at(e.segment, False))
        seen.setdefault(e.v, []).append(point_at(e.segment, True))
    free = [pts[0] for pts in seen.values() if len(pts) == 1]
    reach = float(np.max(allowance[[2 * e.piece for e in chain_edges]]))
    first = origins[min(e.piece for e in chain_edges)]
    if len(free) >= 2:
        a, b = free[0], free[1]
        return (f"open contour: the chain of {len(chain_edges)} segment(s) from {first} ends at ({a[0]:.6g}, "
                f"{a[1]:.6g}), {float(np.linalg.norm(a - b)):.3g} from its other end ({b[0]:.6g}, {b[1]:.6g}); gaps "
                f"close up to {reach:.3g} there")
    p = free[0] if free else point_at(chain_edges[0].segment, False)
    return (f"open contour: the chain of {len(chain_edges)} segment(s) from {first} has a free end at ({p[0]:.6g}, "
            f"{p[1]:.6g}); gaps close up to {reach:.3g} there")
