"""Several views of one part on a drawing sheet (issue 32, class 9), from real drawings of
tests/data/shops (truth read off each rendering and the drawing's own dimensions) and from
small drawings built here, where the truth is known by construction."""

from __future__ import annotations

import io
from pathlib import Path

import ezdxf
import pytest

from algrasp.io.cad import import_bytes, list_parts

SHOPS = Path(__file__).parents[3] / "data" / "shops"


def _real(folder: str, name: str) -> dict:
    path = SHOPS / folder / name
    return list_parts(path.name, path.read_bytes())


def _size(row: dict) -> list[float]:
    x0, y0, x1, y1 = row["bbox"]
    return sorted([x1 - x0, y1 - y0])


def _said(out: dict, words: str) -> list[str]:
    return [s for s in out["ignored"] if s.startswith(words)]


def test_a_machined_clamp_in_four_views_is_its_plan_view() -> None:
    """SolidWorks A3 sheet of a torch clamp: top view (a flange on a split ring, 59.93 wide
    and 77.03 deep by its dimensions), front and side views under and beside it, an
    isometric view. Tangent edges split each view into faces: 16 "parts" before."""
    out = _real("batch-fl2", "irnas-goodenoughcnc-torch-mount-drawing.dxf")
    assert len(out["parts"]) == 1
    assert _size(out["parts"][0]) == pytest.approx([59.933, 77.026], rel=1e-3)
    assert len(_said(out, "projected view")) == 2  # front and side
    assert len(_said(out, "pictorial view")) == 1  # the isometric view
    assert any("joined into one outline" in w for w in out["warnings"])


def test_a_section_view_is_set_aside_with_the_pocket_it_shows() -> None:
    """Voron build plate: the hatched section A-A shows a counterbore pocket as an
    unhatched loop, which was listed as a second part."""
    out = _real("batch-sz", "vorondesign-voron-2-build-plate-300-drawing.dxf")
    assert [(r["holes"], _size(r)) for r in out["parts"]] == [(6, pytest.approx([305.0, 305.0]))]
    assert len(_said(out, "section view")) == 1


def test_an_l_bracket_lies_on_its_long_leg() -> None:
    """Three views of an L-bracket: the 80 x 40 leg with 3 holes, the L profile, and the
    flange (40 wide, one M8 hole) above the leg's edge, whose box is also 80 x 40: the plan
    is the view of the largest face, not the largest box."""
    out = _real("batch-views", "irnas-goodenoughcnc-bracket-left-drawing.dxf")
    assert [(r["holes"], _size(r)) for r in out["parts"]] == [(3, pytest.approx([40.0, 80.0]))]


@pytest.mark.parametrize(("name", "holes", "size"), [
    ("irnas-goodenoughcnc-tightener-spacer-drawing.dxf", 2, [40.0, 43.0]),
    ("irnas-goodenoughcnc-linear-guide-mount-drawing.dxf", 1, [25.0, 30.0]),
    ("vorondesign-voron-2-build-plate-350-drawing.dxf", 6, [355.0, 355.0]),
])
def test_real_multi_view_drawings_give_their_plan(name: str, holes: int, size: list[float]) -> None:
    out = _real("batch-views", name)
    assert [(r["holes"], _size(r)) for r in out["parts"]] == [(holes, pytest.approx(size, rel=1e-3))]


def test_a_drawing_at_2_to_1_is_read_at_full_size() -> None:
    """The linear guide mount is drawn at 2:1 (60 x 50 on the sheet); its dimensions read
    30 and 25 (DIMLFAC 0.5)."""
    out = _real("batch-views", "irnas-goodenoughcnc-linear-guide-mount-drawing.dxf")
    assert _size(out["parts"][0]) == pytest.approx([25.0, 30.0])
    assert any("2:1" in w and "DIMLFAC" in w for w in out["warnings"])


def _bytes(d: ezdxf.document.Drawing) -> bytes:
    buf = io.StringIO()
    d.write(buf)
    return buf.getvalue().encode()


def _box(m: object, x0: float, y0: float, x1: float, y1: float) -> None:
    m.add_lwpolyline([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], close=True)  # type: ignore[attr-defined]


def _block_drawing(side_view: bool) -> bytes:
    """A 60 x 40 x 20 block: plan (60 wide, 40 deep, one bore) at the top, front view under
    it (60 wide, 20 high, a cross hole), and optionally the side view beside the front
    (40 wide, 20 high): plan depth 40 = side width."""
    d = ezdxf.new(units=4, setup=True)
    m = d.modelspace()
    _box(m, 0, 100, 60, 140)
    m.add_circle((30, 120), 8)
    _box(m, 0, 40, 60, 60)
    m.add_circle((15, 50), 3)
    if side_view:
        _box(m, 100, 40, 140, 60)
        m.add_line((120, 40), (120, 60))  # a visible edge splits the side view
    m.add_linear_dim(base=(0, 90), p1=(0, 100), p2=(60, 100)).render()
    return _bytes(d)


