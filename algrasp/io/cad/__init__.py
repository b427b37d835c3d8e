"""CAD import adapters: DXF (ezdxf), SVG (svgelements) and 3-D meshes (trimesh) become
part documents (conventions §5). Curves stay exact (arcs, ellipse arcs, rational
Beziers); only meshes, already tessellated, give polygons marked ``approximate``.

These adapters read bytes and import their libraries lazily; the core never imports them.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from pathlib import Path, PurePath
from typing import Any, TypeVar

from algrasp.errors import AlgraspError, ConfigError, LimitExceededError, PartDocumentError
from algrasp.geometry.limits import DEFAULT_LIMITS
from algrasp.io.cad.readers import (  # noqa: F401 - CAD_SUFFIXES, is_cad: the package's entry points
    CAD_SUFFIXES,
    DRAWING_SUFFIXES,
    MESH_SUFFIXES,
    file_type,
    is_cad,
    unsupported,
)

T = TypeVar("T")
MAX_WARNINGS = 20
"""Warnings kept in a document's ``source`` (ezdxf may log hundreds on a damaged file)."""


def _scale(seg: dict[str, Any], k: float) -> dict[str, Any]:
    if k == 1.0:
        return seg
    out = dict(seg)
    for key in ("start", "end", "center"):
        if key in out:
            out[key] = [k * out[key][0], k * out[key][1]]
    for key in ("radius", "rx", "ry"):
        if key in out:
            out[key] = k * out[key]
    if "points" in out:
        out["points"] = [[k * x, k * y] for x, y in out["points"]]
    return out


def _need_cad_extra(filename: str) -> None:
    """A clear error when the reader of ``filename``'s type is not installed (the ``cad`` extra)."""
    import importlib.util

    t = file_type(filename)
    if t is not None and t.library is not None and importlib.util.find_spec(t.library) is None:
        reader = t.library
        raise ConfigError("FILE", f"reading {t.description}s needs {reader}: pip install 'algrasp[cad]'")


LIBRARY_FAULTS = (ValueError, TypeError, AttributeError, LookupError, RuntimeError, ArithmeticError, AssertionError,
                  OSError)
"""What reader libraries raise on files they cannot handle (RecursionError is a RuntimeError)."""
LIBRARIES = ("ezdxf", "shapely", "svgelements", "trimesh", "zipfile")
"""Libraries whose own exception bases (ezdxf's DXFError, shapely's GEOSException) are faults too."""


def _library_faults(fn: Callable[..., T]) -> Callable[..., T]:
    """Any fault of a reader library (ezdxf, svgelements, trimesh, shapely, numpy) on a
    file it cannot handle becomes a PartDocumentError naming the file, never a traceback:
    the adapters name the entity where they can, this is the net under them."""

    @functools.wraps(fn)
    def guarded(filename: str, *args: Any, **kw: Any) -> T:
        try:
            return fn(filename, *args, **kw)
        except AlgraspError:
            raise
        except Exception as exc:  # noqa: BLE001 - filtered below: only the libraries' faults are the file's
            if not isinstance(exc, LIBRARY_FAULTS) and type(exc).__module__.split(".")[0] not in LIBRARIES:
                raise
            raise PartDocumentError(PurePath(filename).name or "file", f"the file cannot be read ({type(exc).__name__}: "
                                    f"{str(exc)[:200]})") from None

    return guarded


