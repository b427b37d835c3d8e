"""DXF drawings (ezdxf) → exact part documents.

LINE, ARC, CIRCLE, ELLIPSE, LWPOLYLINE/POLYLINE (bulges become exact arcs), SPLINE (split
exactly into rational Bezier segments) and INSERT (block references, expanded with their
transformation by ezdxf). Annotation (text, dimensions, hatches, points) is skipped;
any other entity is refused by name. Entities must lie in the XY plane (extrusion ±Z).
"""

from __future__ import annotations

import contextlib
import io
import logging
import math
import re
from collections.abc import Iterator
from typing import Any

import numpy as np

from algrasp.errors import LimitExceededError, PartDocumentError
from algrasp.geometry.angles import TWO_PI, to_deg
from algrasp.geometry.limits import DEFAULT_LIMITS
from algrasp.geometry.tolerances import ROUNDING
from algrasp.io.cad.chain import Piece, Segment, check_bounded
from algrasp.io.cad.clutter import Marks
from algrasp.io.cad.colours import dxf_colour
from algrasp.io.cad.dxf_marks import drawing_scale, hatch_points, measured_points, text_marks
from algrasp.io.cad.nurbs import nurbs_to_beziers

SKIPPED = {"TEXT", "MTEXT", "DIMENSION", "ARC_DIMENSION", "LEADER", "MLEADER", "MULTILEADER", "ATTRIB", "ATTDEF",
           "POINT", "HATCH", "MPOLYGON", "VIEWPORT", "IMAGE", "WIPEOUT", "TOLERANCE", "SOLID", "TRACE", "3DFACE", "RAY",
           "XLINE", "ACAD_TABLE", "SHAPE", "OLE2FRAME", "ACAD_PROXY_ENTITY", "MESH", "3DSOLID", "BODY", "REGION",
           "SURFACE", "EXTRUDEDSURFACE", "LOFTEDSURFACE", "REVOLVEDSURFACE", "SWEPTSURFACE", "PLANESURFACE", "UNDERLAY",
           "PDFUNDERLAY", "DWFUNDERLAY", "DGNUNDERLAY", "LIGHT", "HELIX"}
"""Annotation, fills, construction and 3-D entities: set aside (and counted in the warnings)."""
INSUNITS = {1: ("in", 1.0), 2: ("mm", 304.8), 3: ("m", 1609.344), 4: ("mm", 1.0), 5: ("cm", 1.0), 6: ("m", 1.0),
            7: ("m", 1000.0), 8: ("um", 0.0254), 9: ("um", 25.4), 10: ("mm", 914.4), 11: ("um", 1e-4), 12: ("um", 1e-3),
            13: ("um", 1.0), 14: ("mm", 100.0), 15: ("m", 10.0), 16: ("m", 100.0), 17: ("m", 1e9), 18: ("m", 1.495978707e11),
            19: ("m", 9.4607304725808e15), 20: ("m", 3.0856775814913673e16), 21: ("mm", 304.8006096),
            22: ("mm", 25.4000508), 23: ("mm", 914.4018288), 24: ("m", 1609.347219)}
"""$INSUNITS code (every code DXF defines) → (document unit, factor applied to the
coordinates). Units the part document has no name for (feet, mils, yards, US survey
units, …) are converted to one it has."""


BINARY_SENTINEL = b"AutoCAD Binary DXF"


def read_dxf(data: bytes) -> Any:
    """The drawing as AutoCAD reads it: any line endings (CRLF is the normal case), the
    encoding its ``$DWGCODEPAGE`` names, binary DXF, R12 to current; structural flaws are
    repaired by ezdxf's recover mode. ezdxf's log messages are kept on the drawing
    (``algrasp_warnings``), never printed."""
    from ezdxf import recover

    with captured_ezdxf_log() as messages:
        try:
            doc = _read_binary(data) if data.startswith(BINARY_SENTINEL) else _read_text(data, messages)
        except Exception:  # noqa: BLE001 - a damaged file: let the recover mode repair it
            try:
                doc, _ = recover.read(io.BytesIO(data))
                messages.append("the drawing was damaged and has been repaired (ezdxf recover mode)")
            except Exception as exc:  # noqa: BLE001 - ezdxf raises several types for a malformed file
                raise PartDocumentError("dxf", f"not a readable DXF drawing: {exc}") from None
    doc.algrasp_warnings = list(messages)
    # ezdxf fills a missing header with its defaults ($INSUNITS = 6, metres): keep which
    # variables the file itself sets.
    doc.algrasp_header_vars = {v for v in ("$INSUNITS", "$MEASUREMENT") if v.encode() in data}
    return doc


