"""Several parts on one sheet (issue 17), on a real nested sheet of ten gears
(koppi/involute-gear-collection, CC0; tests/data/real/SOURCES.md)."""

from __future__ import annotations

import io
import json
from pathlib import Path

import ezdxf
import ezdxf.bbox
import pytest

from algrasp.cli import main
from algrasp.errors import ConfigError, PartDocumentError
from algrasp.io.cad import import_bytes, list_parts

SHEET = Path(__file__).parents[3] / "data" / "real" / "koppi-involute-teeth-20-multiple.dxf"


def test_real_sheet_lists_its_ten_gears() -> None:
    out = list_parts(SHEET.name, SHEET.read_bytes())
    assert len(out["parts"]) == 10
    # ezdxf's own bounding box of the whole sheet holds every part's box
    box = ezdxf.bbox.extents(ezdxf.read(io.StringIO(SHEET.read_text())).modelspace())
    for r in out["parts"]:
        x0, y0, x1, y1 = r["bbox"]
        assert r["holes"] == 1 and x1 - x0 == pytest.approx(56.0225, abs=1e-3)
        assert box.extmin.x - 1e-9 <= x0 and x1 <= box.extmax.x + 1e-9
    with pytest.raises(PartDocumentError, match="holds 10 parts"):
        import_bytes(SHEET.name, SHEET.read_bytes())
    doc = import_bytes(SHEET.name, SHEET.read_bytes(), part=3)
    assert doc["name"].endswith("#3") and len(doc["holes"]) == 1
    with pytest.raises(ConfigError, match="no part 10"):
        import_bytes(SHEET.name, SHEET.read_bytes(), part=10)


def test_cli_list_json_and_plan_one_part(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["import", str(SHEET), "--list", "--json"]) == 0
    assert len(json.loads(capsys.readouterr().out)["parts"]) == 10
    assert main(["plan", str(SHEET), "--part", "2", "--json", "--no-record"]) == 0
    plan = json.loads(capsys.readouterr().out)
    assert plan["symmetry_period_deg"] == 18.0 and plan["verified"]
    assert main(["analyze", str(SHEET), "--no-record"]) == 2
    assert "--part K" in capsys.readouterr().err


def _frame_sheet() -> bytes:
    d = ezdxf.new(units=4)
    m = d.modelspace()
    m.add_lwpolyline([(0, 0), (200, 0), (200, 100), (0, 100)], close=True, dxfattribs={"layer": "FRAME"})
    m.add_lwpolyline([(140, 0), (200, 0), (200, 20), (140, 20)], close=True, dxfattribs={"layer": "FRAME"})
    m.add_lwpolyline([(20, 20), (80, 20), (80, 60), (20, 60)], close=True, dxfattribs={"layer": "CUT"})
    m.add_circle((50, 40), 5, dxfattribs={"layer": "CUT"})
    m.add_line((10, 40), (90, 40), dxfattribs={"layer": "CENTER"})  # a centre line: an open chain
    m.add_line((20, 20), (80, 20), dxfattribs={"layer": "CUT"})  # drawn twice
    m.add_line((30, 30), (30, 30), dxfattribs={"layer": "CUT"})  # zero length
    m.add_text("PLATE 1", dxfattribs={"layer": "TEXT"}).set_placement((30, 50))
    buf = io.StringIO()
    d.write(buf)
    return buf.getvalue().encode()


def test_frame_title_block_centre_lines_text_and_duplicates_are_set_aside() -> None:
    doc = import_bytes("plate.dxf", _frame_sheet())
    assert len(doc["boundary"]) == 4 and len(doc["holes"]) == 1
    assert [r["layer"] for r in list_parts("plate.dxf", _frame_sheet())["parts"]] == ["CUT"]
    warnings = " ".join(doc["source"]["warnings"])
    assert "frame" in warnings and "open chain" in warnings
    assert "duplicated" in warnings and "zero-length" in warnings


def test_a_sheet_in_a_catalogue_is_one_item_per_part(tmp_path: Path) -> None:
    from service.catalogue import read_catalogue

    (tmp_path / "gears.dxf").write_bytes(SHEET.read_bytes())
    entries = read_catalogue(tmp_path, 100, 10_000_000)
    assert [n for n, _, _ in entries] == [f"gears#{k}" for k in range(10)]
    assert all(err is None and len(doc["holes"]) == 1 for _, doc, err in entries)


def test_block_content_is_named_by_block_and_insert_and_self_insertion_is_refused() -> None:
    d = ezdxf.new(units=4)
    blk = d.blocks.new("BRACKET")
    blk.add_line((0, 0), (10, 0))
    blk.add_line((10, 0), (10, 5))
    insert = d.modelspace().add_blockref("BRACKET", (0, 0))
    buf = io.StringIO()
    d.write(buf)
    with pytest.raises(PartDocumentError) as e:
        import_bytes("b.dxf", buf.getvalue().encode())
    assert f"in block 'BRACKET' (INSERT #{insert.dxf.handle})" in str(e.value) and "#None" not in str(e.value)
    loop = ezdxf.new(units=4)
    selfish = loop.blocks.new("LOOP")
    selfish.add_line((0, 0), (1, 0))
    selfish.add_blockref("LOOP", (1, 0))
    loop.modelspace().add_blockref("LOOP", (0, 0))
    buf = io.StringIO()
    loop.write(buf)
    with pytest.raises(PartDocumentError, match="nested deeper"):
        import_bytes("loop.dxf", buf.getvalue().encode())


