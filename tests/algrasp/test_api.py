"""The public Python API (issues 19, 33): every exported name resolves, the calls give
what the CLI gives for the same input, each function accepts what the others return, and
wrong input is a ConfigError naming the argument."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

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


def test_all_is_the_lazy_table() -> None:
    assert sorted(algrasp.__all__) == sorted(algrasp._API)


def test_plan_matches_the_cli(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["plan", str(PIE), "--action", "push-grasp", "--json", "--no-record"]) == 0
    cli = json.loads(capsys.readouterr().out)
    api = algrasp.plan(PIE, action="push_grasp").to_dict()
    assert cli["action"] == api["action"] == "push_grasp"  # one spelling out, both accepted in
    assert [s["gripper_angle_deg"] for s in api["steps"]] == pytest.approx([s["gripper_angle_deg"] for s in cli["steps"]])


def test_every_result_is_accepted_as_a_source() -> None:
    """The paper's pie (exact model): two 70° squeeze steps per half turn, a 3-squeeze plan,
    from every form the part can be handed over in."""
    doc = json.loads(PIE.read_text())
    part = algrasp.load_part(doc)
    analysis = algrasp.analyse(part, exact=True)
    sq = analysis.to_dict()["squeeze"]
    assert sorted(round(s["end_deg"] - s["start_deg"], 6) for s in sq["steps"]) == [70, 70]
    first = algrasp.plan(analysis)
    assert first.analysis is analysis
    for source in (doc, PIE, str(PIE), part, analysis, first):
        p = algrasp.plan(source, action="squeeze", exact=True)
        assert len(p.steps) == 3 and p.verified and p.bounds is None
        assert [s.gripper_angle for s in p.steps] == pytest.approx([s.gripper_angle for s in first.steps])
    assert algrasp.analyse(first) is analysis  # a plan hands its analysis on
    assert algrasp.load_part(analysis).area == pytest.approx(part.area)
    assert algrasp.document(first) == doc


def test_options_given_with_an_analysis_are_not_ignored() -> None:
    exact = algrasp.analyse(PIE, exact=True)
    robust = algrasp.plan(exact, exact=False, action="squeeze")
    assert exact.robust is None and robust.bounds is not None and robust.final_uncertainty > 0
    ranged = algrasp.plan(exact, exact=False, physics={"jaw_friction": [0.0, 0.05]}, limits="none")
    assert ranged.analysis is not None and ranged.analysis.robust is not None
    assert ranged.analysis.robust.physics.jaw_friction == (0.0, 0.05)


def _arc_polygon(n: int) -> dict[str, Any]:
    """A half disc of radius 10: its diameter and the arc tessellated by n chords."""
    arc = [[10 * math.cos(math.pi * k / n), 10 * math.sin(math.pi * k / n)] for k in range(n + 1)]
    return {"name": "half-disc", "polygon": arc}


def test_load_part_reads_a_part_as_the_model_does() -> None:
    doc = _arc_polygon(48)  # 48 chords + the closing diameter
    assert len(algrasp.load_part(doc, exact=True).boundary) == 49
    snapped = algrasp.load_part(doc)
    assert len(snapped.boundary) == len(algrasp.analyse(doc).part.boundary) < 49
    assert snapped.recognised


def test_drawings_are_typed_and_compose() -> None:
    drawing = algrasp.import_drawing(GEAR)
    assert isinstance(drawing, algrasp.Drawing) and drawing.name == GEAR.stem
    assert algrasp.load_part(drawing).area == pytest.approx(algrasp.load_part(GEAR).area)
    assert drawing.to_dict() == algrasp.document(drawing)
    with pytest.raises(algrasp.PartDocumentError) as err:
        algrasp.load_part({"boundary": [[0, 0], [1, 0]]})
    assert err.value.field == "boundary" and err.value.http_status == 422 and err.value.exit_code == 2


def test_optimise_and_gripper(tmp_path: Path) -> None:
    base = algrasp.plan(PIE, action="push_grasp", exact=True)
    p = algrasp.plan(base, action="push_grasp", optimise=True, gripper={"jaw_max_speed_m_s": 0.02})
    doc = p.to_dict()
    assert p.execution is not None and doc["cycle_time_s"] > 0
    assert doc["gripper_profile"]["jaw_max_speed_m_s"] == 0.02
    faster = algrasp.plan(base, action="push_grasp", optimise=True, gripper={"jaw_max_speed_m_s": 0.05})
    assert faster.to_dict()["cycle_time_s"] < doc["cycle_time_s"]  # a slower jaw takes longer
    profile = tmp_path / "slow.yaml"
    profile.write_text("jaw_max_speed_m_s: 0.02\n")
    from_file = algrasp.plan(base, action="push_grasp", optimise=True, gripper=profile)
    assert from_file.to_dict()["cycle_time_s"] == pytest.approx(doc["cycle_time_s"])


@pytest.mark.parametrize(("call", "field"), [
    (lambda: algrasp.plan(42), "source"),  # type: ignore[arg-type]
    (lambda: algrasp.analyse([[0, 0], [1, 0], [0, 1]]), "source"),  # type: ignore[arg-type]
    (lambda: algrasp.plan(PIE, action="poke"), "action"),
    (lambda: algrasp.plan(PIE, min_margin_deg="1"), "min_margin_deg"),  # type: ignore[arg-type]
    (lambda: algrasp.plan(PIE, limits="some"), "limits"),  # type: ignore[arg-type]
    (lambda: algrasp.plan(PIE, gripper={"jaw_max_speed_m_s": 0.02}), "gripper"),
    (lambda: algrasp.plan(PIE, optimise=True, gripper=3), "gripper"),
    (lambda: algrasp.plan(PIE, optimise=True, push_scale=0), "push_scale"),
    (lambda: algrasp.model(physics=3), "physics"),  # type: ignore[arg-type]
    (lambda: algrasp.model(exact="yes"), "exact"),  # type: ignore[arg-type]
    (lambda: algrasp.import_drawing(3), "path"),  # type: ignore[arg-type]
    (lambda: algrasp.validate(PIE, samples=0), "samples"),
    (lambda: algrasp.validate(PIE, samples=2.5), "samples"),  # type: ignore[arg-type]
    (lambda: algrasp.validate(PIE, placement="sideways"), "placement"),  # type: ignore[arg-type]
    (lambda: algrasp.validate(PIE, tolerance_deg=-1), "tolerance_deg"),
    (lambda: algrasp.validate(PIE, workers=0), "workers"),
    (lambda: algrasp.validate(algrasp.plan(PIE, exact=True), action="push_grasp"), "action"),
])
def test_wrong_input_is_a_config_error_naming_the_argument(call: Any, field: str) -> None:
    with pytest.raises(algrasp.ConfigError) as err:
        call()
    assert err.value.field == field and err.value.http_status == 422


def test_options_are_keyword_only() -> None:
    with pytest.raises(TypeError):
        algrasp.plan(PIE, "squeeze")  # type: ignore[misc]


@pytest.mark.sim
def test_validate_a_plan_as_it_is() -> None:
    """The paper's pie under an optimised push-grasp plan: every clear sample ends at the
    predicted orientation (the plan given is simulated, not planned again)."""
    p = algrasp.plan(PIE, action="push_grasp", exact=True, optimise=True)
    v = algrasp.validate(p, samples=3, seed=3, workers=1)
    assert isinstance(v, algrasp.Validation) and len(v.samples) == 3 and v.optimised
    assert v.agreement_clear == 1.0
    doc = v.to_dict()
    assert doc["plan"]["steps"] == p.to_dict()["steps"] and doc["plan"]["cycle_time_s"] == p.to_dict()["cycle_time_s"]
