"""``algrasp fences`` and ``algrasp.fences``: the fence document, its drawings (the DXF
re-read with ezdxf and algrasp's own importer), and errors naming the flag."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

import algrasp
from algrasp.cli import main
from algrasp.io.documents import FenceDocument

ROOT = Path(__file__).resolve().parents[2]
RECT = {"name": "rect", "units": "mm", "boundary": [[0, 0], [40, 0], [40, 20], [0, 20]]}


@pytest.fixture
def rect_file(tmp_path: Path) -> Path:
    p = tmp_path / "rect.json"
    p.write_text(json.dumps(RECT))
    return p


def test_json_is_the_typed_fence_document(rect_file: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["fences", str(rect_file), "--exact", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    FenceDocument.model_validate(doc)
    fences = doc["fences"]
    assert len(fences) == 2 and {f["side"] for f in fences} == {"left", "right"}
    assert doc["units"] == "mm" and doc["final_orientations_deg"] and doc["last_fence_uncertainty_deg"] == 0.0
    assert doc["final_uncertainty_deg"] == pytest.approx(0.5 * doc["exit"]["steepness_deg"])  # the guide's end turn
    rise = doc["exit"]["push_distance_bound"] * math.cos(math.radians(doc["exit"]["steepness_deg"]))
    for i, f in enumerate(fences):  # the side follows the angle, lengths reach h (the last h less the guide's rise)
        assert (f["angle_deg"] < 90) == (f["side"] == "right")
        reach = doc["reach"] - (rise if i == len(fences) - 1 else 0.0)
        assert f["length"] * math.sin(math.radians(f["steepness_deg"])) == pytest.approx(reach)
    assert fences[0]["position"] == 0.0 and fences[1]["position"] > 0.0
    assert doc["reach"] < doc["belt_width"]


def test_table_and_drawings(rect_file: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    import ezdxf

    svg, dxf = tmp_path / "belt.svg", tmp_path / "belt.dxf"
    assert main(["fences", str(rect_file), "--exact", "--svg", str(svg), "--dxf", str(dxf)]) == 0
    text = capsys.readouterr().out
    assert "2 fences" in text and "belt width" in text and f"drawing written to {dxf}" in text
    import xml.etree.ElementTree as ET

    root = ET.fromstring(svg.read_text())
    assert len([e for e in root.iter() if e.get("class") == "fence"]) == 2
    doc = json.loads(json.dumps(algrasp.fences(RECT, exact=True).to_dict()))
    lines = list(ezdxf.readfile(dxf).modelspace().query('LINE[layer=="FENCES"]'))
    assert len(lines) == 2
    for line, fence in zip(lines, doc["fences"]):
        (x0, y0), (x1, y1) = (line.dxf.start.x, line.dxf.start.y), (line.dxf.end.x, line.dxf.end.y)
        assert x0 == pytest.approx(fence["position"])
        assert math.hypot(x1 - x0, y1 - y0) == pytest.approx(fence["length"])
        assert math.degrees(math.atan2(y1 - y0, x1 - x0)) % 180 == pytest.approx(fence["angle_deg"] % 180)
        assert y0 == pytest.approx(0.0 if fence["side"] == "right" else doc["belt_width"])
    assert ezdxf.readfile(dxf).header["$INSUNITS"] == 4
    assert len(ezdxf.readfile(dxf).modelspace().query("DIMENSION")) >= 3


def test_dxf_is_read_by_algrasps_importer(rect_file: Path, tmp_path: Path) -> None:
    """The importer reads the drawing back as a fence layout: nothing is mistaken for a
    part (tests/algrasp/io/test_fence_import.py compares the numbers)."""
    from algrasp.io.cad import import_file

    dxf = tmp_path / "belt.dxf"
    assert main(["fences", str(rect_file), "--exact", "--dxf", str(dxf)]) == 0
    got = import_file(dxf)
    assert got["kind"] == "fence_layout" and len(got["fences"]) == 2 and "boundary" not in got


@pytest.mark.parametrize(("argv", "flag"), [
    (["--fence-friction", "0.5,0.1"], "--fence-friction"),
    (["--belt-friction", "-1"], "--fence-friction"),
    (["--belt-width", "1"], "--belt-width"),
    (["--min-margin-deg", "60"], "--min-margin-deg"),
    (["--exit-steepness-deg", "0"], "--exit-steepness-deg"),
    (["--exit-steepness-deg", "12"], "--exit-steepness-deg"),
])
def test_bad_options_name_the_flag(rect_file: Path, argv: list[str], flag: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["fences", str(rect_file), "--exact", *argv]) == 2
    assert capsys.readouterr().err.startswith(f"algrasp: error: {flag}: ")


def test_disk_is_refused_as_json(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    disk = tmp_path / "disk.json"
    disk.write_text(json.dumps({"name": "disk", "boundary": [
        {"type": "arc", "center": [0, 0], "radius": 5, "start_deg": 0, "end_deg": 360}]}))
    assert main(["fences", str(disk), "--json"]) == 2
    err = json.loads(capsys.readouterr().out)["error"]
    assert err["type"] == "not_orientable" and err["reason"] in ("no_step", "dead_band")


def test_api_matches_the_cli(rect_file: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["fences", str(rect_file), "--exact", "--json", "--fence-friction", "0.2"]) == 0
    cli = json.loads(capsys.readouterr().out)
    api = algrasp.fences(RECT, exact=True, fence_friction=0.2).to_dict()
    assert json.loads(json.dumps(api)) == cli
    assert cli["fence_friction"] == [0.2, 0.2]


def test_drawing_by_suffix(rect_file: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "belt.dxf"
    assert main(["fences", str(rect_file), "--exact", "--drawing", str(out)]) == 0
    assert out.read_text().lstrip().startswith("0")
    assert main(["fences", str(rect_file), "--exact", "--drawing", str(tmp_path / "belt.png")]) == 2
    assert capsys.readouterr().err.startswith("algrasp: error: --drawing: expected a .dxf or .svg file name")


def test_same_rail_flag_is_the_apis(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """``--same-rail`` on ``fences`` and ``validate --fences`` (the shared options): the
    triangle's design is the API's, with consecutive fences on one rail; without
    ``--fences`` the flag is named as needing it."""
    tri = tmp_path / "tri.json"
    tri.write_text(json.dumps({"name": "tri", "units": "in", "boundary": [[0, 0], [5, 0], [1, 3]]}))
    # fence friction up to 0.03: over 0.1–0.3 the triangle has no design (conventions §9)
    assert main(["fences", str(tri), "--exact", "--same-rail", "--fence-friction", "0,0.03", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc == json.loads(json.dumps(algrasp.fences(json.loads(tri.read_text()), exact=True, same_rail=True,
                                                       fence_friction=[0.0, 0.03]).to_dict()))
    sides = [f["side"] for f in doc["fences"]]
    assert doc["same_rail"] and any(a == b for a, b in zip(sides, sides[1:]))
    assert main(["validate", str(tri), "--exact", "--same-rail"]) == 2
    assert capsys.readouterr().err.startswith("algrasp: error: --same-rail: needs --fences")