def test_small_gaps_close_arcs_included() -> None:
    """0.015 mm gaps on a 300 mm plate (seen in real drawings) close; the arc corner stays
    exact and a bridging line keeps the loop continuous."""
    from algrasp.geometry.part import load_part

    d = ezdxf.new(units=4)
    m = d.modelspace()
    g = 0.015
    m.add_line((0, 0), (300 - g, 0))
    m.add_line((300, g), (300, 90))
    m.add_arc((290, 90), 10, 0, 90)
    m.add_line((290 + g, 100), (0, 100))
    m.add_line((0, 100 - g), (0, g))
    buf = io.StringIO()
    d.write(buf)
    doc = import_bytes("plate.dxf", buf.getvalue().encode())
    assert any(s["type"] == "arc" and s["radius"] == 10 for s in doc["boundary"])
    part = load_part(doc)
    assert part.area == pytest.approx(300 * 100 - (100 - 25 * 3.141592653589793) * 1, rel=1e-4)


def test_spline_with_bad_knots_is_one_clear_error() -> None:
    """A SPLINE whose knot vector does not fit its control points (seen in a real file
    written by another tool) is refused naming the entity — not a traceback."""
    d = ezdxf.new(units=4)
    sp = d.modelspace().add_spline(dxfattribs={"layer": "CUT"})
    sp.control_points = [(0, 0), (1, 2), (3, 2), (4, 0)]
    sp.dxf.degree = 3
    sp.knots = [0, 0, 0, 1, 1]
    buf = io.StringIO()
    d.write(buf)
    with pytest.raises(PartDocumentError, match=r"SPLINE #\w+: malformed SPLINE on layer 'CUT'.*knot"):
        import_bytes("s.dxf", buf.getvalue().encode())


def test_kerf_loop_resolves_to_the_region_it_bounds() -> None:
    """A laser-cut outline with a 0.1 mm kerf loop at a corner (boxes.py draws these)."""
    from algrasp.geometry.part import load_part

    pts = [(0, 0), (50, 0), (50, 30), (50.1, 30.1), (49.9, 30.1), (50, 30), (0, 30)]
    d = ezdxf.new(units=4)
    d.modelspace().add_lwpolyline(pts, close=True)
    buf = io.StringIO()
    d.write(buf)
    doc = import_bytes("kerf.dxf", buf.getvalue().encode())
    assert any("kerf" in w for w in doc["source"]["warnings"])
    assert load_part(doc).area == pytest.approx(1500.0, rel=1e-3)


def _workshop_drawing() -> bytes:
    """A drawing as a draughtsman makes it: frame and title block, the part (a plate with
    a bore) with rendered dimensions, a hatched section view on the part's own layer, and
    a part number engraved inside the plate as closed polylines."""
    d = ezdxf.new(units=4, setup=True)
    m = d.modelspace()
    m.add_lwpolyline([(0, 0), (297, 0), (297, 210), (0, 210)], close=True, dxfattribs={"layer": "BORDER"})
    for box in ([(197, 0), (297, 0), (297, 40), (197, 40)], [(197, 0), (247, 0), (247, 20), (197, 20)]):
        m.add_lwpolyline(box, close=True, dxfattribs={"layer": "BORDER"})
    m.add_lwpolyline([(30, 60), (130, 60), (130, 140), (30, 140)], close=True, dxfattribs={"layer": "OUTLINE"})
    m.add_circle((80, 100), 12, dxfattribs={"layer": "OUTLINE"})
    for x in (40.0, 48.0):  # an engraved "II": two closed strokes
        m.add_lwpolyline([(x, 70), (x + 3, 70), (x + 3, 80), (x, 80)], close=True, dxfattribs={"layer": "ENGRAVE"})
    dim = m.add_linear_dim(base=(30, 50), p1=(30, 60), p2=(130, 60), dxfattribs={"layer": "DIM"})
    dim.render()
    m.add_lwpolyline([(160, 60), (170, 60), (170, 140), (160, 140)], close=True, dxfattribs={"layer": "OUTLINE"})
    hatch = m.add_hatch(dxfattribs={"layer": "HATCH"})
    hatch.set_pattern_fill("ANSI31", scale=0.5)
    hatch.paths.add_polyline_path([(160, 60), (170, 60), (170, 140), (160, 140)], is_closed=True)
    m.add_text("PLATE 7", dxfattribs={"layer": "TEXT"}).set_placement((210, 10))
    buf = io.StringIO()
    d.write(buf)
    return buf.getvalue().encode()


def test_workshop_drawing_finds_the_plate_its_bore_and_nothing_else() -> None:
    data = _workshop_drawing()
    listing = list_parts("plate.dxf", data)
    assert [(r["layer"], r["holes"]) for r in listing["parts"]] == [("OUTLINE", 1)]
    assert listing["parts"][0]["bbox"] == pytest.approx([30, 60, 130, 140])
    ignored = " ".join(listing["ignored"])
    assert "frame" in ignored and "title block" in ignored and "section view" in ignored and "engraving" in ignored
    doc = import_bytes("plate.dxf", data)
    assert len(doc["boundary"]) == 4 and len(doc["holes"]) == 1
    assert "DIMENSION" in " ".join(doc["source"]["warnings"])


def test_hatched_parts_alone_are_still_parts() -> None:
    d = ezdxf.new(units=4)
    m = d.modelspace()
    m.add_lwpolyline([(0, 0), (10, 0), (10, 5), (0, 5)], close=True)
    m.add_hatch().paths.add_polyline_path([(0, 0), (10, 0), (10, 5), (0, 5)], is_closed=True)
    buf = io.StringIO()
    d.write(buf)
    assert len(list_parts("h.dxf", buf.getvalue().encode())["parts"]) == 1
