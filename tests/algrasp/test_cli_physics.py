"""The CLI's physics flags (conventions §8): ranges in, physics and limits out, bad ranges
exit 2 naming the key; the cell comes from --cell or ALGRASP_CELL."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from algrasp.cli import main

ROOT = Path(__file__).resolve().parents[2]
BRACKET = str(ROOT / "algrasp" / "examples" / "bracket.json")


def _plan(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, dict]:
    code = main(["plan", BRACKET, "--no-record", "--json", *args])
    out = capsys.readouterr().out
    return code, json.loads(out)


def test_ranges_reach_the_plan(capsys: pytest.CaptureFixture[str]) -> None:
    code, plan = _plan(capsys, "--cell", "default", "--jaw-friction", "0,0.2", "--support-friction", "0.05,0.6",
                       "--placement", "centred", "--limits")
    assert code == 0
    band = plan["dead_band"]
    assert band["jaw_friction"] == [0.0, 0.2] and band["support_friction"] == [0.05, 0.6]
    assert band["placement"] == "centred"
    assert {"jaw_friction_max", "support_friction_min", "profile_tolerance_max", "advice"} <= set(plan["limits"])
    assert plan["limits"]["jaw_friction_max"]["value"] >= 0.2


def test_the_environment_names_the_cell(capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("ALGRASP_CELL", '{"jaw_friction": [0, 0.05], "placement": "centred"}')
    code, plan = _plan(capsys)
    assert code == 0 and plan["dead_band"]["jaw_friction"] == [0.0, 0.05]


@pytest.mark.parametrize(("args", "field"), [(["--jaw-friction", "0.3,0.1"], "physics.jaw_friction"),
                                             (["--support-friction", "50"], "physics.support_friction"),
                                             (["--cell", "sideways"], "--cell")])
def test_bad_ranges_exit_2_naming_the_key(capsys: pytest.CaptureFixture[str], args: list[str], field: str) -> None:
    code = main(["plan", BRACKET, "--no-record", "--json", *args])
    err = json.loads(capsys.readouterr().out)["error"]
    assert code == 2 and err["field"] == field


def test_refusal_prints_the_limits(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["plan", str(ROOT / "algrasp" / "examples" / "pie-20.json"), "--no-record", "--cell", "default",
                 "--action", "push_grasp"])
    err = capsys.readouterr().err
    # The paper's 5 mm pie needs a part almost exactly as drawn: its push-grasp holds only
    # for a profile tolerance far below the cell's 0.15 mm manufacturing floor.
    found = re.search(r"orientable by push-grasp with (an exact part only|profile tolerance ≤ ([0-9.]+) mm)", err)
    assert code == 2 and found is not None
    assert found.group(2) is None or float(found.group(2)) < 0.01
