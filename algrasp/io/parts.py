"""Part files: a JSON part document or a CAD drawing/mesh, read into a part document.

The one reader of part files for the CLI, the Python API and the service's catalogues; JSON
goes through the same bounds as HTTP bodies (``algrasp.io.jsonguard``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from algrasp.errors import LimitExceededError, PartDocumentError
from algrasp.geometry.limits import DEFAULT_LIMITS
from algrasp.io.jsonguard import parse_json


def parse_part_json(data: bytes, where: str) -> dict[str, Any]:
    """A JSON part document within the bounds of :func:`~algrasp.io.jsonguard.parse_json`
    (finite numbers, bounded depth and sizes), and an object; else PartDocumentError naming ``where``."""
    doc = parse_json(data, where)
    if not isinstance(doc, dict):
        raise PartDocumentError(where, "a part document must be a JSON object")
    return doc


def read_part_file(path: str | Path, **import_options: Any) -> dict[str, Any]:
    """The part document in ``path``: a ``.json`` part document (size-limited), or a
    drawing/mesh imported with ``import_options`` (``layer``, ``element_id``, ``pose``,
    ``part``, ``tolerance``, ``units``)."""
    from algrasp.io.cad import import_file
    from algrasp.io.cad.readers import file_type, is_cad, suffix_of, unsupported

    p = Path(path)
    if is_cad(p.name):
        from algrasp.io.fence_import import refuse_layout

        return refuse_layout(import_file(str(p), **import_options), "PART")
    if suffix_of(p.name) and file_type(p.name) is None:  # no suffix: read as a JSON document
        raise unsupported(p.name, "PART")
    if not p.is_file():
        raise PartDocumentError("PART", f"no such file: {path}")
    if p.stat().st_size > DEFAULT_LIMITS.max_document_bytes:
        raise LimitExceededError("PART", f"file larger than {DEFAULT_LIMITS.max_document_bytes} bytes")
    return parse_part_json(p.read_bytes(), "PART")
