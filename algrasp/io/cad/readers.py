"""The file types algrasp reads: one registry, from which every list of suffixes, every
"which reader" question and every "unsupported file type" message is derived.

>>> file_type("bracket.DXF").kind, file_type("bracket.DXF").library
('drawing', 'ezdxf')
>>> file_type("part.step") is None
True
>>> supported()
'.json, .dxf, .svg, .stl, .obj, .ply, .off, .glb'
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import PurePath
from typing import Literal

from algrasp.errors import PartDocumentError


@dataclass(frozen=True)
class FileType:
    """One readable file type: its ``suffix`` (lower case, with the dot), its ``kind`` (a
    part ``document`` in JSON, a 2-D ``drawing`` sheet, a 3-D ``mesh`` laid on a resting
    pose) and the ``library`` that reads it (None: the standard library)."""

    suffix: str
    kind: Literal["document", "drawing", "mesh"]
    library: str | None
    description: str


FILE_TYPES: tuple[FileType, ...] = (
    FileType(".json", "document", None, "part document"),
    FileType(".dxf", "drawing", "ezdxf", "DXF drawing"),
    FileType(".svg", "drawing", "svgelements", "SVG drawing"),
    *(FileType(s, "mesh", "trimesh", f"{s[1:].upper()} mesh") for s in (".stl", ".obj", ".ply", ".off", ".glb")),
)
"""Every type read, in the order messages list them."""

_BY_SUFFIX = {t.suffix: t for t in FILE_TYPES}
PART_SUFFIXES = tuple(t.suffix for t in FILE_TYPES)
"""Suffixes of files that hold parts (catalogues, archives)."""
CAD_SUFFIXES = tuple(t.suffix for t in FILE_TYPES if t.kind != "document")
"""Suffixes of files that are imported (drawings and meshes)."""
DRAWING_SUFFIXES = tuple(t.suffix for t in FILE_TYPES if t.kind == "drawing")
MESH_SUFFIXES = tuple(t.suffix for t in FILE_TYPES if t.kind == "mesh")


def suffix_of(filename: str) -> str:
    return PurePath(filename).suffix.lower()


def file_type(filename: str) -> FileType | None:
    """The registered type of ``filename`` by its suffix (any case), or None."""
    return _BY_SUFFIX.get(suffix_of(filename))


def is_cad(filename: str) -> bool:
    """Whether ``filename`` is a drawing or a mesh (imported, not parsed as a document)."""
    t = file_type(filename)
    return t is not None and t.kind != "document"


def supported(kinds: tuple[str, ...] = ("document", "drawing", "mesh")) -> str:
    """The suffixes of the given kinds, as a message lists them."""
    return ", ".join(t.suffix for t in FILE_TYPES if t.kind in kinds)


def unsupported(filename: str, field: str, kinds: tuple[str, ...] = ("document", "drawing", "mesh")) -> PartDocumentError:
    """The error for a file this place cannot read: names the field, its suffix and what
    this place reads (only ``kinds``: a mesh given where a sheet is needed is told so)."""
    suffix = suffix_of(filename) or "(none)"
    t = file_type(filename)
    why = f"a {t.description} cannot be read here" if t is not None else f"unsupported file type {suffix}"
    return PartDocumentError(field, f"{why}: use {supported(kinds)}")
