"""MCAP run records: read back with the mcap reader, every message checked against its
channel's schema; replay reproduces; crashes leave no complete-looking file."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import jsonschema
import pytest
from mcap.reader import make_reader
from mcap_protobuf.decoder import DecoderFactory

from algrasp.cli import main
from algrasp.io.record.recorder import RunRecorder
from algrasp.io.record.replay import read_record, replay

EXAMPLE = Path(__file__).parents[4] / "algrasp" / "examples" / "pie-20.json"


def check_record(path: Path) -> dict[str, int]:
    """Validate every message against its channel's schema; count messages per topic."""
    counts: dict[str, int] = {}
    decoders = DecoderFactory()
    with open(path, "rb") as f:
        reader = make_reader(f)
        for schema, channel, message in reader.iter_messages():
            counts[channel.topic] = counts.get(channel.topic, 0) + 1
            if channel.message_encoding == "json":
                assert schema is not None and schema.encoding == "jsonschema"
                jsonschema.validate(json.loads(message.data), json.loads(schema.data))
            else:
                assert channel.message_encoding == "protobuf" and schema is not None
                assert schema.name in ("foxglove.SceneUpdate", "foxglove.FrameTransforms")
                decode = decoders.decoder_for(channel.message_encoding, schema)
                assert decode is not None
                decoded = decode(message.data)
                assert decoded.ByteSize() > 0
    return counts


def _run(args: list[str], capsys: pytest.CaptureFixture[str]) -> dict[str, Any]:
    assert main(args) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("extra", [["--action", "squeeze"], ["--action", "push-grasp", "--optimise"]])
def test_plan_record_validates_and_replays(tmp_path: Path, capsys: pytest.CaptureFixture[str], extra: list[str]) -> None:
    out = _run(["plan", str(EXAMPLE), "--json", "--record-dir", str(tmp_path), *extra], capsys)
    path = Path(out["record_path"])
    assert path.parent == tmp_path and path.name == f"{out['run_id']}.mcap" and path.is_file()
    counts = check_record(path)
    steps = len(out["steps"])  # a plan-only record's scene: the start and each action's outcome (issue 35)
    assert counts == {"/request": 1, "/analysis": 1, "/plan": 1, "/run": 1, "/scene": 1, "/tf": steps + 1}
    result = replay(path)
    assert result["differences"] == []
    assert [s["gripper_angle_deg"] for s in result["steps"]] == [s["gripper_angle_deg"] for s in out["steps"]]
    replayed = _run(["replay", str(path), "--json"], capsys)
    assert replayed["run_id"] == out["run_id"] and replayed["differences"] == []


def test_replay_reports_a_tampered_record(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A record whose plan differs from what its request gives is reported, field by field."""
    out = _run(["plan", str(EXAMPLE), "--json", "--record-dir", str(tmp_path)], capsys)
    rec = read_record(Path(out["record_path"]))
    forged = tmp_path / "forged"
    with RunRecorder(forged, run_id="forged") as r:
        r.write("/request", rec["/request"][0])
        plan = rec["/plan"][0]
        plan["steps"][0]["gripper_angle_deg"] += 1.0
        r.write("/plan", plan)
    diffs = replay(forged / "forged.mcap")["differences"]
    assert [d["path"] for d in diffs] == ["$.steps[0].gripper_angle_deg"]


def test_no_record_writes_nothing(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = _run(["analyze", str(EXAMPLE), "--json", "--no-record", "--record-dir", str(tmp_path)], capsys)
    assert out["record_path"] is None and out["run_id"]
    assert list(tmp_path.iterdir()) == []


def test_failed_run_is_recorded_with_its_error(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "disk.json"
    bad.write_text(json.dumps({"boundary": [{"type": "arc", "center": [0, 0], "radius": 1, "start_deg": 0, "end_deg": 360}]}))
    assert main(["plan", str(bad), "--record-dir", str(tmp_path / "runs")]) == 2
    (path,) = (tmp_path / "runs").glob("*.mcap")
    run = read_record(path)["/run"][0]
    assert run["status"] == "error" and run["error"]["reason"] == "constant_width"
    check_record(path)


def test_crash_leaves_a_partial_file_that_reads_up_to_the_crash(tmp_path: Path) -> None:
    rec = RunRecorder(tmp_path, run_id="crash")
    rec.write("/request", {"run_id": "crash", "command": "plan", "part": {"polygon": [[0, 0], [1, 0], [0, 1]]},
                           "options": {}})
    for i in range(3000):  # several chunks' worth
        rec.write("/sim/state", {"sample": 0, "t_s": i * 0.02, "x_m": 0.0, "y_m": 0.0, "phi_deg": float(i),
                                 "gripper_angle_deg": 0.0, "lower_jaw_m": -0.01, "higher_jaw_m": 0.01})
    rec._file.close()  # the process dies here: no summary, no index, no rename
    assert not (tmp_path / "crash.mcap").exists() and (tmp_path / "crash.mcap.partial").exists()
    got = read_record(tmp_path / "crash.mcap.partial", partial_ok=True)
    states = got["/sim/state"]
    assert got["/request"][0]["run_id"] == "crash" and 1000 < len(states) <= 3000
    assert [s["phi_deg"] for s in states] == [float(i) for i in range(len(states))]


def test_runs_lists_records(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    a = _run(["analyze", str(EXAMPLE), "--json", "--record-dir", str(tmp_path)], capsys)
    b = _run(["plan", str(EXAMPLE), "--json", "--record-dir", str(tmp_path)], capsys)
    runs = _run(["runs", "--dir", str(tmp_path), "--json"], capsys)
    assert {r["run_id"] for r in runs} == {a["run_id"], b["run_id"]}
    plan_run = next(r for r in runs if r["run_id"] == b["run_id"])
    assert plan_run["steps"] == len(b["steps"]) and plan_run["action"] == "squeeze"
