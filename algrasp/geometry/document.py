"""Parse and validate part documents (conventions §5) into :class:`~algrasp.geometry.part.Part`.

Every problem becomes a :class:`PartDocumentError` whose ``field`` names where it is
(``boundary[3].radius``) and whose message says what is wrong; nothing else escapes.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from algrasp.errors import LimitExceededError, PartDocumentError
from algrasp.geometry.angles import to_rad
from algrasp.geometry.limits import DEFAULT_LIMITS, Limits
from algrasp.geometry.segments import Bezier, EllipseArc, Line, Segment

_SEGMENT_KEYS = {
    "line": ({"start", "end"}, set()),
    "arc": ({"center", "radius", "start_deg", "end_deg"}, set()),
    "ellipse_arc": ({"center", "rx", "ry", "start_deg", "end_deg"}, {"rotation_deg"}),
    "bezier": ({"points"}, {"weights"}),
}
_DOC_KEYS = {"name", "units", "boundary", "polygon", "holes", "center_of_mass", "approximate", "source"}


def number(value: Any, field: str, index: int | None = None) -> float:
    """A finite float, or a PartDocumentError naming ``field``."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise PartDocumentError(field, f"expected a number, got {type(value).__name__}", index)
    x = float(value)
    if not math.isfinite(x):
        raise PartDocumentError(field, f"must be finite, got {value}", index)
    return x


def point(value: Any, field: str, index: int | None, limits: Limits) -> tuple[float, float]:
    """An ``[x, y]`` pair of finite numbers within the coordinate limit."""
    if not isinstance(value, Sequence) or isinstance(value, str) or len(value) != 2:
        raise PartDocumentError(field, "expected a point [x, y]", index)
    x, y = number(value[0], f"{field}[0]", index), number(value[1], f"{field}[1]", index)
    if max(abs(x), abs(y)) > limits.max_abs_coordinate:
        raise LimitExceededError(field, f"coordinate magnitude exceeds the limit {limits.max_abs_coordinate:g}", index)
    return x, y


def _positive(value: Any, field: str, index: int) -> float:
    x = number(value, field, index)
    if x <= 0.0:
        raise PartDocumentError(field, f"must be positive, got {x:g}", index)
    return x


def _length(value: Any, field: str, index: int, limits: Limits) -> float:
    """A positive length within the coordinate limit (radii, semi-axes)."""
    x = _positive(value, field, index)
    if x > limits.max_abs_coordinate:
        raise LimitExceededError(field, f"{x:g} exceeds the coordinate limit {limits.max_abs_coordinate:g}", index)
    return x


def _sweep(seg: Mapping[str, Any], field: str, index: int) -> tuple[float, float]:
    a = number(seg["start_deg"], f"{field}.start_deg", index)
    b = number(seg["end_deg"], f"{field}.end_deg", index)
    if abs(b - a) > 360.0:
        raise PartDocumentError(f"{field}.end_deg", f"arc sweeps {abs(b - a):g}°, more than 360°", index)
    if a == b:
        raise PartDocumentError(f"{field}.end_deg", "zero-length arc (start_deg equals end_deg)", index)
    return to_rad(a), to_rad(b)


def parse_segment(seg: Any, field: str, index: int, limits: Limits) -> Segment:
    """One segment object → Line / EllipseArc / Bezier."""
    if not isinstance(seg, Mapping):
        raise PartDocumentError(field, "expected a segment object", index)
    kind = seg.get("type")
    if not isinstance(kind, str) or kind not in _SEGMENT_KEYS:
        raise PartDocumentError(f"{field}.type", f"unknown segment type {kind!r} (line, arc, ellipse_arc, bezier)", index)
    required, optional = _SEGMENT_KEYS[kind]
    missing = sorted(required - set(seg))
    if missing:
        raise PartDocumentError(f"{field}.{missing[0]}", f"missing for a {kind} segment", index)
    extra = sorted(set(seg) - required - optional - {"type"})
    if extra:
        raise PartDocumentError(f"{field}.{extra[0]}", f"unknown key for a {kind} segment", index)
    if kind == "line":
        return Line(point(seg["start"], f"{field}.start", index, limits), point(seg["end"], f"{field}.end", index, limits))
    if kind == "arc":
        c = point(seg["center"], f"{field}.center", index, limits)
        r = _length(seg["radius"], f"{field}.radius", index, limits)
        a, b = _sweep(seg, field, index)
        return EllipseArc(c, r, r, 0.0, a, b, is_circle=True)
    if kind == "ellipse_arc":
        c = point(seg["center"], f"{field}.center", index, limits)
        rx = _length(seg["rx"], f"{field}.rx", index, limits)
        ry = _length(seg["ry"], f"{field}.ry", index, limits)
        rot = to_rad(number(seg.get("rotation_deg", 0.0), f"{field}.rotation_deg", index))
        a, b = _sweep(seg, field, index)
        return EllipseArc(c, rx, ry, rot, a, b, is_circle=rx == ry)
    return _parse_bezier(seg, field, index, limits)