@_library_faults
def import_bytes(filename: str, data: bytes, layer: str | None = None, element_id: str | None = None,
                 pose: int | None = None, tolerance: float | None = None, units: str | None = None,
                 part: int | None = None, engrave_colours: str | None = None) -> dict[str, Any]:
    """The part document of a DXF/SVG/mesh file's bytes (a fence layout DXF gives its layout
    document, ``kind`` "fence_layout": :mod:`algrasp.io.fence_import`). ``layer`` (DXF), ``element_id``
    (SVG), ``pose`` (mesh) choose what to import; ``part`` chooses one of several parts on
    a sheet (:func:`list_parts` lists them); ``tolerance`` is the join and gap tolerance in
    drawing units (default: ends within 1e-6 of the drawing's size join, and gaps up to
    2e-3 of the chains meeting there close); ``units`` overrides the unit
    (meshes carry none: default mm); ``engrave_colours`` names the stroke colours that are
    engraving ("#ff0000,#00f"; "none": every colour is cut; default: judged from the drawing,
    :mod:`algrasp.io.cad.colours`)."""
    suffix = PurePath(filename).suffix.lower()
    name = PurePath(filename).stem
    _need_cad_extra(filename)
    if not is_cad(filename):
        raise unsupported(filename, "FILE", ("drawing", "mesh"))
    if suffix in MESH_SUFFIXES:
        from algrasp.io.cad.mesh import mesh_document

        _check_options(suffix, layer, element_id, pose)
        if engrave_colours is not None:
            raise ConfigError("engrave_colours", "a mesh has no stroke colours (only DXF/SVG drawings)")
        if part not in (None, 0):
            raise ConfigError("part", "a mesh is one part (choose a resting pose with --pose)")
        return mesh_document(data, suffix[1:], name, pose, units or "mm")
    if suffix == ".dxf" and (fences := _fence_layout(data, name)) is not None:
        return fences  # a drawing of belt fences (algrasp fences --dxf): its layout, no part
    sheet, doc_units, k, source = _sheet(filename, data, layer, element_id, pose, tolerance, units, engrave_colours)
    if part is None and len(sheet.parts) > 1:
        rows = sheet.summary(units or doc_units)["parts"]
        listing = "; ".join(f"{r['index']}: {r['segments']} segments, {r['holes']} hole(s), area {k * k * r['area']:.4g}"
                            for r in rows[:10])
        raise PartDocumentError("part", f"the drawing holds {len(rows)} parts ({listing}{'; …' if len(rows) > 10 else ''}); "
                                "choose one with --part K (algrasp import FILE --list shows them)"
                                + "".join(f"; {w}" for w in sheet.warnings if w.startswith("overlapping")))
    if not sheet.parts:
        kinds = "; ".join(sorted({w.split(":")[0] for w in sheet.ignored if not w.startswith("open contour")}))
        raise PartDocumentError("drawing", "no part to cut: every closed loop was set aside"
                                + (f" ({kinds}: see algrasp import FILE --list)" if kinds else ""))
    index = 0 if part is None else part
    if not 0 <= index < len(sheet.parts):
        raise ConfigError("part", f"no part {index}: the drawing holds {len(sheet.parts)} (0 to {len(sheet.parts) - 1})")
    return _part_document(sheet, index, name, units or doc_units, k, source)


def _fence_layout(data: bytes, name: str) -> dict[str, Any] | None:
    from algrasp.io.fence_import import fence_layout_of

    return fence_layout_of(data, name)


@_library_faults
def import_all_parts(filename: str, data: bytes) -> list[dict[str, Any]]:
    """Every part of a DXF/SVG sheet as its own document (``FILE#K`` when there are
    several), read once; a mesh or a one-part drawing gives one document. For catalogues."""
    suffix = PurePath(filename).suffix.lower()
    if suffix not in DRAWING_SUFFIXES:
        return [import_bytes(filename, data)]
    sheet, doc_units, k, source = _sheet(filename, data, None, None, None, None, None)
    name = PurePath(filename).stem
    return [_part_document(sheet, i, name, doc_units, k, dict(source)) for i in range(len(sheet.parts))]


@_library_faults
def sheet_documents(filename: str, data: bytes, documents: int, layer: str | None = None,
                    element_id: str | None = None, tolerance: float | None = None,
                    units: str | None = None, engrave_colours: str | None = None) -> dict[str, Any]:
    """:func:`list_parts`' listing of a DXF/SVG sheet with the part documents of its first
    ``documents`` parts (``"documents"``), the drawing read once: one upload shows a sheet."""
    sheet, doc_units, k, source = _sheet(filename, data, layer, element_id, None, tolerance, units, engrave_colours)
    out = _listing(sheet, units or doc_units, k, source)
    name = PurePath(filename).stem
    out["documents"] = [_part_document(sheet, i, name, units or doc_units, k, dict(source))
                        for i in range(min(documents, len(sheet.parts)))]
    return out


