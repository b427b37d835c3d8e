"""CAD import adapters: DXF (ezdxf), SVG (svgelements) and 3-D meshes (trimesh) become
part documents (conventions §5). Curves stay exact (arcs, ellipse arcs, rational
Beziers); only meshes, already tessellated, give polygons marked ``approximate``.

These adapters read bytes and import their libraries lazily; the core never imports them.
"""

from __future__ import annotations

from pathlib import Path, PurePath
from typing import Any

from algrasp.errors import ConfigError, LimitExceededError, PartDocumentError
from algrasp.limits import DEFAULT_LIMITS

MAX_WARNINGS = 20
"""Warnings kept in a document's ``source`` (ezdxf may log hundreds on a damaged file)."""
CAD_SUFFIXES = (".dxf", ".svg", ".stl", ".obj", ".ply", ".off", ".glb")


def is_cad(filename: str) -> bool:
    return PurePath(filename).suffix.lower() in CAD_SUFFIXES


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


def import_bytes(filename: str, data: bytes, layer: str | None = None, element_id: str | None = None,
                 pose: int | None = None, tolerance: float | None = None, units: str | None = None) -> dict[str, Any]:
    """The part document of a DXF/SVG/mesh file's bytes. ``layer`` (DXF), ``element_id``
    (SVG), ``pose`` (mesh) choose what to import; ``tolerance`` is the chaining
    tolerance in drawing units (default: 1e-6 of the drawing's size); ``units`` overrides
    the unit (meshes carry none: default mm)."""
    from algrasp.cad.chain import chain, default_tolerance, outline_document

    suffix = PurePath(filename).suffix.lower()
    name = PurePath(filename).stem
    _check_options(suffix, layer, element_id, pose)
    if suffix in (".stl", ".obj", ".ply", ".off", ".glb"):
        from algrasp.cad.mesh import mesh_document

        return mesh_document(data, suffix[1:], name, pose, units or "mm")
    if suffix == ".dxf":
        from algrasp.cad.dxf import dxf_pieces, read_dxf

        drawing = read_dxf(data)
        pieces, doc_units, k = dxf_pieces(drawing, layer)
        source: dict[str, Any] = {"format": "dxf", "layer": layer}
        # With --units the unit assumption is the user's, not ours to warn about.
        kept = [w for w in drawing.algrasp_warnings if units is None or "$INSUNITS" not in w][:MAX_WARNINGS]
        if kept:
            source["warnings"] = kept
    elif suffix == ".svg":
        from algrasp.cad.svg import svg_pieces

        pieces, doc_units, k = svg_pieces(data, element_id), "mm", 1.0
        source = {"format": "svg", "id": element_id}
    else:
        raise PartDocumentError("FILE", f"unsupported file type {suffix or '(none)'}: use .json, {', '.join(CAD_SUFFIXES)}")
    loops = chain(pieces, tolerance if tolerance is not None else default_tolerance(pieces))
    loops = [[_scale(s, k) for s in lp] for lp in loops]
    return outline_document(loops, name, units or doc_units, source)


def _check_options(suffix: str, layer: str | None, element_id: str | None, pose: int | None) -> None:
    if layer is not None and suffix != ".dxf":
        raise ConfigError("--layer", "only DXF drawings have layers")
    if element_id is not None and suffix != ".svg":
        raise ConfigError("--id", "only SVG documents have element ids")
    if pose is not None and suffix in (".dxf", ".svg"):
        raise ConfigError("--pose", "only 3-D meshes have resting poses")


def import_file(path: str, **options: Any) -> dict[str, Any]:
    """``import_bytes`` of a file on disk (size-limited)."""
    p = Path(path)
    if not p.is_file():
        raise PartDocumentError("FILE", f"no such file: {path}")
    if p.stat().st_size > DEFAULT_LIMITS.max_document_bytes * 8:
        raise LimitExceededError("FILE", f"file larger than {DEFAULT_LIMITS.max_document_bytes * 8} bytes")
    return import_bytes(p.name, p.read_bytes(), **options)