def _parse_bezier(seg: Mapping[str, Any], field: str, index: int, limits: Limits) -> Bezier:
    pts_raw = seg["points"]
    if not isinstance(pts_raw, Sequence) or isinstance(pts_raw, str):
        raise PartDocumentError(f"{field}.points", "expected a list of control points", index)
    if len(pts_raw) < 2:
        raise PartDocumentError(f"{field}.points", f"degree {len(pts_raw) - 1}: a Bezier needs degree ≥ 1 (≥ 2 points)", index)
    if len(pts_raw) - 1 > limits.max_bezier_degree:
        raise LimitExceededError(f"{field}.points", f"degree {len(pts_raw) - 1} exceeds the limit {limits.max_bezier_degree}", index)
    pts = np.array([point(p, f"{field}.points[{i}]", index, limits) for i, p in enumerate(pts_raw)])
    weights = np.ones(len(pts))
    if "weights" in seg:
        w_raw = seg["weights"]
        if not isinstance(w_raw, Sequence) or isinstance(w_raw, str) or len(w_raw) != len(pts):
            raise PartDocumentError(f"{field}.weights", f"expected {len(pts)} weights, one per control point", index)
        weights = np.array([_positive(w, f"{field}.weights[{i}]", index) for i, w in enumerate(w_raw)])
    return Bezier(pts, weights / weights.max())


def parse_loop(raw: Any, field: str, limits: Limits) -> list[Segment]:
    """A loop given as segments or as polygon vertices → list of segments."""
    if not isinstance(raw, Sequence) or isinstance(raw, str):
        raise PartDocumentError(field, "expected a list of segments or of [x, y] vertices")
    if len(raw) == 0:
        raise PartDocumentError(field, "empty loop")
    if len(raw) > limits.max_segments:
        raise LimitExceededError(field, f"{len(raw)} segments exceed the limit {limits.max_segments}")
    if isinstance(raw[0], Sequence) and not isinstance(raw[0], (str, Mapping)):
        return polygon_segments(raw, field, limits)
    lines = _fast_lines(raw, limits)
    if lines is not None:
        return lines
    return [parse_segment(s, f"{field}[{i}]", i, limits) for i, s in enumerate(raw)]


def _fast_lines(raw: Sequence[Any], limits: Limits) -> list[Segment] | None:
    """All segments at once when every one is a valid line object (exactly the keys
    type, start and end); else None, and :func:`parse_segment` finds and names what is
    wrong. The checks of :func:`_fast_points`, without a field name made per point."""
    raw_ends: list[Any] = []
    for seg in raw:
        if type(seg) is not dict or len(seg) != 3 or seg.get("type") != "line":
            return None
        raw_ends += (seg.get("start"), seg.get("end"))
    ends = _fast_points(raw_ends, limits)  # all end points in one pass
    if ends is None:
        return None
    return [Line(ends[i], ends[i + 1]) for i in range(0, len(ends), 2)]


def polygon_segments(raw: Sequence[Any], field: str, limits: Limits) -> list[Segment]:
    """Polygon shorthand: vertices in order, closed implicitly."""
    if len(raw) < 3:
        raise PartDocumentError(field, f"a polygon needs at least 3 vertices, got {len(raw)}")
    verts = _fast_points(raw, limits)
    if verts is None:  # something is wrong: find and name it
        verts = [point(p, f"{field}[{i}]", i, limits) for i, p in enumerate(raw)]
    return [Line(verts[i], verts[(i + 1) % len(verts)]) for i in range(len(verts))]


def _fast_points(raw: Sequence[Any], limits: Limits) -> list[tuple[float, float]] | None:
    """All vertices at once when every one is a valid [x, y] of numbers; else None.
    Plain floats: a comparison per coordinate (NaN fails it, ±inf exceeds the limit)."""
    top = limits.max_abs_coordinate
    out = []
    for p in raw:
        if type(p) not in (list, tuple) or len(p) != 2:
            return None
        x, y = p
        if type(x) not in (int, float) or type(y) not in (int, float) or not (abs(x) <= top and abs(y) <= top):
            return None
        out.append((float(x), float(y)))
    return out


def check_document_shape(doc: Any, limits: Limits) -> None:
    """Top-level structure: an object with exactly one of boundary / polygon."""
    if not isinstance(doc, Mapping):
        raise PartDocumentError("$", "a part document must be a JSON object")
    if not doc:
        raise PartDocumentError("$", "empty part document: give 'boundary' or 'polygon'")
    extra = sorted(set(doc) - _DOC_KEYS)
    if extra:
        raise PartDocumentError(extra[0], "unknown key in a part document")
    if ("boundary" in doc) == ("polygon" in doc):
        raise PartDocumentError("boundary", "give exactly one of 'boundary' and 'polygon'")
    for key in ("name", "units"):
        if key in doc and not isinstance(doc[key], str):
            raise PartDocumentError(key, "expected a string")
    holes = doc.get("holes", [])
    if not isinstance(holes, Sequence) or isinstance(holes, str):
        raise PartDocumentError("holes", "expected a list of loops")
    if len(holes) > limits.max_holes:
        raise LimitExceededError("holes", f"{len(holes)} holes exceed the limit {limits.max_holes}")


def parse_loops(doc: Mapping[str, Any], limits: Limits = DEFAULT_LIMITS) -> tuple[list[Segment], list[list[Segment]]]:
    """Boundary and hole segment lists of a document (structure checked)."""
    check_document_shape(doc, limits)
    key = "polygon" if "polygon" in doc else "boundary"
    boundary = parse_loop(doc[key], key, limits)
    holes = [parse_loop(h, f"holes[{i}]", limits) for i, h in enumerate(doc.get("holes", []))]
    total = len(boundary) + sum(len(h) for h in holes)
    if total > limits.max_total_segments:
        raise LimitExceededError("boundary", f"{total} segments in all exceed the limit {limits.max_total_segments}")
    return boundary, holes
