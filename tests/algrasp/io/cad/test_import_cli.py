"""``algrasp import`` and CAD files given straight to analyze/plan."""

from __future__ import annotations

import io
import json
import math
from pathlib import Path

import ezdxf
import pytest

from algrasp.cli import main

S, C = math.sin(math.radians(70)) * 5, math.cos(math.radians(70)) * 5


def _pie_dxf(path: Path) -> Path:
    d = ezdxf.new(units=4)
    m = d.modelspace()
    m.add_lwpolyline([(0, 0), (C, S)], dxfattribs={"layer": "CUT"})
    m.add_arc((0, 0), 5, 70, 110, dxfattribs={"layer": "CUT"})
    m.add_line((-C, S), (0, 0), dxfattribs={"layer": "CUT"})
    m.add_lwpolyline([(1, 1), (12, 1), (12, 8), (1, 8)], close=True, dxfattribs={"layer": "FRAME"})
    buf = io.StringIO()
    d.write(buf)
    path.write_text(buf.getvalue())
    return path


def test_import_then_plan_equals_planning_the_drawing(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    dxf = _pie_dxf(tmp_path / "pie.dxf")
    out = tmp_path / "pie.json"
    assert main(["import", str(dxf), "--layer", "CUT", "-o", str(out)]) == 0
    assert "line, arc" in capsys.readouterr().out.replace("arc, line", "line, arc")
    assert main(["plan", str(out), "--json", "--no-record"]) == 0
    from_json = json.loads(capsys.readouterr().out)
    assert main(["plan", str(dxf), "--layer", "CUT", "--json", "--no-record"]) == 0
    from_dxf = json.loads(capsys.readouterr().out)
    assert from_json["steps"] == from_dxf["steps"] and len(from_dxf["final_orientations_deg"]) == 2


def test_import_errors_exit_2_naming_the_problem(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    dxf = _pie_dxf(tmp_path / "pie.dxf")
    assert main(["analyze", str(dxf), "--no-record"]) == 2  # frame and pie overlap as loops
    assert "overlapping loops" in capsys.readouterr().err
    assert main(["import", str(dxf), "--pose", "1"]) == 2
    assert "--pose" in capsys.readouterr().err
