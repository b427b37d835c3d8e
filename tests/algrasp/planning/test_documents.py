"""The plan document codec (issue 19): every plan document — exact, robust, optimised —
reads back into a typed PlanDocument and writes out unchanged; a malformed one is an
error naming the field."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from algrasp import analyse, plan
from algrasp.errors import PartDocumentError
from algrasp.planning.documents import PlanDocument

PIE = Path(__file__).resolve().parents[3] / "algrasp" / "examples" / "pie-20.json"


@pytest.mark.parametrize("exact", [True, False])
@pytest.mark.parametrize("action", ["squeeze", "push_grasp"])
def test_plan_documents_round_trip(exact: bool, action: str) -> None:
    p = plan(analyse(PIE, exact=exact), action=action)
    doc = json.loads(json.dumps(p.to_dict()))  # as written to a record or sent over HTTP
    back = PlanDocument.from_json(doc)
    assert back.to_json() == doc
    assert back.action == action and len(back.steps) == len(p.steps)
    # radians inside: the first step's angle is the plan's, wrapped into [0, 2π)
    assert back.steps[0].gripper_angle == pytest.approx(p.steps[0].gripper_angle % (2 * math.pi), abs=1e-12)
    assert back.symmetry_period == pytest.approx(p.symmetry_period)


def test_optimised_fields_are_kept() -> None:
    from optimisation.execution import optimise_execution
    from optimisation.profile import DEFAULT_PROFILE

    a = analyse(PIE)
    p = plan(a, action="push_grasp")
    doc = json.loads(json.dumps(optimise_execution(a, p, DEFAULT_PROFILE).apply_to(p.to_dict())))
    back = PlanDocument.from_json(doc)
    assert back.to_json() == doc
    assert back.execution["cycle_time_s"] == doc["cycle_time_s"] and "push_distance" in back.steps[0].execution


@pytest.mark.parametrize("broken, field", [
    ({"steps": "no"}, "plan.steps"),
    ({"steps": [{"margin_deg": None}]}, "plan.steps[0].gripper_angle_deg"),
    ({"symmetry_period_deg": "180"}, "plan.symmetry_period_deg"),
    ({"intervals_deg": [[0.0]]}, "plan.intervals_deg"),
])
def test_malformed_plan_documents_name_the_field(broken: dict[str, object], field: str) -> None:
    doc = {**plan(analyse(PIE, exact=True), action="squeeze").to_dict(), **broken}
    with pytest.raises(PartDocumentError) as err:
        PlanDocument.from_json(doc)
    assert err.value.field == field


DISK = {"name": "disk", "boundary": [{"type": "arc", "center": [0, 0], "radius": 3, "start_deg": 0, "end_deg": 360}]}


@pytest.mark.parametrize("exact", [True, False])
@pytest.mark.parametrize("source", [PIE, DISK], ids=["pie", "disk"])
def test_analysis_documents_round_trip(source: object, exact: bool) -> None:
    from algrasp.planning.documents import AnalysisDocument

    a = analyse(source, exact=exact)  # type: ignore[arg-type]
    doc = json.loads(json.dumps(a.to_dict(), default=str))
    back = AnalysisDocument.from_json(doc)
    assert json.loads(json.dumps(back.to_json(), default=str)) == doc
    # radians inside, the paper's pie: two squeeze steps of 70° each per half turn
    if source is PIE:
        assert sorted(round(math.degrees(b - s), 6) for s, b, _ in back.squeeze.steps) == [70.0, 70.0]
    else:
        assert not back.squeeze.orientable and back.squeeze.reason


def test_malformed_analysis_document_names_the_field() -> None:
    from algrasp.planning.documents import AnalysisDocument

    doc = analyse(PIE, exact=True).to_dict()
    doc["push"] = {**doc["push"], "steps": [{"start_deg": "x"}]}  # type: ignore[dict-item]
    with pytest.raises(PartDocumentError) as err:
        AnalysisDocument.from_json(doc)
    assert err.value.field == "analysis.push.steps[0].start_deg"

