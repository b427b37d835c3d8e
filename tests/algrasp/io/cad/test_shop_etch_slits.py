"""Issue 32's last two shop-corpus misses: etching told from cutting by stroke colour (the
cnlohr Mini-ITX case sheet) and outlines that stop a hair short of open snap-clip slits (the
VisiCut box). Each with its real file and a drawing built here, the truth known by
construction."""

from __future__ import annotations

import io
import json
from pathlib import Path
from typing import Any

import ezdxf
import pytest

from algrasp.errors import PartDocumentError
from algrasp.io.cad import list_parts

SHOPS = Path(__file__).parents[3] / "data" / "shops"
MM_PER_PX = 25.4 / 96.0


def _svg(body: str) -> bytes:
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="300" height="300" viewBox="0 0 300 300">{body}</svg>'
            ).encode()


def _sizes(rows: list[dict[str, Any]]) -> list[tuple[float, float]]:
    return sorted((r["bbox"][2] - r["bbox"][0], r["bbox"][3] - r["bbox"][1]) for r in rows)


# --- etch by colour -------------------------------------------------------------------

def _corner_etch(etch: str, cut: str = "#0000ff") -> str:
    """A 200 x 100 px panel cut in ``cut`` with a 50 x 40 px rectangle in ``etch`` drawn
    on its corner: two of its sides lie on the panel's outline."""
    return (f'<rect x="0" y="0" width="200" height="100" fill="none" stroke="{cut}"/>'
            f'<rect x="0" y="0" width="50" height="40" fill="none" stroke="{etch}"/>')


def test_a_second_colour_carving_parts_out_of_the_first_colours_parts_is_engraving() -> None:
    """Geometry alone makes the corner rectangle a part nested in an L-shaped one (2 parts,
    as the same drawing in one colour still gives); in a second colour that lies on the
    first colour's part it is an etch, said in the warnings: 1 panel, 200 x 100 px, no hole."""
    one = list_parts("one.svg", _svg(_corner_etch("#0000ff")))
    assert len(one["parts"]) == 2
    out = list_parts("etch.svg", _svg(_corner_etch("#ff0000")))
    (row,) = out["parts"]
    assert row["holes"] == 0
    assert _sizes([row]) == [pytest.approx((200 * MM_PER_PX, 100 * MM_PER_PX), abs=0.02)]
    assert any("#ff0000" in w and "engraving" in w for w in out["warnings"])


def test_a_second_colour_that_only_cuts_holes_or_parts_in_cutouts_stays_a_cut() -> None:
    """Shops that cut inner contours first in their own colour: a red hole changes no part
    and stays a hole; a red part nested in a blue part's cutout lies in the cutout, not on
    the material, and stays a part."""
    hole = list_parts("hole.svg", _svg('<rect x="0" y="0" width="200" height="100" fill="none" stroke="#0000ff"/>'
                                      '<circle cx="100" cy="50" r="20" fill="none" stroke="#ff0000"/>'))
    assert [r["holes"] for r in hole["parts"]] == [1]
    nested = list_parts("nested.svg", _svg('<polygon points="0,0 200,0 200,100 20,100 0,80" fill="none" '
                                          'stroke="#0000ff"/><circle cx="100" cy="50" r="40" fill="none" '
                                          'stroke="#0000ff"/><rect x="85" y="35" width="30" height="30" fill="none" '
                                          'stroke="#ff0000"/>'))
    assert sorted(r["holes"] for r in nested["parts"]) == [0, 1]


def test_dxf_colours_are_read_for_the_same_rule() -> None:
    """The corner etch as a DXF: the panel on a layer drawn BYLAYER in blue (ACI 5), the
    etch rectangle in red true colour: 1 panel."""
    d = ezdxf.new()
    d.layers.add("CUT", color=5)
    m = d.modelspace()
    m.add_lwpolyline([(0, 0), (200, 0), (200, 100), (0, 100)], close=True, dxfattribs={"layer": "CUT"})
    m.add_lwpolyline([(0, 60), (50, 60), (50, 100), (0, 100)], close=True, dxfattribs={"layer": "CUT",
                                                                                          "true_color": 0xFF0000})
    buf = io.StringIO()
    d.write(buf)
    (row,) = list_parts("etch.dxf", buf.getvalue().encode())["parts"]
    assert row["bbox"] == pytest.approx([0, 0, 200, 100]) and row["holes"] == 0


def test_cnlohr_case_sheet_red_etch_is_not_a_part() -> None:
    """The real sheet: 7 parts (6 panels and a bracket); none is the red 100 x 125 mm etch
    rectangle at (10.3, 189.5) in the file, which shares two sides with the left panel."""
    path = SHOPS / "batch-ae" / "cnlohr-mitx-laser-cut-case-case.svg"
    out = list_parts(path.name, path.read_bytes())
    assert len(out["parts"]) == 7
    assert all(abs(r["bbox"][2] - r["bbox"][0] - 100.0) > 1.0 for r in out["parts"])
    assert any("#ff0000" in w and "engraving" in w for w in out["warnings"])


