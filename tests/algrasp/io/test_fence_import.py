"""A fence layout DXF re-imported (issue 36): algrasp's importer and ezdxf read the fences
back at the document's angles, positions and lengths, also after a shop rotates, moves
and re-saves the drawing; nothing in it is mistaken for a part."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import pytest

import algrasp
from algrasp.cli import main
from algrasp.errors import PartDocumentError
from algrasp.io.cad import import_file
from algrasp.io.fence_drawing import write_dxf

ROOT = Path(__file__).resolve().parents[3]
EXAMPLES = ROOT / "algrasp" / "examples"
LENGTH_TOL = 1e-9
"""Relative to the belt width: the DXF keeps coordinates to double precision."""
ANGLE_TOL_DEG = 1e-9
SHOP_TOL = 1e-6
"""After a rotation and a move (rounding of sin/cos and re-save): relative and degrees."""


def _parts() -> dict[str, tuple[dict[str, Any], dict[str, Any]]]:
    """Part documents and the fence options they are designed with (the triangle and the
    bracket in Berretty et al.'s model: with the tips' turns modelled they have no design)."""
    return {
        "rect": ({"name": "rect", "units": "mm", "boundary": [[0, 0], [40, 0], [40, 20], [0, 20]]}, {"exact": True}),
        "triangle": ({"name": "tri", "units": "in", "boundary": [[0, 0], [5, 0], [1, 3]]},
                     {"exact": True, "exit_turns": False}),
        "bracket": (json.loads((EXAMPLES / "bracket.json").read_text()), {"exit_turns": False}),
        "triangle-same-rail": ({"name": "tri", "units": "in", "boundary": [[0, 0], [5, 0], [1, 3]]},
                               {"exact": True, "same_rail": True, "fence_friction": [0.0, 0.03]}),
        "square-tail": ({"name": "sq", "units": "mm", "boundary": [[0, 0], [30, 0], [30, 30], [0, 30]]},
                        {"tail": {"radius": 20.0}, "belt_width": 300.0}),
    }


def _ezdxf_fences(path: Path) -> list[tuple[str, float, float, float]]:
    """(side, angle, root x, length) of each LINE on FENCES, by ezdxf alone: the root is the
    end on a BELT line (the rails are horizontal as written)."""
    import ezdxf

    msp = ezdxf.readfile(path).modelspace()
    rails = sorted(e.dxf.start.y for e in msp.query('LINE[layer=="BELT"]'))
    out = []
    for e in msp.query('LINE[layer=="FENCES"]'):
        a, b = e.dxf.start, e.dxf.end
        root, tip = (a, b) if min(abs(a.y - r) for r in rails) < min(abs(b.y - r) for r in rails) else (b, a)
        side = "right" if abs(root.y - rails[0]) < abs(root.y - rails[1]) else "left"
        angle = math.degrees(math.atan2(tip.y - root.y, tip.x - root.x)) % 180.0
        out.append((side, angle, root.x, math.hypot(tip.x - root.x, tip.y - root.y)))
    return sorted(out, key=lambda f: f[2])


@pytest.mark.parametrize("name", list(_parts()))
def test_layout_reimported_matches_the_document(name: str, tmp_path: Path) -> None:
    part, options = _parts()[name]
    layout = algrasp.fences(part, **options)
    doc: dict[str, Any] = dict(layout.to_dict())
    path = write_dxf(layout, tmp_path / f"{name}.dxf")
    got = import_file(str(path))
    W = doc["belt_width"]
    assert got["kind"] == "fence_layout" and got["units"] == doc["units"]
    assert got["belt_width"] == pytest.approx(W, rel=LENGTH_TOL)
    assert len(got["fences"]) == len(doc["fences"]) == len(_ezdxf_fences(path))
    for mine, want, ez in zip(got["fences"], doc["fences"], _ezdxf_fences(path)):
        assert mine["side"] == want["side"] == ez[0]
        assert mine["angle_deg"] == pytest.approx(want["angle_deg"], abs=ANGLE_TOL_DEG)
        assert ez[1] == pytest.approx(want["angle_deg"], abs=ANGLE_TOL_DEG)
        assert mine["steepness_deg"] == pytest.approx(want["steepness_deg"], abs=ANGLE_TOL_DEG)
        for got_v, ez_v, key in ((mine["position"], ez[2], "position"), (mine["length"], ez[3], "length")):
            assert got_v == pytest.approx(want[key], abs=LENGTH_TOL * W)
            assert ez_v == pytest.approx(want[key], abs=LENGTH_TOL * W)
    if "tail" in doc:
        assert got["tail"]["radius"] == pytest.approx(doc["tail"]["radius"], rel=LENGTH_TOL)
        assert got["tail"]["sweep_deg"] == pytest.approx(doc["tail"]["sweep_deg"], abs=ANGLE_TOL_DEG)
        assert got["tail"]["fence"] == len(doc["fences"])
    else:
        assert "tail" not in got
    if doc.get("exit"):  # the guide from the last fence's tip (or tail) at its angle, as designed
        ex, want_ex = got["exit"], doc["exit"]
        assert ex["angle_deg"] == pytest.approx(want_ex["angle_deg"], abs=ANGLE_TOL_DEG)
        assert ex["length"] == pytest.approx(want_ex["length"], abs=LENGTH_TOL * W)
        for key in ("start", "end"):
            assert ex[key] == pytest.approx(want_ex[key], abs=LENGTH_TOL * W)
    else:
        assert "exit" not in got


def test_rotated_and_moved_drawing_reads_the_same(tmp_path: Path) -> None:
    """A shop turns the drawing by 30° and moves it: in the rails' frame the fences are
    where they were (positions measured along the rails from the drawing's origin's
    projection, so the move along the belt shifts them by its component along it)."""
    import ezdxf
    from ezdxf.math import Matrix44

    part, options = _parts()["rect"]
    doc: dict[str, Any] = dict(algrasp.fences(part, **options).to_dict())
    path = write_dxf(algrasp.fences(part, **options), tmp_path / "rect.dxf")
    drawing = ezdxf.readfile(path)
    turn = math.radians(30.0)
    m = Matrix44.z_rotate(turn) @ Matrix44.translate(0.0, 0.0, 0.0)
    for e in drawing.modelspace().query("LINE ARC"):
        e.transform(m)  # type: ignore[attr-defined]
    drawing.saveas(tmp_path / "turned.dxf")
    got = import_file(str(tmp_path / "turned.dxf"))
    W = doc["belt_width"]
    assert got["belt_width"] == pytest.approx(W, rel=SHOP_TOL)
    for mine, want in zip(got["fences"], doc["fences"]):
        assert mine["side"] == want["side"]
        assert mine["angle_deg"] == pytest.approx(want["angle_deg"], abs=SHOP_TOL)
        assert mine["position"] == pytest.approx(want["position"], abs=SHOP_TOL * W)
        assert mine["length"] == pytest.approx(want["length"], abs=SHOP_TOL * W)


def test_cli_import_reports_the_layout_and_planners_refuse_it(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    part, options = _parts()["square-tail"]
    doc: dict[str, Any] = dict(algrasp.fences(part, **options).to_dict())
    path = write_dxf(algrasp.fences(part, **options), tmp_path / "belt.dxf")
    out = tmp_path / "belt.json"
    assert main(["import", str(path), "-o", str(out)]) == 0
    text = capsys.readouterr().out
    n = len(doc["fences"])
    assert f"fence layout, {n} fence{'s' if n > 1 else ''} on a belt" in text and f"tail on fence {n}:" in text
    assert f"exit guide: {doc['exit']['steepness_deg']:.4f}° to the belt" in text
    read = json.loads(out.read_text())
    assert main(["import", str(path), "--list", "--json"]) == 0  # no parts on it: its fences
    assert json.loads(capsys.readouterr().out)["fences"] == read["fences"]
    assert [f["side"] for f in read["fences"]] == [f["side"] for f in doc["fences"]]
    assert main(["plan", str(path)]) == 2
    assert f"is a fence layout ({n} fence{'s' if n > 1 else ''} on layer FENCES), not a part" in capsys.readouterr().err
    drawing = algrasp.import_drawing(path)
    assert drawing.document["kind"] == "fence_layout"
    with pytest.raises(PartDocumentError, match="fence layout"):
        algrasp.plan(drawing)


def test_a_fence_line_off_the_rails_is_named(tmp_path: Path) -> None:
    import ezdxf

    drawing = ezdxf.new("R2010")
    msp = drawing.modelspace()
    for y in (0.0, 100.0):
        msp.add_line((-10, y), (300, y), dxfattribs={"layer": "BELT"})
    msp.add_line((0, 0), (50, 50), dxfattribs={"layer": "FENCES"})
    msp.add_line((60, 20), (90, 60), dxfattribs={"layer": "FENCES"})
    drawing.saveas(tmp_path / "bad.dxf")
    with pytest.raises(PartDocumentError, match="line 2 on layer FENCES touches neither rail"):
        import_file(str(tmp_path / "bad.dxf"))