_ACADVER = re.compile(rb"\$ACADVER\s*\r?\n\s*1\s*\r?\n\s*(AC\d{4})")
_CODEPAGE = re.compile(rb"\$DWGCODEPAGE\s*\r?\n\s*3\s*\r?\n\s*(\S+)")


def _read_text(data: bytes, messages: list[str]) -> Any:
    """The fast path for a sound ASCII DXF: UTF-8 from R2007 (AC1021) on, before that the
    $DWGCODEPAGE encoding; CR, LF or CRLF line ends all read as one; LWPOLYLINEs written
    without subclass markers get them (`algrasp.io.cad.dxf_repair`, said in ``messages``)."""
    import ezdxf
    from ezdxf.tools.codepage import toencoding

    from algrasp.io.cad.dxf_repair import lwpolyline_markers

    version = _ACADVER.search(data[:65536])
    codepage = _CODEPAGE.search(data[:65536])
    if version is not None and version.group(1) >= b"AC1021":
        encoding = "utf-8"
    else:
        encoding = toencoding(codepage.group(1).decode("ascii", "replace")) if codepage else "cp1252"
    text = data.decode(encoding, errors="replace").replace("\r\n", "\n").replace("\r", "\n")
    repaired = lwpolyline_markers(text)
    if repaired is not None:
        messages.append("LWPOLYLINEs without subclass markers (OpenJsCad-style): markers added to read them")
    return ezdxf.read(io.StringIO(repaired or text))


def _read_binary(data: bytes) -> Any:
    import tempfile

    import ezdxf

    with tempfile.NamedTemporaryFile(suffix=".dxf") as f:  # ezdxf reads binary DXF from files only
        f.write(data)
        f.flush()
        return ezdxf.readfile(f.name)


class _ListHandler(logging.Handler):
    def __init__(self, out: list[str]) -> None:
        super().__init__(logging.WARNING)
        self.out = out

    def emit(self, record: logging.LogRecord) -> None:
        self.out.append(record.getMessage())


@contextlib.contextmanager
def captured_ezdxf_log() -> Iterator[list[str]]:
    """ezdxf's warnings go into a list instead of stderr while a drawing is read."""
    log = logging.getLogger("ezdxf")
    messages: list[str] = []
    handler = _ListHandler(messages)
    old = log.propagate
    log.addHandler(handler)
    log.propagate = False
    try:
        yield messages
    finally:
        log.removeHandler(handler)
        log.propagate = old


def _xy(v: Any) -> list[float]:
    return [float(v[0]), float(v[1])]


def _normal_sign(e: Any) -> float:
    z = e.dxf.extrusion if e.dxf.hasattr("extrusion") else (0.0, 0.0, 1.0)
    if abs(abs(z[2]) - 1.0) > ROUNDING:
        raise PartDocumentError(_origin(e), "not in the XY plane (extrusion is not ±Z)")
    return 1.0 if z[2] > 0 else -1.0


def _origin(e: Any) -> str:
    handle = e.dxf.get("handle")
    return f"{e.dxftype()} #{handle}" if handle else e.dxftype()


def _arc(e: Any, full: bool) -> Segment:
    sign = _normal_sign(e)
    c = e.ocs().to_wcs(e.dxf.center)
    a0 = 0.0 if full else float(e.dxf.start_angle)
    sweep = 360.0 if full else (float(e.dxf.end_angle) - a0) % 360.0 or 360.0
    start = a0 if sign > 0 else 180.0 - a0  # OCS with −Z extrusion mirrors x
    return {"type": "arc", "center": _xy(c), "radius": float(e.dxf.radius), "start_deg": start,
            "end_deg": start + sign * sweep}


def _ellipse(e: Any) -> Segment:
    sign = _normal_sign(e)
    major = e.dxf.major_axis
    rx = math.hypot(major[0], major[1])
    t0, t1 = float(e.dxf.start_param), float(e.dxf.end_param)
    sweep = (t1 - t0) % TWO_PI or TWO_PI
    # minor axis = extrusion × major · ratio: with −Z the parameter runs clockwise
    return {"type": "ellipse_arc", "center": _xy(e.dxf.center), "rx": rx, "ry": rx * float(e.dxf.ratio),
            "rotation_deg": to_deg(math.atan2(major[1], major[0])),
            "start_deg": sign * to_deg(t0), "end_deg": sign * to_deg(t0 + sweep)}


