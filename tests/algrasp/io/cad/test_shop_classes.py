"""Drawings as shops send them (issue 32), one class each, built here so the truth is known
by construction (areas, counts and boxes written in the test); the same classes in real
files are checked in test_shop_corpus.py."""

from __future__ import annotations

import io
import math

import ezdxf
import pytest

from algrasp.geometry.part import load_part
from algrasp.io.cad import import_bytes, list_parts


def _bytes(d: ezdxf.document.Drawing) -> bytes:
    buf = io.StringIO()
    d.write(buf)
    return buf.getvalue().encode()


def test_a_segment_shorter_than_the_join_tolerance_is_no_loop_and_no_traceback() -> None:
    """KiCad stroke outlines and title blocks hold segments of 1e-9 mm: once a shapely
    'linearring requires at least 4 coordinates' traceback."""
    d = ezdxf.new(units=4)
    m = d.modelspace()
    m.add_lwpolyline([(0, 0), (40, 0), (40, 20), (0, 20)], close=True)
    m.add_line((40, 20), (40, 20 + 1e-9))  # a stub at a corner
    m.add_line((10, 10), (10 + 1e-9, 10))  # a lone speck
    m.add_lwpolyline([(5, 5), (5 + 1e-9, 5), (5, 5 + 1e-9)], close=True)  # a closed speck
    doc = import_bytes("stub.dxf", _bytes(d))
    assert load_part(doc).area == pytest.approx(800.0, rel=1e-9) and not doc["holes"]


def test_a_grid_cut_by_full_length_lines_is_nine_parts() -> None:
    """Common-line cutting: 4 + 4 lines across a 30 mm square cut it into 9 parts; every
    part is a 10 mm square."""
    d = ezdxf.new(units=4)
    m = d.modelspace()
    for k in range(4):
        m.add_line((0, 10 * k), (30, 10 * k))
        m.add_line((10 * k, 0), (10 * k, 30))
    rows = list_parts("grid.dxf", _bytes(d))["parts"]
    assert len(rows) == 9 and all(r["area"] == pytest.approx(100.0) for r in rows)


def test_neighbours_sharing_cut_lines_and_arcs_both_close() -> None:
    """Three plates in a row sharing their sides (drawn once, or overlapping part-way), and
    a plate sharing an arc with a round tab: every part closes, with its own area."""
    d = ezdxf.new(units=4)
    m = d.modelspace()
    m.add_lwpolyline([(0, 0), (20, 0), (20, 10), (0, 10)], close=True)
    m.add_lwpolyline([(20, 0), (40, 0), (40, 10), (20, 10)])  # open: its left side is the first plate's right
    m.add_line((40, 2), (55, 2))  # the third plate shares only part of the second's right side
    m.add_line((55, 2), (55, 8))
    m.add_line((55, 8), (40, 8))
    m.add_line((40, 8), (40, 2))  # drawn again over the second plate's side: a duplicate stretch
    m.add_arc((10, 20), 5, 0, 180)  # a tab on the first plate's top… sharing the plate's top edge
    m.add_line((5, 20), (5, 10))
    m.add_line((15, 20), (15, 10))
    areas = sorted(round(r["area"], 6) for r in list_parts("row.dxf", _bytes(d))["parts"])
    tab = 10 * 10 + math.pi * 25 / 2
    assert areas == pytest.approx(sorted([200.0, 200.0, 90.0, tab]), rel=1e-4)