# --- outlines a hair short of open slits ---------------------------------------------

def _clips(stroke_width: float) -> bytes:
    """A 100 x 50 px panel with two 10 x 10 px clips on its top edge whose legs run on 20 px
    into the panel as open slits; the top edge between the clips stops 0.05 and 0.1 px
    short of the legs (more than 2e-3 of its 39.85 px, less than half a 0.5 px stroke)."""
    style = f'fill="none" stroke="#000" stroke-width="{stroke_width}"'
    return _svg(f'<g transform="translate(50 50)">'
                f'<polyline points="20,0 0,0 0,50 100,50 100,0 80,0" {style}/>'
                f'<path d="M20,20 V-10 H30 V20" {style}/><path d="M70,20 V-10 H80 V20" {style}/>'
                f'<line x1="30.05" y1="0" x2="69.9" y2="0" {style}/></g>')


def test_an_outline_closes_across_a_gap_narrower_than_its_stroke() -> None:
    """Drawn with 0.5 px strokes the gap of 0.1 px is closed on the drawing: one panel,
    100 x 60 px with its clips, the slits set aside as open cuts. With 0.1 px strokes the
    gap shows and the outline stays open."""
    out = list_parts("clips.svg", _clips(0.5))
    (row,) = out["parts"]
    assert row["holes"] == 0
    assert _sizes([row]) == [pytest.approx((100 * MM_PER_PX, 60 * MM_PER_PX), abs=0.02)]
    assert row["area"] == pytest.approx((100 * 50 + 2 * 10 * 10) * MM_PER_PX ** 2, rel=1e-3)
    with pytest.raises(PartDocumentError):
        list_parts("thin.svg", _clips(0.1))


def test_an_end_stopping_short_of_a_closed_outlines_corner_joins_it() -> None:
    """A rectangle and a U-shaped polyline whose ends stop 0.02 px short of the rectangle's
    lower corners: two 100 x 50 px panels sharing the rectangle's lower side."""
    out = list_parts("corner.svg", _svg('<rect x="0" y="0" width="100" height="50" fill="none" stroke="#000" '
                                        'stroke-width="0.01"/><polyline points="0,50.02 0,100 100,100 100,50.02" '
                                        'fill="none" stroke="#000" stroke-width="0.01"/>'))
    side = pytest.approx((100 * MM_PER_PX, 50 * MM_PER_PX), abs=0.02)
    assert _sizes(out["parts"]) == [side, side]


def test_visicut_box_has_its_six_panels() -> None:
    """The real VisiCut box: six panels sharing cut lines, their sizes read off the file's
    coordinates (px at 1:1): two 195.087 x 85.039 tops (the <rect>); two sides from x 377.329
    to 445.362 (and 445.362 to 513.391) and y 75.554 to 271.849 (clip tip to clip tip); two
    ends from x 183.433 to 277.420 (280.135 to 374.104) and y 244.578 to 329.617."""
    path = SHOPS / "batch-sz" / "t-oster-visicut-box-6x3x3.svg"
    rows = list_parts(path.name, path.read_bytes())["parts"]
    want = sorted([(68.033, 196.295), (68.029, 196.295), (93.987, 85.039), (93.969, 85.039), (195.087, 85.039),
                   (195.087, 85.039)])
    got = [(w / MM_PER_PX, h / MM_PER_PX) for w, h in _sizes(rows)]
    assert got == [pytest.approx(w, abs=0.05) for w in want]


def test_engrave_colours_name_the_engraving_or_none(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """``engrave_colours`` decides instead of the drawing: "none" keeps the corner rectangle
    a part (2 parts); naming blue (#00f) engraves the panel and leaves the red rectangle
    alone (1 part, 50 x 40 px); a bad colour is a ConfigError naming the field. The CLI's
    ``--engrave-colours`` gives the same listing."""
    from algrasp.cli import main
    from algrasp.errors import ConfigError

    data = _svg(_corner_etch("#ff0000"))
    assert len(list_parts("etch.svg", data, engrave_colours="none")["parts"]) == 2
    (red,) = list_parts("etch.svg", data, engrave_colours="#00F")["parts"]
    assert _sizes([red]) == [pytest.approx((50 * MM_PER_PX, 40 * MM_PER_PX), abs=0.02)]
    with pytest.raises(ConfigError, match="engrave_colours"):
        list_parts("etch.svg", data, engrave_colours="red")
    path = tmp_path / "etch.svg"
    path.write_bytes(data)
    assert main(["import", str(path), "--list", "--json", "--engrave-colours", "none"]) == 0
    assert len(json.loads(capsys.readouterr().out)["parts"]) == 2
