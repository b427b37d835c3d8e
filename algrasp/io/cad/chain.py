"""Drawing segments (part-document segment dicts) and where they came from: end points,
reversal, sample points, loops as polygons, the drawing's size and coordinate bounds.
Loops are found by `algrasp.io.cad.arrange`, parts and holes by `algrasp.io.cad.sheet`.

Only loop classification looks at sampled points (to find which loop contains which);
the segments themselves stay exact.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from algrasp.errors import LimitExceededError
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
    colour: str | None = None
    """The stroke colour (``#rrggbb``; SVG stroke, DXF true colour or ACI), None: not known."""
    reach: float = 0.0
    """Half the drawn stroke's width (drawing units): an SVG shows gaps narrower than this closed."""


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


def ring(loop: list[Segment]) -> np.ndarray:
    """The loop's sample points (each segment without its end point), shape (N, 2)."""
    return np.vstack([samples(s)[:-1] for s in loop])


def _polygon(loop: list[Segment]) -> Any:
    from shapely.geometry import Polygon

    return Polygon(ring(loop)).buffer(0)


BRIDGE_REL = 1e-9
"""Gaps below this (relative to the coordinates) need no bridging line."""


def drawing_extent(pieces: Sequence[Piece]) -> float:
    """The drawing's size: the larger side of the box of its entities' ends (a lone
    circle's ends coincide: its radius still sizes it)."""
    pts = [point_at(p.segment, e) for p in pieces for e in (False, True)]
    for p in pieces:
        r = max(float(p.segment.get(k, 0.0)) for k in ("radius", "rx", "ry"))
        if r > 0.0:
            c = np.asarray(p.segment["center"], dtype=float)
            pts += [c - r, c + r]
    size = float(np.max(np.ptp(np.array(pts), axis=0))) if pts else 1.0
    return max(size, ROUNDING)


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