def bulge_segment(p1: list[float], p2: list[float], bulge: float) -> Segment:
    """The exact segment between two polyline vertices: a line (bulge 0) or the arc of
    included angle 4·atan(bulge), counter-clockwise for a positive bulge."""
    if bulge == 0.0:
        return {"type": "line", "start": p1, "end": p2}
    theta = 4.0 * math.atan(bulge)
    v = np.subtract(p2, p1)
    L = float(np.hypot(*v))
    c = (np.add(p1, p2) / 2 + np.array([-v[1], v[0]]) / L * (L / (2 * math.tan(theta / 2)))) if L > 0 else np.array(p1)
    start = to_deg(math.atan2(p1[1] - c[1], p1[0] - c[0]))
    return {"type": "arc", "center": _xy(c), "radius": L / (2 * abs(math.sin(theta / 2))), "start_deg": start,
            "end_deg": start + to_deg(theta)}


def _polyline(e: Any) -> list[Segment]:
    sign = _normal_sign(e)
    ocs = e.ocs()
    if e.dxftype() == "LWPOLYLINE":
        verts = [(_xy(ocs.to_wcs((x, y, 0.0))), sign * b) for x, y, b in e.get_points("xyb")]
        closed = bool(e.closed)
    elif e.is_2d_polyline:
        verts = [(_xy(ocs.to_wcs(v.dxf.location)), sign * float(v.dxf.bulge)) for v in e.vertices]
        closed = bool(e.is_closed)
    else:
        verts = [(_xy(v.dxf.location), 0.0) for v in e.vertices]
        closed = bool(e.is_closed)
    pairs = list(zip(verts, verts[1:] + (verts[:1] if closed else [])))
    return [bulge_segment(a, b, bulge) for (a, bulge), (b, _) in pairs if a != b]


def _spline(e: Any) -> list[Segment]:
    # A SPLINE's points are world coordinates and its normal (code 210) is optional: many
    # writers (Fusion 360, keyboard-plate generators) leave it (0, 0, 0). Planar in XY is
    # what matters: a normal along ±Z, or none with every control point at one height.
    bs = e.construction_tool()
    z = e.dxf.extrusion if e.dxf.hasattr("extrusion") else (0.0, 0.0, 1.0)
    if max(abs(float(c)) for c in z) > ROUNDING:
        _normal_sign(e)
    heights = [float(p[2]) for p in bs.control_points]
    if heights and max(heights) - min(heights) > ROUNDING * max(1.0, *(abs(h) for h in heights)):
        raise PartDocumentError(_origin(e), "not in the XY plane (its control points are at different heights)")
    ctrl = np.array([_xy(p) for p in bs.control_points])
    w = np.array(bs.weights(), float) if bs.is_rational else np.ones(len(ctrl))
    segs = nurbs_to_beziers(bs.degree, ctrl, w, np.array(bs.knots(), float), _origin(e))
    out = []
    for P, W in segs:
        seg: Segment = {"type": "bezier", "points": P.tolist()}
        if bs.is_rational:
            seg["weights"] = W.tolist()
        out.append(seg)
    return out


CONSTRUCTION_LINETYPE = re.compile(r"center|centre|dash|hidden|phantom|dot|divide|achs|mittel|strich|axe|axis|eje|"
                                   r"trait|punt|tratt|hidd", re.IGNORECASE)
"""Linetypes of centre, hidden and construction lines (never cut paths): set aside."""


ANNOTATION_LAYER = re.compile(r"dimension|annotation|center ?mark|centre ?mark|center ?line|centre ?line|break ?line|"
                              r"section ?line|view ?label|thread|hatch|bema(ss|ß)ung|mittellinie|schraffur|cotation|"
                              r"hachure|acotaci|cota\b|quota|寸法|中心線|尺寸|标注|中心线", re.IGNORECASE)
"""Layers a drafting template keeps for annotation (the ISO/ANSI layer sets of Inventor,
Fusion 360 and AutoCAD drawings: "Dimension (ISO)", "Center Mark (ISO)", "Thread Lines"…):
set aside when other layers hold the geometry."""


def construction_line(e: Any) -> bool:
    """Whether an entity is drawn in a centre/hidden/construction linetype (its own, or its
    layer's when it says BYLAYER)."""
    name = str(e.dxf.get("linetype", "BYLAYER"))
    if name.upper() == "BYLAYER" and e.doc is not None and e.doc.layers.has_entry(e.dxf.layer):
        name = str(e.doc.layers.get(e.dxf.layer).dxf.get("linetype", "CONTINUOUS"))
    return bool(CONSTRUCTION_LINETYPE.search(name))