def _part_document(sheet: Any, index: int, name: str, units: str, k: float, source: dict[str, Any]) -> dict[str, Any]:
    outline, holes = sheet.parts[index]
    warnings = [*source.pop("warnings", []), *sheet.warnings, *sheet.ignored][:MAX_WARNINGS]
    if warnings:
        source["warnings"] = warnings
    if len(sheet.parts) > 1:
        source["part"] = index
    doc_name = name if len(sheet.parts) == 1 else f"{name}#{index}"
    return {"name": doc_name, "units": units, "boundary": [_scale(s, k) for s in outline],
            "holes": [[_scale(s, k) for s in h] for h in holes], "source": source}


@_library_faults
def list_parts(filename: str, data: bytes, layer: str | None = None, element_id: str | None = None,
               tolerance: float | None = None, units: str | None = None,
               engrave_colours: str | None = None) -> dict[str, Any]:
    """``{"parts": [{"index", "bbox", "area", "holes", "segments", "units"}], "ignored",
    "warnings"}`` of a DXF/SVG sheet, lengths in the document's unit."""
    sheet, doc_units, k, source = _sheet(filename, data, layer, element_id, None, tolerance, units, engrave_colours)
    return _listing(sheet, units or doc_units, k, source)


def _listing(sheet: Any, units: str, k: float, source: dict[str, Any]) -> dict[str, Any]:
    """The sheet's summary in ``units`` (lengths scaled by ``k``), the reader's warnings first."""
    out: dict[str, Any] = sheet.summary(units)
    for row in out["parts"]:
        row["bbox"] = [k * v for v in row["bbox"]]
        row["area"] = k * k * row["area"]
    out["warnings"] = [*source.get("warnings", []), *out["warnings"]]
    return out


def _sheet(filename: str, data: bytes, layer: str | None, element_id: str | None, pose: int | None,
           tolerance: float | None, units: str | None,
           engrave_colours: str | None = None) -> tuple[Any, str, float, dict[str, Any]]:
    """The parts of a DXF/SVG drawing, its unit, scale and source description."""
    from algrasp.io.cad.chain import drawing_extent, point_at
    from algrasp.io.cad.clutter import Marks
    from algrasp.io.cad.colours import by_colour, parse_colours
    from algrasp.io.cad.sheet import find_parts

    suffix = PurePath(filename).suffix.lower()
    _check_options(suffix, layer, element_id, pose)
    engrave = parse_colours(engrave_colours)
    if suffix == ".dxf":
        pieces, doc_units, k, source, marks = _dxf(data, layer, units)
    elif suffix == ".svg":
        from algrasp.io.cad.svg import svg_pieces

        fills: list[tuple[float, float]] = []
        pieces, doc_units, k = svg_pieces(data, element_id, fills), "mm", 1.0
        marks = Marks(hatched=fills)
        source = {"format": "svg", "id": element_id}
    else:  # a mesh or anything else: only drawings are sheets
        raise unsupported(filename, "FILE", ("drawing",))
    for p in pieces:  # a transform can overflow (SVG scale(1e308) scale(1e308))
        if not all(math.isfinite(c) for e in (False, True) for c in point_at(p.segment, e)):
            raise PartDocumentError(p.origin, "coordinates overflow to infinity (an extreme scale or transform?)")
    size = drawing_extent(pieces)
    sheet = by_colour(pieces, size, lambda kept: find_parts(kept, size, tolerance, marks), engrave)
    if units is None and suffix == ".dxf":
        doc_units, k = _plausible_units(sheet, doc_units, k, source)
    return sheet, doc_units, k, source


def _dxf(data: bytes, layer: str | None, units: str | None) -> tuple[list[Any], str, float, dict[str, Any], Any]:
    from algrasp.io.cad.dxf import captured_ezdxf_log, dxf_pieces, read_dxf

    drawing = read_dxf(data)
    with captured_ezdxf_log() as log:  # expanding blocks logs too
        pieces, doc_units, k = dxf_pieces(drawing, layer)
    drawing.algrasp_warnings += sorted(set(log))
    source: dict[str, Any] = {"format": "dxf", "layer": layer}
    # With --units the unit assumption is the user's, not ours to warn about.
    kept = [w for w in drawing.algrasp_warnings if units is None or "$INSUNITS" not in w][:MAX_WARNINGS]
    if kept:
        source["warnings"] = kept
    return pieces, doc_units, k, source, drawing.algrasp_marks


