"""The shell passes typed objects (issue 33): a request body is parsed once (by the
guard; the framework reads that parse), the options object and its model are built once,
the plan is not embedded in the validation to be stripped again, and simulation workers
get the planned part, not its document to parse."""

from __future__ import annotations

import json
import types
from pathlib import Path
from typing import Any

import pytest

from algrasp.io.record.session import recording
from algrasp.pipeline import PlanRequest, plan_part
from algrasp.planning.analysis import Model

SQUARE = {"name": "square", "polygon": [[0, 0], [10, 0], [10, 6], [0, 6]]}


def test_a_plan_body_is_parsed_once(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import starlette.requests
    from fastapi.testclient import TestClient

    from service.app import create_app
    from service.settings import Settings

    parses: list[bytes] = []

    def counting(data: Any, **kw: Any) -> Any:
        parses.append(data)
        return json.loads(data, **kw)

    with TestClient(create_app(Settings(log_dir=tmp_path, workers=1, fast_workers=1))) as c:
        monkeypatch.setattr(starlette.requests, "json", types.SimpleNamespace(loads=counting))
        r = c.post("/v1/plans", json={"part": SQUARE, "exact": True})
        jobs = c.post("/v1/jobs", json={"parts": [SQUARE], "options": {"exact": True}})
    assert r.status_code == 200 and r.json()["steps"], r.text
    assert jobs.status_code == 202, jobs.text
    assert parses == []  # the framework read the guard's parse: no second json.loads of the bytes


def test_the_model_is_built_once(monkeypatch: pytest.MonkeyPatch) -> None:
    built = []
    original = Model.from_options

    def counting(options: Any, *args: Any, **kw: Any) -> Model:
        built.append(options)
        return original(options, *args, **kw)

    monkeypatch.setattr(Model, "from_options", staticmethod(counting))
    req = PlanRequest(action="push_grasp", physics={"support_friction": [0.25, 0.35]})
    with recording(False, None, "plan", SQUARE, req.record_options()) as rec:
        out = plan_part(SQUARE, req, rec)
    assert out.plan.steps and len(built) == 1


def test_a_validation_document_without_its_plan() -> None:
    from algrasp.sim.validate import Sample, Validation

    v = Validation((Sample(0.0, 90.0, 90.2, True, False, 0.0),), 1.0, 1.0, 1.0, "centred", 1.0, 1.0, {},
                   plan_document={"action": "squeeze"})
    assert v.to_dict()["plan"] == {"action": "squeeze"}
    assert "plan" not in v.to_dict(with_plan=False) and v.to_dict(with_plan=False)["agreement"] == 1.0


def test_simulation_tasks_carry_the_planned_part() -> None:
    import dataclasses

    from algrasp.geometry.part import Part
    from algrasp.sim.validate import SimTask

    kinds = {f.name: f.type for f in dataclasses.fields(SimTask)}
    assert kinds["part"] in (Part, "Part") and "doc" not in kinds