MAX_BLOCK_DEPTH = 16
"""Nested INSERTs deeper than this (or a block inserting itself) are refused."""
MAX_EXPANDED_SEGMENTS = 2 * DEFAULT_LIMITS.max_total_segments
"""Most segments a drawing may expand to (INSERTs included): a sheet holds many parts, each
within the part limits, plus title block and annotation that is set aside."""


def entity_pieces(e: Any, within: str = "", depth: int = 0, budget: list[int] | None = None) -> list[Piece]:
    """The exact segments of one entity (INSERT: of its expanded block; their origins name
    the block and the INSERT's handle, as block content has no handle of its own).
    ``budget``: segments still allowed (one list shared by the whole expansion, so an
    INSERT fan-out of 2^16 stops at the limit instead of expanding for seconds)."""
    budget = [MAX_EXPANDED_SEGMENTS] if budget is None else budget
    t = e.dxftype()
    if t in SKIPPED or t.endswith("DIMENSION"):  # every dimension flavour is annotation
        return []
    if t == "INSERT":
        return _insert_pieces(e, within, depth, budget)
    if construction_line(e):
        return []
    handlers = {"LINE": lambda: [{"type": "line", "start": _xy(e.dxf.start), "end": _xy(e.dxf.end)}],
                "ARC": lambda: [_arc(e, False)], "CIRCLE": lambda: [_arc(e, True)], "ELLIPSE": lambda: [_ellipse(e)],
                "LWPOLYLINE": lambda: _polyline(e), "POLYLINE": lambda: _polyline(e), "SPLINE": lambda: _spline(e)}
    origin = _origin(e) + within
    if t not in handlers:
        raise PartDocumentError(origin, f"unsupported DXF entity {t} on layer {e.dxf.layer!r} "
                                "(supported: LINE, ARC, CIRCLE, ELLIPSE, LWPOLYLINE, POLYLINE, SPLINE, INSERT)")
    try:
        segments = handlers[t]()
    except (ValueError, ArithmeticError, IndexError, TypeError) as exc:  # malformed data (bad knots, …)
        raise PartDocumentError(origin, f"malformed {t} on layer {e.dxf.layer!r}: {exc}") from None
    check_bounded(segments, origin)
    budget[0] -= len(segments)
    if budget[0] < 0:
        raise LimitExceededError(origin, f"the drawing expands to more than {MAX_EXPANDED_SEGMENTS} segments "
                                 "(blocks inserted many times over?)")
    colour = dxf_colour(e)
    return [Piece(s, origin, e.dxf.layer, colour) for s in segments]


def _insert_pieces(e: Any, within: str, depth: int, budget: list[int]) -> list[Piece]:
    if depth >= MAX_BLOCK_DEPTH:
        raise PartDocumentError(f"INSERT #{e.dxf.handle}", f"blocks nested deeper than {MAX_BLOCK_DEPTH} "
                                f"(block {e.dxf.name!r} inserts itself?)")
    top = within or f" (INSERT #{e.dxf.handle})"  # nested block content has no handle: name the top INSERT
    if e.doc is not None:
        if e.doc.blocks.get(e.dxf.name) is None:
            raise PartDocumentError(f"block {e.dxf.name!r}{top}", f"inserts block {e.dxf.name!r}, which the drawing does not define "
                                    "(a damaged or partly exported file?)")
        if depth == 0 and _entities(e.doc, e.dxf.name, {}) * _copies(e) > budget[0]:  # before expanding anything
            raise LimitExceededError(f"block {e.dxf.name!r}{top}", f"block {e.dxf.name!r} expands to more than "
                                     f"{MAX_EXPANDED_SEGMENTS} segments (inserted many times over?)")
    return [Piece(p.segment, f"{p.origin.split(' in block ')[0]} in block {e.dxf.name!r}{top}", p.layer, p.colour)
            for v in e.virtual_entities() for p in entity_pieces(v, top, depth + 1, budget)]


def _size(e: Any) -> int:
    """Segments an entity gives, roughly (a polyline one per vertex)."""
    t = e.dxftype()
    return len(e) if t == "LWPOLYLINE" else len(e.vertices) if t == "POLYLINE" else 1


def _copies(e: Any) -> int:
    return max(1, int(e.dxf.get("row_count", 1))) * max(1, int(e.dxf.get("column_count", 1)))


def _entities(doc: Any, name: str, memo: dict[str, int], depth: int = 0) -> int:
    """Entities a block expands to, INSERTs counted through (memoised: O(blocks))."""
    if name not in memo:
        memo[name] = 0  # a block inserting itself counts as empty here; the depth limit refuses it
        block = doc.blocks.get(name)
        if block is not None and depth < MAX_BLOCK_DEPTH:
            memo[name] = sum(_entities(doc, x.dxf.name, memo, depth + 1) * _copies(x) if x.dxftype() == "INSERT"
                             else _size(x) for x in block)
    return memo[name]