def test_three_views_agreeing_on_width_depth_and_height_are_one_part() -> None:
    out = list_parts("block.dxf", _block_drawing(side_view=True))
    assert [(r["holes"], r["bbox"]) for r in out["parts"]] == [(1, pytest.approx([0, 100, 60, 140]))]
    assert len(_said(out, "projected view")) == 1 and len(_said(out, "side view")) == 1


def test_two_plates_of_one_width_with_holes_stay_two_parts() -> None:
    """Without a side view tying them together, two aligned loops with holes of their own
    are two parts (a front and a back plate)."""
    out = list_parts("plates.dxf", _block_drawing(side_view=False))
    assert len(out["parts"]) == 2


def test_an_isometric_view_is_set_aside_once_views_are_recognised() -> None:
    """Plan and elevation of a plate, and an isometric sketch of it no dimension measures:
    edges at 30 and 150 degrees."""
    d = ezdxf.new(units=4, setup=True)
    m = d.modelspace()
    _box(m, 0, 100, 60, 140)
    m.add_circle((30, 120), 8)
    _box(m, 0, 80, 60, 85)
    c, s = 0.8660254, 0.5
    pts = [(150, 100), (150 + 60 * c, 100 + 60 * s), (150 + 60 * c - 40 * c, 100 + 60 * s + 40 * s),
           (150 - 40 * c, 100 + 40 * s)]
    m.add_lwpolyline(pts, close=True)
    m.add_linear_dim(base=(0, 150), p1=(0, 140), p2=(60, 140)).render()
    out = list_parts("iso.dxf", _bytes(d))
    assert [(r["holes"], r["bbox"]) for r in out["parts"]] == [(1, pytest.approx([0, 100, 60, 140]))]
    assert len(_said(out, "pictorial view")) == 1


def test_faces_of_a_plan_view_join_into_one_outline_with_exact_curves() -> None:
    """A plan split by two visible edges (a channel seen from above), with its elevation:
    the part is the plan's outline, its rounded corners still arcs, and one document."""
    d = ezdxf.new(units=4, setup=True)
    m = d.modelspace()
    m.add_lwpolyline([(2, 0, 0), (58, 0, 0.41421356), (60, 2, 0), (60, 38, 0.41421356), (58, 40, 0),
                      (2, 40, 0.41421356), (0, 38, 0), (0, 2, 0.41421356)], format="xyb", close=True)
    m.add_line((20, 0), (20, 40))
    m.add_line((40, 0), (40, 40))
    m.add_circle((10, 20), 3)
    _box(m, 0, 60, 60, 70)
    m.add_linear_dim(base=(0, -10), p1=(0, 0), p2=(60, 0)).render()
    doc = import_bytes("channel.dxf", _bytes(d))
    assert sum(s["type"] == "arc" for s in doc["boundary"]) == 4
    assert len(doc["holes"]) == 1
    xs = [p for s in doc["boundary"] if s["type"] == "line" for p in (s["start"][0], s["end"][0])]
    assert min(xs) == pytest.approx(0.0) and max(xs) == pytest.approx(60.0)


def test_a_section_labelled_beside_the_plan_is_set_aside_unhatched() -> None:
    """A section drawn without a hatch, placed away from the plan (not in projection),
    labelled "SECTION A-A" under it: a view, not a second part."""
    d = ezdxf.new(units=4, setup=True)
    m = d.modelspace()
    _box(m, 0, 100, 60, 140)
    m.add_circle((30, 120), 8)
    _box(m, 120, 10, 180, 16)
    m.add_line((140, 10), (140, 16))
    m.add_text("SECTION A-A", dxfattribs={"height": 3}).set_placement((135, 4))
    m.add_linear_dim(base=(0, 150), p1=(0, 140), p2=(60, 140)).render()
    out = list_parts("section.dxf", _bytes(d))
    assert [(r["holes"], r["bbox"]) for r in out["parts"]] == [(1, pytest.approx([0, 100, 60, 140]))]
    assert len(_said(out, "section or detail view labelled 'SECTION A-A'")) == 1


def test_dimlfac_of_a_unit_change_is_not_a_drawing_scale() -> None:
    """ezdxf's own dimension styles carry DIMLFAC 100 (drawn in m, dimensioned in cm): the
    part is read as drawn, and that is said; DIMLFAC 0.5 (a 2:1 drawing) halves it."""
    def plate(dimlfac: float | None) -> bytes:
        d = ezdxf.new(units=4, setup=True)
        m = d.modelspace()
        _box(m, 0, 0, 60, 40)
        dim = m.add_linear_dim(base=(0, -10), p1=(0, 0), p2=(60, 0), dimstyle="Standard",
                               override={} if dimlfac is None else {"dimlfac": dimlfac})
        dim.render()
        return _bytes(d)

    as_drawn = list_parts("m.dxf", plate(100.0))
    assert as_drawn["parts"][0]["bbox"] == pytest.approx([0, 0, 60, 40])
    assert any("unit change" in w for w in as_drawn["warnings"])
    assert list_parts("2to1.dxf", plate(0.5))["parts"][0]["bbox"] == pytest.approx([0, 0, 30, 20])
    assert list_parts("1to1.dxf", plate(None))["parts"][0]["bbox"] == pytest.approx([0, 0, 60, 40])