def test_a_border_on_the_parts_layer_is_a_frame_not_a_part() -> None:
    d = ezdxf.new(units=4)
    m = d.modelspace()
    m.add_lwpolyline([(0, 0), (500, 0), (500, 300), (0, 300)], close=True)
    for k in range(13):
        x, y = 10 + (k % 5) * 95, 10 + (k // 5) * 95
        m.add_lwpolyline([(x, y), (x + 80, y), (x + 80, y + 80), (x, y + 80)], close=True)
        m.add_circle((x + 40, y + 40), 10)
    out = list_parts("sheet.dxf", _bytes(d))
    assert len(out["parts"]) == 13 and all(r["holes"] == 1 for r in out["parts"])
    assert any(i.startswith("frame") for i in out["ignored"])


def test_a_hatched_logo_is_engraving_and_never_removes_its_plate() -> None:
    d = ezdxf.new(units=4)
    m = d.modelspace()
    m.add_lwpolyline([(0, 0), (100, 0), (100, 60), (0, 60)], close=True)
    m.add_circle((10, 10), 3)
    m.add_circle((90, 10), 3)
    m.add_lwpolyline([(40, 20), (60, 20), (50, 40)], close=True)
    m.add_hatch().paths.add_polyline_path([(40, 20), (60, 20), (50, 40)], is_closed=True)
    out = list_parts("logo.dxf", _bytes(d))
    assert [r["holes"] for r in out["parts"]] == [2]
    assert any("hatch" in i for i in out["ignored"])


@pytest.mark.parametrize("layer", ["彫刻パス", "Gravur", "gravure", "grabado", "雕刻", "각인", "Гравировка"])
def test_engraving_layers_in_any_language_are_not_holes(layer: str) -> None:
    d = ezdxf.new(units=4)
    d.layers.add(layer)
    m = d.modelspace()
    m.add_lwpolyline([(0, 0), (100, 0), (100, 60), (0, 60)], close=True, dxfattribs={"layer": "CUT"})
    m.add_circle((50, 30), 8, dxfattribs={"layer": "CUT"})
    for x in (20.0, 28.0):
        m.add_lwpolyline([(x, 10), (x + 3, 10), (x + 3, 18), (x, 18)], close=True, dxfattribs={"layer": layer})
    out = list_parts("plate.dxf", _bytes(d))
    assert [r["holes"] for r in out["parts"]] == [1]


def test_engraved_letters_on_the_parts_own_layer_are_not_holes() -> None:
    """Five different letter outlines in a row; the two drilled holes stay holes. A grille
    of equal slots stays holes."""
    d = ezdxf.new(units=4)
    m = d.modelspace()
    m.add_lwpolyline([(0, 0), (200, 0), (200, 100), (0, 100)], close=True)
    m.add_circle((20, 20), 5)
    m.add_circle((180, 20), 5)
    glyphs = [[(0, 0), (2, 0), (2, 6), (0, 6)], [(0, 0), (4, 0), (4, 6), (2, 3), (0, 6)], [(0, 0), (4, 0), (2, 6)],
              [(0, 0), (4, 0), (4, 2), (1, 2), (1, 6), (0, 6)], [(0, 0), (3, 0), (4, 3), (3, 6), (0, 6)]]
    for k, g in enumerate(glyphs):
        m.add_lwpolyline([(x + 60 + 6 * k, y + 50) for x, y in g], close=True)
    assert [r["holes"] for r in list_parts("text.dxf", _bytes(d))["parts"]] == [2]
    for k in range(6):
        m.add_lwpolyline([(40 + 8 * k, 75), (43 + 8 * k, 75), (43 + 8 * k, 90), (40 + 8 * k, 90)], close=True)
    assert [r["holes"] for r in list_parts("grille.dxf", _bytes(d))["parts"]] == [8]


def test_a_circle_drawn_as_two_half_arcs_is_one_hole() -> None:
    """Same ends, centre, radius and sweep: once taken for a duplicate (one half dropped,
    the hole lost)."""
    d = ezdxf.new(units=4)
    m = d.modelspace()
    m.add_lwpolyline([(0, 0), (50, 0), (50, 30), (0, 30)], close=True)
    m.add_arc((25, 15), 5, 0, 180)
    m.add_arc((25, 15), 5, 180, 360)
    doc = import_bytes("half.dxf", _bytes(d))
    assert len(doc["holes"]) == 1
    assert load_part(doc).area == pytest.approx(1500 - math.pi * 25, rel=1e-9)


def test_the_same_hole_drawn_twice_a_hair_apart_is_one_hole() -> None:
    d = ezdxf.new(units=4)
    m = d.modelspace()
    m.add_lwpolyline([(0, 0), (50, 0), (50, 30), (0, 30)], close=True)
    m.add_circle((25, 15), 3)
    m.add_circle((25, 15), 3 - 0.0045)  # 0.009 mm smaller in diameter
    out = list_parts("twice.dxf", _bytes(d))
    assert [r["holes"] for r in out["parts"]] == [1]
    assert any("near-duplicate" in w for w in out["warnings"])


def test_small_gaps_close_against_the_chains_meeting_there_not_the_sheet() -> None:
    """A 20 mm part 0.035 mm short of closing at every corner, on a 400 mm sheet: once set
    aside (1e-4 of the sheet is 0.04… but of a 300 mm sheet 0.03). A dimension line 0.6 mm
    off the outline stays apart."""
    d = ezdxf.new(units=4)
    m = d.modelspace()
    g = 0.035
    m.add_line((0, 0), (20 - g, 0))
    m.add_line((20, 0), (20, 20 - g))
    m.add_line((20, 20), (g, 20))
    m.add_line((0, 20), (0, g))
    m.add_line((0, -0.6), (0, -8))  # an extension line
    m.add_lwpolyline([(380, 380), (400, 380), (400, 400), (380, 400)], close=True)
    out = list_parts("gaps.dxf", _bytes(d))
    assert sorted(round(r["area"], 1) for r in out["parts"]) == [400.0, 400.0]
    assert any("4 gap(s) closed" in w and "0.035" in w for w in out["warnings"])
    assert any("open chain" in w for w in out["warnings"])


def test_mm_content_under_an_inch_header_is_read_in_mm_and_said() -> None:
    """KiCad writes $MEASUREMENT 0 with millimetre content: a 100 × 60 board read as
    inches would be 2.5 m across."""
    d = ezdxf.new()
    d.header["$MEASUREMENT"] = 0
    d.modelspace().add_lwpolyline([(0, 0), (100, 0), (100, 60), (0, 60)], close=True)
    data = _bytes(d).replace(b"$INSUNITS", b"$XNSUNITS")  # as KiCad: no $INSUNITS at all
    doc = import_bytes("board.dxf", data)
    assert doc["units"] == "mm" and any("--units in" in w for w in doc["source"]["warnings"])
    assert import_bytes("board.dxf", data, units="in")["units"] == "in"
    little = ezdxf.new()
    little.header["$MEASUREMENT"] = 0
    little.modelspace().add_lwpolyline([(0, 0), (4, 0), (4, 2.5), (0, 2.5)], close=True)
    small = _bytes(little).replace(b"$INSUNITS", b"$XNSUNITS")
    assert import_bytes("small.dxf", small)["units"] == "in"  # 4 in is a plausible part


def test_a_drawing_with_views_keeps_the_plan_view() -> None:
    """Plan view with two bores, a front view under it and a hatched section beside it,
    dimensions, a frame with a title block: one part, the plan view."""
    d = ezdxf.new(units=4, setup=True)
    m = d.modelspace()
    m.add_lwpolyline([(0, 0), (420, 0), (420, 297), (0, 297)], close=True)
    m.add_line((300, 0), (300, 40))
    m.add_line((300, 40), (420, 40))
    m.add_line((300, 20), (420, 20))
    m.add_text("BRACKET", dxfattribs={"height": 5}).set_placement((310, 25))
    m.add_lwpolyline([(50, 100), (150, 100), (150, 180), (50, 180)], close=True)
    m.add_circle((75, 140), 6)
    m.add_circle((125, 140), 6)
    m.add_lwpolyline([(50, 60), (150, 60), (150, 70), (50, 70)], close=True)
    m.add_lwpolyline([(190, 100), (200, 100), (200, 180), (190, 180)], close=True)
    hatch = m.add_hatch()
    hatch.set_pattern_fill("ANSI31", scale=0.5)
    hatch.paths.add_polyline_path([(190, 100), (200, 100), (200, 180), (190, 180)], is_closed=True)
    m.add_linear_dim(base=(50, 90), p1=(50, 100), p2=(150, 100)).render()
    out = list_parts("views.dxf", _bytes(d))
    assert [(r["holes"], r["bbox"]) for r in out["parts"]] == [(2, pytest.approx([50, 100, 150, 180]))]
    ignored = " ".join(out["ignored"])
    assert "frame" in ignored and "title block" in ignored and "section view" in ignored and "side view" in ignored


def test_copies_of_a_part_side_by_side_are_parts_not_views() -> None:
    d = ezdxf.new(units=4, setup=True)
    m = d.modelspace()
    for x in (0, 60):
        m.add_lwpolyline([(x, 0), (x + 50, 0), (x + 50, 30), (x, 30)], close=True)
        m.add_circle((x + 25, 15), 4)
    m.add_linear_dim(base=(0, -10), p1=(0, 0), p2=(50, 0)).render()
    assert len(list_parts("copies.dxf", _bytes(d))["parts"]) == 2


def test_centre_lines_by_linetype_never_cut_a_hole() -> None:
    """A centre cross drawn exactly to a bore's edge (both ends on the circle) would cut
    the bore in quarters; its CENTER linetype says it is no cut."""
    d = ezdxf.new(units=4, setup=True)
    m = d.modelspace()
    m.add_lwpolyline([(0, 0), (50, 0), (50, 30), (0, 30)], close=True)
    m.add_circle((25, 15), 5)
    m.add_line((25, 10), (25, 20), dxfattribs={"linetype": "CENTER"})
    m.add_line((20, 15), (30, 15), dxfattribs={"linetype": "CENTER"})
    doc = import_bytes("bore.dxf", _bytes(d))
    assert load_part(doc).area == pytest.approx(1500 - 25 * math.pi, rel=1e-9)


def test_a_construction_line_through_two_corners_does_not_cut_the_part() -> None:
    """An open line snapped through two corners and running on past the outline: its
    stretch inside is a stray chord, not a cut."""
    d = ezdxf.new(units=4)
    m = d.modelspace()
    m.add_lwpolyline([(0, 0), (40, 0), (40, 20), (0, 20)], close=True)
    m.add_line((-10, -5), (50, 25))  # through (0, 0) and (40, 20)
    m.add_line((0, 0), (40, 20))  # a diagonal from corner to corner on its own does cut
    assert len(list_parts("diag.dxf", _bytes(d))["parts"]) == 2
    d2 = ezdxf.new(units=4)
    d2.modelspace().add_lwpolyline([(0, 0), (40, 0), (40, 20), (0, 20)], close=True)
    d2.modelspace().add_line((-10, -5), (50, 25))
    assert [r["area"] for r in list_parts("stray.dxf", _bytes(d2))["parts"]] == [pytest.approx(800.0)]
