"""One registry of file types (issue 33): every registered type is read by the import
entry point and by catalogues; everything else is refused naming the field and listing
the registry — truthfully (an STL given where a sheet is listed once read "unsupported
file type .stl: use … .stl")."""

from __future__ import annotations

import io
import json
import zipfile
from pathlib import Path

import pytest

from algrasp.errors import PartDocumentError
from algrasp.io.cad import import_bytes, list_parts
from algrasp.io.cad.readers import CAD_SUFFIXES, FILE_TYPES, PART_SUFFIXES, file_type
from algrasp.io.parts import read_part_file
from service.catalogue import read_archive

SQUARE_SVG = b'<svg xmlns="http://www.w3.org/2000/svg" width="10mm" height="10mm" viewBox="0 0 10 10">' \
             b'<rect x="1" y="1" width="8" height="4"/></svg>'


def _dxf() -> bytes:
    import ezdxf

    doc = ezdxf.new()
    doc.modelspace().add_lwpolyline([(0, 0), (8, 0), (8, 4), (0, 4)], close=True)
    out = io.StringIO()
    doc.write(out)
    return out.getvalue().encode()


def _mesh(suffix: str) -> bytes:
    import trimesh

    data = trimesh.creation.box((8.0, 4.0, 2.0)).export(file_type=suffix[1:])
    return data if isinstance(data, bytes) else data.encode()


def sample(suffix: str) -> bytes:
    """A small real file of each registered type (made by the libraries that write them)."""
    if suffix == ".json":
        return json.dumps({"polygon": [[0, 0], [8, 0], [8, 4], [0, 4]]}).encode()
    return {".dxf": _dxf, ".svg": lambda: SQUARE_SVG}.get(suffix, lambda: _mesh(suffix))()


@pytest.mark.parametrize("suffix", CAD_SUFFIXES)
def test_every_registered_drawing_and_mesh_imports(suffix: str) -> None:
    doc = import_bytes(f"part{suffix.upper()}", sample(suffix))
    loop = doc.get("polygon") or doc["boundary"]
    xs = [p[0] for seg in loop for p in ([seg] if isinstance(seg, list) else [seg["start"], seg["end"]])]
    assert max(xs) - min(xs) == pytest.approx(8.0, rel=1e-6)  # the 8-long side, whatever the reader


def test_a_catalogue_reads_every_registered_type() -> None:
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        for suffix in PART_SUFFIXES:
            z.writestr(f"part{suffix}", sample(suffix))
        z.writestr("notes.txt", "not a part")
    entries = read_archive(buf.getvalue(), 100, 10_000_000)
    assert len(entries) == len(PART_SUFFIXES) and {n for n, _, _ in entries} == {"part"}
    assert all(e is None for _, _, e in entries), [e for _, _, e in entries]


def test_the_registry_is_the_one_list() -> None:
    assert tuple(t.suffix for t in FILE_TYPES) == PART_SUFFIXES and ".json" not in CAD_SUFFIXES
    assert {t.library for t in FILE_TYPES} == {None, "ezdxf", "svgelements", "trimesh"}
    assert file_type("A.StL") is file_type("a.stl") is not None


def test_an_unknown_type_is_refused_naming_the_field(tmp_path: Path) -> None:
    with pytest.raises(PartDocumentError) as e:
        import_bytes("part.step", b"ISO-10303-21;")
    assert e.value.field == "FILE" and "unsupported file type .step: use .dxf, .svg, .stl" in e.value.message
    step = tmp_path / "part.step"
    step.write_bytes(b"ISO-10303-21;")
    with pytest.raises(PartDocumentError) as e:
        read_part_file(step)
    assert e.value.field == "PART" and e.value.message.endswith("use .json, .dxf, .svg, .stl, .obj, .ply, .off, .glb")


def test_a_mesh_where_a_sheet_is_needed_is_told_so() -> None:
    with pytest.raises(PartDocumentError) as e:
        list_parts("part.stl", sample(".stl"))
    assert e.value.message.endswith("a STL mesh cannot be read here: use .dxf, .svg")
