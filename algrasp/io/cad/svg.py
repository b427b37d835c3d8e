"""SVG outlines (svgelements) → exact part documents.

svgelements applies every transform and unit (``reify``) and gives user units at 96 px
per inch; coordinates become millimetres, and y is flipped (SVG's y axis points down) so
the part is not mirrored. Lines and quadratic/cubic Beziers stay Beziers of the same
degree; elliptical arcs become exact ``arc``/``ellipse_arc`` segments.
"""

from __future__ import annotations

import io
from typing import Any

import numpy as np

from algrasp.errors import PartDocumentError
from algrasp.geometry.angles import to_deg
from algrasp.io.cad.chain import Piece, Segment, check_bounded, samples

MM_PER_PX = 1.0 / (96.0 * 0.0393701)
"""svgelements turns mm into px with its rounded 0.0393701 in/mm at 96 px/in; inverting
the same constant gives mm drawings back exactly (inch drawings: 1e-7 relative off)."""
CIRCULAR_REL = 1e-12
"""An SVG arc whose radii differ by less than this (relative) is written as a circular arc."""


def _pt(p: Any) -> list[float]:
    return [float(p[0]) * MM_PER_PX, -float(p[1]) * MM_PER_PX]


def _arc(s: Any) -> Segment:
    rot = float(s.get_rotation())
    t0, sweep = float(s.get_start_t()), float(s.sweep)
    c, rx, ry = _pt(s.center), float(s.rx) * MM_PER_PX, float(s.ry) * MM_PER_PX
    # after y ↦ −y: rotation ↦ −rotation and parameter t ↦ −t
    if abs(rx - ry) <= CIRCULAR_REL * max(rx, ry):
        start = -to_deg(t0 + rot)
        return {"type": "arc", "center": c, "radius": rx, "start_deg": start, "end_deg": start - to_deg(sweep)}
    return {"type": "ellipse_arc", "center": c, "rx": rx, "ry": ry, "rotation_deg": -to_deg(rot),
            "start_deg": -to_deg(t0), "end_deg": -to_deg(t0 + sweep)}


def _segment(s: Any) -> Segment | None:
    from svgelements import Arc, Close, CubicBezier, Line, Move, QuadraticBezier

    if isinstance(s, Move):
        return None
    if isinstance(s, (Line, Close)):
        if s.start is None or s.end is None or s.start == s.end:
            return None
        return {"type": "line", "start": _pt(s.start), "end": _pt(s.end)}
    if isinstance(s, QuadraticBezier):
        return {"type": "bezier", "points": [_pt(s.start), _pt(s.control), _pt(s.end)]}
    if isinstance(s, CubicBezier):
        return {"type": "bezier", "points": [_pt(s.start), _pt(s.control1), _pt(s.control2), _pt(s.end)]}
    if isinstance(s, Arc):
        return _arc(s)
    raise PartDocumentError("svg", f"unsupported path segment {type(s).__name__}")


INKSCAPE_LABEL = "{http://www.inkscape.org/namespaces/inkscape}label"


def _layers(svg: Any) -> dict[int, str]:
    """Each shape's layer name: its Inkscape layer label, else Illustrator's ``data-name``,
    else the id of the top-level group holding it (Illustrator writes layers as top-level
    groups named by id, escaping non-ASCII names). Keyed by ``id(shape)``."""
    from svgelements import Group, Shape

    out: dict[int, str] = {}
    for child in svg:
        if isinstance(child, Group) and getattr(child, "id", None):
            for e in child.select():
                out[id(e)] = str(child.id)
    for e in svg.elements():
        if isinstance(e, Shape):
            label = e.values.get(INKSCAPE_LABEL) or e.values.get("data-name")
            if label:
                out[id(e)] = str(label)
    return out


def _painted(paint: Any) -> bool:
    return paint is not None and getattr(paint, "value", None) is not None


def _stroke(shape: Any) -> tuple[str | None, float]:
    """A shape's stroke colour (``#rrggbb``, None when unstroked) and half its stroke
    width in mm (after every transform)."""
    if not _painted(shape.stroke):
        return None, 0.0
    width = float(getattr(shape, "implicit_stroke_width", None) or shape.stroke_width or 0.0)
    return str(shape.stroke.hex)[:7].lower(), 0.5 * width * MM_PER_PX


def fill_points(shape: Any, segments: list[Segment]) -> list[tuple[float, float]]:
    """One point inside each region a shape fills without a stroke (black-filled icons
    to engrave, as a hatch in a DXF): its subpaths filled even-odd. Empty for a stroked
    or unfilled shape (a cut line)."""
    from algrasp.io.cad.dxf_marks import even_odd

    if not _painted(shape.fill) or (_painted(shape.stroke) and float(shape.stroke_width or 0.0) > 0.0):
        return []
    rings: list[list[Any]] = []
    for seg in segments:
        pts = samples(seg)
        if not rings or float(np.linalg.norm(np.subtract(rings[-1][-1], pts[0]))) > 0.0:
            rings.append([])
        rings[-1] += list(pts)
    out = []
    for g in even_odd([np.asarray(r) for r in rings if len(r) >= 3]):
        pt = g.representative_point()
        out.append((float(pt.x), float(pt.y)))
    return out


def svg_pieces(data: bytes, element_id: str | None, fills: list[tuple[float, float]] | None = None) -> list[Piece]:
    """Exact segments of the element ``element_id`` (default: every shape); ``fills``, if
    given, receives a point inside each region filled without a stroke (`fill_points`)."""
    from svgelements import SVG, Path, Shape

    try:
        svg = SVG.parse(io.BytesIO(data), reify=True, ppi=96.0)
    except Exception as exc:  # noqa: BLE001 - the XML parser raises several types
        raise PartDocumentError("svg", f"not a readable SVG document: {exc}") from None
    if not isinstance(svg, SVG):  # svgelements returns whatever the root is (<html>, a bare <g>)
        raise PartDocumentError("svg", f"the root element is <{getattr(svg, 'tag', None) or type(svg).__name__}>, "
                                "not <svg> in the SVG namespace: not an SVG drawing")
    if element_id is not None:
        el = svg.get_element_by_id(element_id)
        if el is None:
            # Every element with an id: groups (boxes.py's parts are <g id="p-0">) as well as shapes.
            ids = sorted({str(e.id) for e in svg.elements() if getattr(e, "id", None)})
            shown = ", ".join(ids[:40]) + (", …" if len(ids) > 40 else "")
            raise PartDocumentError("id", f"no element with id {element_id!r} (elements with ids: {shown or 'none'})")
        shapes = [e for e in ([el] if isinstance(el, Shape) else el.select()) if isinstance(e, Shape)]
    else:
        shapes = [e for e in svg.elements() if isinstance(e, Shape)]
    layers = _layers(svg)
    pieces = []
    for shape in shapes:
        origin = f"{type(shape).__name__}#{shape.id}" if shape.id else type(shape).__name__
        path = shape if isinstance(shape, Path) else Path(shape)
        segments = [seg for seg in map(_segment, path.segments()) if seg is not None]
        check_bounded(segments, origin)
        colour, reach = _stroke(shape)
        pieces += [Piece(seg, origin, layers.get(id(shape)), colour, reach) for seg in segments]
        if fills is not None:
            fills += fill_points(shape, segments)
    if not pieces:
        raise PartDocumentError("id" if element_id else "svg", "no outline geometry (paths or shapes) found")
    return pieces
