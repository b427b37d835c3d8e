"""The last fence's curved tail (conventions §9): in the document, and in the DXF as an
ARC tangent to the fence at its tip (re-read by ezdxf), and in the SVG."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

import algrasp
from algrasp.errors import ConfigError
from algrasp.io.fence_drawing import svg_text, write_dxf

RECT = {"name": "rect", "units": "mm", "boundary": [[0, 0], [40, 0], [40, 20], [0, 20]]}
SQUARE = {"name": "square", "units": "mm", "boundary": [[0, 0], [30, 0], [30, 30], [0, 30]]}


@pytest.mark.parametrize("part", [RECT, SQUARE])
@pytest.mark.parametrize("sweep", [None, 20.0])
def test_dxf_tail_is_an_arc_tangent_to_the_last_fence(tmp_path: Path, part: dict, sweep: float | None) -> None:
    import ezdxf

    layout = algrasp.fences(part, belt_width=300.0, tail={"radius": 25.0, "sweep_deg": sweep})
    doc = layout.to_dict()
    last = doc["fences"][-1]
    assert doc["tail"]["radius"] == 25.0
    default = last["steepness_deg"] - doc["exit"]["steepness_deg"]  # ends tangent to the exit guide
    assert doc["tail"]["sweep_deg"] == pytest.approx(sweep if sweep is not None else default)
    msp = ezdxf.readfile(write_dxf(layout, tmp_path / "belt.dxf")).modelspace()
    (arc,) = msp.query('ARC[layer=="FENCES"]')
    lines = list(msp.query('LINE[layer=="FENCES"]'))
    assert len(lines) == len(doc["fences"])
    tip = layout.tip(len(doc["fences"]) - 1)
    line = min(lines, key=lambda e: min(math.dist(tip, e.dxf.start.vec2), math.dist(tip, e.dxf.end.vec2)))
    (sx, sy), (ex, ey) = line.dxf.start.vec2, line.dxf.end.vec2
    d = ((ex - sx) / math.dist((sx, sy), (ex, ey)), (ey - sy) / math.dist((sx, sy), (ex, ey)))
    c, R = arc.dxf.center, arc.dxf.radius
    assert pytest.approx(25.0) == R
    ends = [(c[0] + R * math.cos(math.radians(t)), c[1] + R * math.sin(math.radians(t)))
            for t in (arc.dxf.start_angle, arc.dxf.end_angle)]
    at_tip = min(ends, key=lambda p: math.dist(p, tip))
    assert math.dist(at_tip, tip) < 1e-6  # the arc starts at the fence's tip ...
    radial = ((at_tip[0] - c[0]) / R, (at_tip[1] - c[1]) / R)
    assert abs(radial[0] * d[0] + radial[1] * d[1]) < 1e-9  # ... tangent to the fence there
    # It bends away from the part: the centre is behind the fence's face.
    n = (-math.sin(math.radians(last["angle_deg"])), math.cos(math.radians(last["angle_deg"])))
    assert (c[0] - tip[0]) * n[0] + (c[1] - tip[1]) * n[1] == pytest.approx(-R)
    span = (arc.dxf.end_angle - arc.dxf.start_angle) % 360.0
    assert span == pytest.approx(doc["tail"]["sweep_deg"])
    # The part leaves it turned by the sweep towards the belt direction.
    turn = doc["tail"]["turn_deg"]
    assert turn == pytest.approx(-doc["tail"]["sweep_deg"] if last["side"] == "right" else doc["tail"]["sweep_deg"])
    assert 'class="tail"' in svg_text(layout)
    (guide,) = msp.query('LINE[layer=="EXIT"]')  # the exit guide leaves from the tail's end
    assert math.dist(guide.dxf.start.vec2, layout.tail_points()[-1]) < 1e-6


@pytest.mark.parametrize("part", [RECT, SQUARE])
def test_dxf_exit_guide_leaves_the_last_tip_at_its_angle_and_lets_the_part_pass(tmp_path: Path, part: dict) -> None:
    """Re-read by ezdxf: one LINE on layer EXIT from the last fence's tip, at β_e to the
    belt towards the far rail, of the document's length; between its end and the far
    rail there is room for the part (2a + c, c = a/2)."""
    import ezdxf

    layout = algrasp.fences(part)
    doc = layout.to_dict()
    ex, last = doc["exit"], doc["fences"][-1]
    assert ex["side"] == last["side"] and ex["steepness_deg"] == pytest.approx(2.0)
    msp = ezdxf.readfile(write_dxf(layout, tmp_path / "belt.dxf")).modelspace()
    (guide,) = msp.query('LINE[layer=="EXIT"]')
    (sx, sy), (gx, gy) = guide.dxf.start.vec2, guide.dxf.end.vec2
    assert math.dist((sx, sy), layout.tip(len(doc["fences"]) - 1)) < 1e-6
    assert math.dist((sx, sy), (gx, gy)) == pytest.approx(ex["length"])
    rise = gy - sy if last["side"] == "right" else sy - gy
    assert math.degrees(math.atan2(rise, gx - sx)) == pytest.approx(2.0)
    room = doc["belt_width"] - gy if last["side"] == "right" else gy
    assert room >= 2.5 * doc["cover_radius"] - 1e-9
    assert 'class="exit"' in svg_text(layout)


def test_bad_tails_are_refused() -> None:
    with pytest.raises(ConfigError, match="tail"):
        algrasp.fences(RECT, tail={"radius": -1.0})
    with pytest.raises(ConfigError, match="sweep_deg"):
        algrasp.fences(RECT, tail={"radius": 10.0, "sweep_deg": 80.0})
    with pytest.raises(ConfigError, match="wider"):
        algrasp.fences(RECT, tail=1e4, belt_width=300.0)
    with pytest.raises(ConfigError, match="tail"):
        algrasp.fences(RECT, tail={"radius": 10.0, "wobble": 1})
