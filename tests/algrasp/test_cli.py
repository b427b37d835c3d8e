"""The analyze command as a user runs it."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from algrasp import shapes
from algrasp.cli import main

EXAMPLE = Path(__file__).resolve().parents[2] / "algrasp" / "examples" / "pie-20.json"


def test_analyze_json_of_bundled_example(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["analyze", str(EXAMPLE), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) == {"part", "diameter", "radius", "squeeze", "push", "push_grasp"}
    sq = out["squeeze"]
    assert sq["period_deg"] == 180 and sorted(round(s["end_deg"] - s["start_deg"], 6) for s in sq["steps"]) == [70, 70]
    assert [round(r["end_deg"] - r["start_deg"], 6) for r in sq["ramps"]] == [40]
    for key in ("diameter", "radius"):
        starts = [e["theta_deg"] for e in out[key]["extrema"]]
        assert starts == sorted(starts) and all(0 <= s < (180 if key == "diameter" else 360) for s in starts)
    assert out["part"]["center_of_mass"] == [0, 2.5]


def test_analyze_table_output(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["analyze", str(EXAMPLE)]) == 0
    text = capsys.readouterr().out
    assert "Squeeze-grasp" in text and "semiunstable" in text and "ramp" in text


def test_errors_are_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"polygon": [[0, 0], [1, 0], [1, 1]], "center_of_mass": [5, 5]}))
    assert main(["analyze", str(bad)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "center_of_mass" in err
    assert main(["analyze", str(bad), "--json"]) == 2
    out = json.loads(capsys.readouterr().out)
    assert out["error"]["type"] == "part_document_error" and out["error"]["field"] == "center_of_mass"
    (tmp_path / "x.json").write_text("{not json")
    assert main(["analyze", str(tmp_path / "x.json")]) == 2
    assert "not valid JSON" in capsys.readouterr().err
    assert main(["analyze", str(tmp_path / "missing.json")]) == 2


def test_constant_width_is_reported(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    f = tmp_path / "reuleaux.json"
    f.write_text(json.dumps(shapes.reuleaux()))
    assert main(["analyze", str(f)]) == 0
    assert "no squeeze plan can orient" in capsys.readouterr().out


def test_console_script_runs() -> None:
    exe = Path(sys.executable).parent / "algrasp"
    res = subprocess.run([str(exe), "analyze", str(EXAMPLE), "--json"], capture_output=True, text=True, check=True)
    assert json.loads(res.stdout)["squeeze"]["symmetry_period_deg"] == 180