PLAUSIBLE_PART_MM = 500.0
"""The largest part a parallel-jaw gripper cell takes (mm): a drawing whose header unit
makes its parts larger, while millimetres make them a plausible size, is read in mm."""
PLAUSIBLE_MIN_PART_MM = 1.0
PLAUSIBLE_MIN_HOLE_MM = 0.5
"""Read in mm, a drawing whose largest part is under 1 mm across, or whose smallest hole is
under 0.5 mm, may be drawn in a larger unit (a SolidWorks part in metres under an mm
header, a KiCad plot in inches, a cm export)."""
RESCUE_PART_MM = 5.0
RESCUE_HOLE_MM = 1.5
"""A larger unit is taken when it makes the smallest hole at least this (M1.6 clearance)
and the parts between 5 and 500 mm; tried in the order cm, in, m."""
RESCUE_UNITS = (("cm", 10.0), ("in", 25.4), ("m", 1000.0))


def _plausible_units(sheet: Any, units: str, k: float, source: dict[str, Any]) -> tuple[str, float]:
    """The header's unit, unless the content is implausible in it and plausible in another
    (KiCad writes $MEASUREMENT 0 with mm content; some exporters say inches for mm, or mm
    for metres): then the other, with both readings said in the warnings."""
    if not sheet.parts or units not in ("in", "mm"):
        return units, k
    extent, hole = _sizes(sheet)
    extent, hole = extent * k, hole * k
    if units == "in":
        if extent * 25.4 <= PLAUSIBLE_PART_MM or extent > PLAUSIBLE_PART_MM:
            return units, k
        return _reread(source, "inches", f"up to {extent:.4g} in ({extent * 25.4:.4g} mm) across", "mm", k, extent, "in")
    if extent >= PLAUSIBLE_MIN_PART_MM and hole >= PLAUSIBLE_MIN_HOLE_MM:
        return units, k
    for name, to_mm in RESCUE_UNITS:
        if RESCUE_PART_MM <= extent * to_mm <= PLAUSIBLE_PART_MM and hole * to_mm >= RESCUE_HOLE_MM:
            return _reread(source, "millimetres", f"up to {extent:.4g} mm across with holes from {hole:.4g} mm", name, k,
                           extent, "mm")
    return units, k


def _reread(source: dict[str, Any], said: str, then: str, unit: str, k: float, extent: float,
            back: str) -> tuple[str, float]:
    note = (f"the header says {said} (or nothing), but its parts would then be {then}: read as {unit} "
            f"({extent:.4g} {unit}); use --units {back} if they really are {said}")
    source["warnings"] = [*source.get("warnings", []), note][:MAX_WARNINGS]
    return unit, k


def _sizes(sheet: Any) -> tuple[float, float]:
    """The largest part's extent and the smallest hole's smaller side (inf: no holes), in
    drawing units."""
    from algrasp.io.cad.chain import ring

    def span(loop: Any) -> Any:
        r = ring(loop)
        return r.max(axis=0) - r.min(axis=0)

    extent = max(float(max(span(outline))) for outline, _ in sheet.parts)
    holes = [float(min(span(h))) for _, hs in sheet.parts for h in hs]
    return extent, min(holes, default=math.inf)


def _check_options(suffix: str, layer: str | None, element_id: str | None, pose: int | None) -> None:
    if layer is not None and suffix != ".dxf":
        raise ConfigError("layer", "only DXF drawings have layers")
    if element_id is not None and suffix != ".svg":
        raise ConfigError("element_id", "only SVG documents have element ids")
    if pose is not None and suffix in DRAWING_SUFFIXES:
        raise ConfigError("pose", "only 3-D meshes have resting poses")


def import_file(path: str, **options: Any) -> dict[str, Any]:
    """``import_bytes`` of a file on disk (size-limited)."""
    p = Path(path)
    if not p.is_file():
        raise PartDocumentError("FILE", f"no such file: {path}")
    if p.stat().st_size > DEFAULT_LIMITS.max_document_bytes * 8:
        raise LimitExceededError("FILE", f"file larger than {DEFAULT_LIMITS.max_document_bytes * 8} bytes")
    return import_bytes(p.name, p.read_bytes(), **options)
