"""The public Python API (issue 19): every exported name resolves, and the calls give
what the CLI gives for the same input."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import algrasp
from algrasp.cli import main

ROOT = Path(__file__).resolve().parents[2]
PIE = ROOT / "algrasp" / "examples" / "pie-20.json"
GEAR = ROOT / "tests" / "data" / "real" / "koppi-involute-14.5-teeth-09.dxf"


def test_every_exported_name_resolves() -> None:
    for name in algrasp.__all__:
        assert getattr(algrasp, name) is not None
    with pytest.raises(AttributeError):
        _ = algrasp.nothing_of_the_kind  # type: ignore[attr-defined]


def test_plan_matches_the_cli(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["plan", str(PIE), "--action", "push-grasp", "--json", "--no-record"]) == 0
    cli = json.loads(capsys.readouterr().out)
    api = algrasp.plan(PIE, "push_grasp").to_dict()
    assert [s["gripper_angle_deg"] for s in api["steps"]] == pytest.approx([s["gripper_angle_deg"] for s in cli["steps"]])
    analysis = algrasp.analyse(json.loads(PIE.read_text()), exact=True)
    sq = analysis.to_dict()["squeeze"]  # the paper's pie: two 70° steps per half turn
    assert sorted(round(s["end_deg"] - s["start_deg"], 6) for s in sq["steps"]) == [70, 70]
    exact = algrasp.plan(analysis, "squeeze")
    assert len(exact.steps) == 3 and exact.verified


def test_drawings_and_errors() -> None:
    doc = algrasp.import_drawing(GEAR)
    part = algrasp.load_part(GEAR)
    assert part.area == pytest.approx(algrasp.load_part(doc).area)
    with pytest.raises(algrasp.PartDocumentError) as err:
        algrasp.load_part({"boundary": [[0, 0], [1, 0]]})
    assert err.value.field == "boundary" and err.value.http_status == 422 and err.value.exit_code == 2
    with pytest.raises(algrasp.ConfigError):
        algrasp.plan(PIE, "poke")  # type: ignore[arg-type]


def test_all_is_the_lazy_table() -> None:
    assert sorted(algrasp.__all__) == sorted(algrasp._API)
