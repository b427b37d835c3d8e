"""The analyze command as a user runs it."""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

import pytest

from algrasp.cli import main
from algrasp.testing import shapes

EXAMPLE = Path(__file__).resolve().parents[2] / "algrasp" / "examples" / "pie-20.json"


def test_analyze_json_of_bundled_example(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["analyze", str(EXAMPLE), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) == {"part", "diameter", "radius", "squeeze", "push", "push_grasp", "model", "robust", "run_id", "record_path"}
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


def test_plan_json_and_figure(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    fig = tmp_path / "plan.svg"
    assert main(["plan", str(EXAMPLE), "--exact", "--action", "squeeze", "--json", "--figure", str(fig)]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert set(doc) == {"action", "symmetry_period_deg", "intervals_deg", "steps", "final_orientations_deg",
                        "final_uncertainty_deg", "model", "images", "verified", "timings_s", "run_id", "record_path"}
    assert all(s["image_deg"] for s in doc["steps"]) and doc["images"]["pieces"]  # the plan's own images (issue 35)
    assert doc["model"] == "exact" and doc["final_uncertainty_deg"] == 0.0
    assert doc["action"] == "squeeze" and doc["verified"] is True and len(doc["steps"]) == 3
    assert [round(b - a, 6) for a, b in doc["intervals_deg"]] == [70, 140, 180]
    assert doc["steps"][0]["margin_deg"] is None and all(s["margin_deg"] >= 0 for s in doc["steps"][1:])
    assert all(0 <= s["gripper_angle_deg"] < 360 for s in doc["steps"])
    assert set(doc["timings_s"]) == {"analysis", "planning", "verification"}
    assert fig.stat().st_size > 10_000 and fig.read_text().lstrip().startswith("<?xml")


def test_plan_push_grasp_table(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["plan", str(EXAMPLE), "--exact", "--action", "push-grasp"]) == 0
    out = capsys.readouterr().out
    assert "3-step push_grasp plan" in out and "verified: True" in out


def test_plan_errors(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    disk = tmp_path / "disk.json"
    disk.write_text(json.dumps(shapes.disk()))
    assert main(["plan", str(disk), "--json"]) == 2
    err = json.loads(capsys.readouterr().out)["error"]
    assert err["type"] == "not_orientable" and err["reason"] == "constant_width"
    assert main(["plan", str(EXAMPLE), "--min-margin-deg", "60"]) == 2
    assert "no plan tolerates" in capsys.readouterr().err
    assert main(["plan", str(EXAMPLE), "--figure", str(tmp_path / "x.pdf")]) == 2
    assert "unsupported format" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["plan", str(EXAMPLE), "--min-margin-deg", "-1"])


def test_every_command_prints_its_help(capsys: pytest.CaptureFixture[str]) -> None:
    """``--help`` of every subcommand prints (a help text with a bare "%" — a physics
    source says "±20 % force accuracy" — made argparse raise TypeError)."""
    from algrasp.cli import build_parser

    parser = build_parser()
    commands = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices
    outs = {}
    for name in commands:
        with pytest.raises(SystemExit) as stop:
            main([name, "--help"])
        assert stop.value.code == 0, name
        outs[name] = capsys.readouterr().out
        assert outs[name].startswith(f"usage: algrasp {name}"), name
    assert "±20 % force accuracy" in " ".join(outs["plan"].split())