def dxf_pieces(doc: Any, layer: str | None) -> tuple[list[Piece], str, float]:
    """Pieces of the model space (only ``layer`` if given), the unit and the coordinate
    scale from the header's $INSUNITS (unitless drawings are taken as millimetres)."""
    msp = doc.modelspace()
    layers = sorted({e.dxf.layer for e in msp})
    chosen = [e for e in msp if layer is None or e.dxf.layer.lower() == layer.lower()]
    # What the drawing's author hid (layers off or frozen: construction, old revisions) is
    # not cut, unless the layer is asked for by name.
    hidden = set() if layer is not None else _hidden_layers(doc)
    shown = [e for e in chosen if e.dxf.layer.lower() not in hidden]
    skipped: dict[str, int] = {"entity on a hidden (off or frozen) layer": len(chosen) - len(shown)} \
        if len(shown) < len(chosen) else {}
    notes = [e for e in shown if ANNOTATION_LAYER.search(e.dxf.layer)]
    if notes and len(notes) < len(shown):
        skipped["entity on an annotation layer"] = len(notes)
        shown = [e for e in shown if not ANNOTATION_LAYER.search(e.dxf.layer)]
    chosen = shown
    budget = [MAX_EXPANDED_SEGMENTS]  # shared by every entity of the drawing
    pieces = [p for e in chosen for p in entity_pieces(e, budget=budget)]
    dashed = sum(1 for e in chosen if e.dxftype() not in SKIPPED and e.dxftype() != "INSERT" and construction_line(e))
    if dashed:
        skipped["centre/hidden-line entity (by linetype)"] = dashed
    for e in chosen:
        if e.dxftype() in SKIPPED or e.dxftype().endswith("DIMENSION"):
            skipped[e.dxftype()] = skipped.get(e.dxftype(), 0) + 1
    if hasattr(doc, "algrasp_warnings"):
        doc.algrasp_marks = Marks(hatch_points([e for e in msp if e.dxftype() == "HATCH"]), text_marks(msp),
                                  any(e.dxftype() == "DIMENSION" for e in msp), measured_points(msp))
    if skipped and hasattr(doc, "algrasp_warnings"):
        doc.algrasp_warnings.append("set aside (annotation, fills, construction, 3-D): "
                                    + ", ".join(f"{n} {t}" for t, n in sorted(skipped.items())))
    if not pieces:
        where = f"layer {layer!r}" if layer is not None else "the drawing"
        raise PartDocumentError("layer" if layer else "dxf",
                                f"{where} has no outline geometry (layers: {', '.join(layers) or 'none'})")
    units, k = dxf_units(doc)
    scale, said = drawing_scale(msp)
    if said and hasattr(doc, "algrasp_warnings"):
        doc.algrasp_warnings.append(said)
    return pieces, units, k * scale


def _hidden_layers(doc: Any) -> set[str]:
    """Lower-case names of the layers switched off or frozen."""
    out = set()
    for entry in doc.layers:
        try:
            if entry.is_off() or entry.is_frozen():
                out.add(entry.dxf.name.lower())
        except (AttributeError, ValueError):  # a damaged LAYER entry: shown
            continue
    return out


def dxf_units(doc: Any) -> tuple[str, float]:
    """Unit and scale: ``$INSUNITS`` when the file sets it, else ``$MEASUREMENT`` (0:
    imperial → inches, 1: metric → millimetres), else millimetres. Whatever was assumed is
    added to the drawing's warnings (``algrasp_warnings``): never silent."""
    present: set[str] = getattr(doc, "algrasp_header_vars", set())
    warnings: list[str] = getattr(doc, "algrasp_warnings", [])
    code = int(doc.header.get("$INSUNITS", 0)) if "$INSUNITS" in present else 0
    if code in INSUNITS:
        return INSUNITS[code]
    if "$MEASUREMENT" in present:
        imperial = int(doc.header.get("$MEASUREMENT", 1)) == 0
        warnings.append(f"no $INSUNITS: units taken from $MEASUREMENT = {0 if imperial else 1} "
                        f"({'imperial: inches' if imperial else 'metric: millimetres'})")
        return ("in", 1.0) if imperial else ("mm", 1.0)
    warnings.append("unitless drawing (no $INSUNITS or $MEASUREMENT): assumed millimetres; use --units to say otherwise")
    return "mm", 1.0
