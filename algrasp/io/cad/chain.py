"""Chain exact segments (part-document segment dicts, in any order and direction) into
closed loops (which loop is a part and which a hole: `algrasp.io.cad.sheet`).

Only the chaining and the loop classification look at sampled points (to find which
loop contains which); the segments themselves stay exact. Chaining is O(n log n) in the
number of segments (a KD-tree of the end points).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from algrasp.errors import LimitExceededError, PartDocumentError
from algrasp.geometry.angles import to_rad
from algrasp.geometry.limits import DEFAULT_LIMITS
from algrasp.geometry.tolerances import ROUNDING

Segment = dict[str, Any]


@dataclass(frozen=True)
class Piece:
    """A segment and where it came from (``origin``: e.g. ``LINE #2F`` for errors)."""

    segment: Segment
    origin: str
    layer: str | None = None


def _ellipse_point(s: Segment, deg: float) -> np.ndarray:
    t, rot = to_rad(deg), to_rad(s.get("rotation_deg", 0.0))
    x, y = s["rx"] * math.cos(t), s["ry"] * math.sin(t)
    return np.array(s["center"]) + [x * math.cos(rot) - y * math.sin(rot), x * math.sin(rot) + y * math.cos(rot)]


def point_at(s: Segment, end: bool) -> np.ndarray:
    """The start (``end`` False) or end point of a segment."""
    kind = s["type"]
    if kind == "line":
        return np.array(s["end" if end else "start"], dtype=float)
    if kind == "bezier":
        return np.array(s["points"][-1 if end else 0], dtype=float)
    deg = s["end_deg" if end else "start_deg"]
    if kind == "arc":
        a = to_rad(deg)
        return np.array(s["center"]) + s["radius"] * np.array([math.cos(a), math.sin(a)])
    return _ellipse_point(s, deg)


def reverse(s: Segment) -> Segment:
    """The same curve traversed the other way."""
    kind = s["type"]
    if kind == "line":
        return {**s, "start": s["end"], "end": s["start"]}
    if kind == "bezier":
        out = {**s, "points": list(reversed(s["points"]))}
        if "weights" in s:
            out["weights"] = list(reversed(s["weights"]))
        return out
    return {**s, "start_deg": s["end_deg"], "end_deg": s["start_deg"]}


def _snap(s: Segment, start: np.ndarray) -> Segment:
    """Move a line's or a Bezier's first point onto the previous segment's end (arcs are
    left exact: their gap must be within the document tolerance)."""
    if s["type"] == "line":
        return {**s, "start": [float(start[0]), float(start[1])]}
    if s["type"] == "bezier":
        return {**s, "points": [[float(start[0]), float(start[1])], *s["points"][1:]]}
    return s


def samples(s: Segment, n: int = 16) -> np.ndarray:
    """Points along a segment, for loop classification, areas and boxes only: a line's two
    ends; a curve's n points, or one every degree of an arc's sweep (≤ 0.004 % area error)."""
    kind = s["type"]
    if kind == "line":
        return np.array([s["start"], s["end"]], dtype=float)
    if kind != "bezier":
        n = max(n, int(abs(s["end_deg"] - s["start_deg"])) + 1)
    if kind == "bezier":
        P = np.asarray(s["points"], float)
        w = np.asarray(s.get("weights", np.ones(len(P))), float)
        t = np.linspace(0.0, 1.0, n)[:, None]
        k = len(P) - 1
        B = np.hstack([math.comb(k, i) * t**i * (1 - t) ** (k - i) for i in range(k + 1)]) * w
        return np.asarray((B @ P) / B.sum(axis=1, keepdims=True))
    t = to_rad(np.linspace(s["start_deg"], s["end_deg"], n))
    rot = to_rad(s.get("rotation_deg", 0.0))
    rx, ry = (s["radius"], s["radius"]) if kind == "arc" else (s["rx"], s["ry"])
    x, y = rx * np.cos(t), ry * np.sin(t)
    c = np.asarray(s["center"], dtype=float)
    return np.column_stack([c[0] + x * math.cos(rot) - y * math.sin(rot), c[1] + x * math.sin(rot) + y * math.cos(rot)])


def chain(pieces: Sequence[Piece], tol: float, open_chains: list[str] | None = None) -> list[list[Segment]]:
    """Closed loops from the pieces; endpoints closer than ``tol`` join. Raises
    PartDocumentError for an open contour, naming where the gap is and how big — unless
    ``open_chains`` is given: then each open chain is set aside there (its message) and
    chaining goes on with the rest.

    The free ends are found with a KD-tree of all end points (scipy): O(n log n) for n
    pieces (a 10,000-entity sheet chains in well under a second)."""
    from scipy.spatial import cKDTree

    n = len(pieces)
    ends = np.array([point_at(p.segment, e) for p in pieces for e in (False, True)]).reshape(2 * n, 2)
    tree = cKDTree(ends)
    used = np.zeros(n, dtype=bool)
    loops = []
    for i0 in range(n):
        if used[i0]:
            continue
        used[i0] = True
        first = pieces[i0]
        loop = [first.segment]
        start, end = ends[2 * i0], ends[2 * i0 + 1]
        while np.linalg.norm(end - start) > tol:
            k, flip = _nearest_free(tree, ends, used, end, tol)
            if k is None:
                err = _open_contour(first, loop, start, end, ends, used, tol)
                if open_chains is None:
                    raise err
                open_chains.append(err.message)
                loop = []
                break
            used[k] = True
            seg = pieces[k].segment
            seg = _snap(reverse(seg) if flip else seg, end)
            loop += [*_bridge(end, point_at(seg, False), seg), seg]
            end = point_at(seg, True)
        if loop:
            loops.append([*loop, *_bridge(end, start, loop[0])])
    return loops


def _bridge(a: np.ndarray, b: np.ndarray, like: Segment) -> list[Segment]:
    """A line over a gap the chaining tolerance closed but snapping cannot (arcs stay
    exact): the loop stays continuous to the document's tolerance."""
    gap = float(np.linalg.norm(b - a))
    if gap <= BRIDGE_REL * max(float(np.max(np.abs(np.concatenate([a, b])))), 1.0):
        return []
    out: Segment = {"type": "line", "start": [float(a[0]), float(a[1])], "end": [float(b[0]), float(b[1])]}
    if "_layer" in like:
        out["_layer"] = like["_layer"]
    return [out]


def _nearest_free(tree: Any, ends: np.ndarray, used: np.ndarray, p: np.ndarray, tol: float) -> tuple[int | None, bool]:
    """The unused piece with an end within ``tol`` of p (the nearest), and whether that
    end is the piece's end (so the piece must be reversed)."""
    near = [j for j in tree.query_ball_point(p, tol) if not used[j // 2]]
    if not near:
        return None, False
    j = min(near, key=lambda q: float(np.linalg.norm(ends[q] - p)))
    return j // 2, bool(j % 2)


def _open_contour(first: Piece, loop: list[Segment], start: np.ndarray, end: np.ndarray, ends: np.ndarray,
                  used: np.ndarray, tol: float) -> PartDocumentError:
    free = ends[np.repeat(~used, 2)]
    gap = float(np.min(np.linalg.norm(free - end, axis=1))) if len(free) else None
    nearest = "no other segment is left" if gap is None else f"the nearest free end is {gap:.3g} away"
    return PartDocumentError(
        f"contour at ({end[0]:.6g}, {end[1]:.6g})",
        f"open contour: the chain of {len(loop)} segment(s) from {first.origin} ends here, "
        f"{float(np.linalg.norm(end - start)):.3g} from its start ({start[0]:.6g}, {start[1]:.6g}); "
        f"{nearest} (chaining tolerance {tol:.3g})")


def ring(loop: list[Segment]) -> np.ndarray:
    """The loop's sample points (each segment without its end point), shape (N, 2)."""
    return np.vstack([samples(s)[:-1] for s in loop])


def _polygon(loop: list[Segment]) -> Any:
    from shapely.geometry import Polygon

    return Polygon(ring(loop)).buffer(0)


CHAIN_GAP_REL = 1e-4
"""Default chaining tolerance relative to the drawing's size: drawings made by people have
gaps of a few hundredths of a millimetre between entities that should meet (0.015 mm seen
on a 300 mm sheet); lines and curves are snapped over such gaps, arcs get a bridging line."""
BRIDGE_REL = 1e-9
"""Gaps below this (relative to the coordinates) need no bridging line."""


def default_tolerance(pieces: Sequence[Piece]) -> float:
    """Chaining tolerance: ``CHAIN_GAP_REL`` times the drawing's size."""
    pts = [point_at(p.segment, e) for p in pieces for e in (False, True)]
    for p in pieces:  # a lone circle's end points coincide: its radius still sizes it
        r = max(float(p.segment.get(k, 0.0)) for k in ("radius", "rx", "ry"))
        if r > 0.0:
            c = np.asarray(p.segment["center"], dtype=float)
            pts += [c - r, c + r]
    size = float(np.max(np.ptp(np.array(pts), axis=0))) if pts else 1.0
    return CHAIN_GAP_REL * max(size, ROUNDING)


def check_bounded(segments: list[Segment], origin: str) -> None:
    """Every coordinate and radius within ±max_abs_coordinate, checked before any geometry
    (a KD-tree or a polygon of 1e300 overflows)."""
    limit = DEFAULT_LIMITS.max_abs_coordinate
    for seg in segments:
        values = [*seg.get("start", ()), *seg.get("end", ()), *seg.get("center", ()),
                  *(v for pt in seg.get("points", ()) for v in pt[:2]), seg.get("radius", 0.0), seg.get("rx", 0.0),
                  seg.get("ry", 0.0)]
        if not all(math.isfinite(v) and abs(v) <= limit for v in values):
            raise LimitExceededError(origin, f"a coordinate beyond ±{limit:g} (or not a number): not a drawing in "
                                     "any unit algrasp takes")
