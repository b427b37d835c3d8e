"""The typed documents (:mod:`algrasp.io.documents`) hold what the core's codecs write:
each command's JSON output is validated against its model, both by pydantic and by the
derived JSON Schema (what record readers and HTTP clients use)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import jsonschema
import pytest
from pydantic import BaseModel

from algrasp.cli import main
from algrasp.geometry.limits import DEFAULT_LIMITS
from algrasp.io.documents import (
    DOCUMENTS,
    AnalysisDocument,
    ErrorBody,
    PartDocument,
    PlanDocument,
    json_schema,
)

EXAMPLES = sorted((Path(__file__).parents[3] / "algrasp" / "examples").glob("*.json"))


def _both(model: type[BaseModel], doc: dict[str, Any]) -> None:
    model.model_validate(doc)
    jsonschema.validate(doc, json_schema(model))


def _cli(args: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, dict[str, Any]]:
    code = main([*args, "--json", "--no-record"])
    return code, json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_bundled_parts_are_part_documents(path: Path) -> None:
    _both(PartDocument, json.loads(path.read_text()))


@pytest.mark.parametrize("extra", [["--exact"], ["--cell", "ideal"], ["--exact", "--action", "push-grasp", "--optimise"]])
def test_cli_analysis_and_plan_are_their_documents(extra: list[str], capsys: pytest.CaptureFixture[str]) -> None:
    part = str(EXAMPLES[[p.name for p in EXAMPLES].index("pie-20.json")])
    code, plan = _cli(["plan", part, *extra], capsys)
    assert code == 0
    _both(PlanDocument, plan)
    code, analysis = _cli(["analyze", part, *[a for a in extra if a in ("--exact", "--cell", "ideal")]], capsys)
    assert code == 0
    _both(AnalysisDocument, analysis)


def test_cli_error_is_the_error_document(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"polygon": [[0, 0], [1, 0], [2, 0]]}))
    code, err = _cli(["plan", str(bad)], capsys)
    assert code != 0
    _both(ErrorBody, err)


def test_bezier_degree_limit_is_the_core_limit() -> None:
    top = DEFAULT_LIMITS.max_bezier_degree
    ok = {"boundary": [{"type": "bezier", "points": [[float(i), float(i % 2)] for i in range(top + 1)]}]}
    PartDocument.model_validate(ok)
    ok["boundary"][0]["points"].append([0.0, 0.0])
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(ok, json_schema(PartDocument))


def test_plan_document_rejects_a_third_spelling() -> None:
    schema = json_schema(PlanDocument)
    assert schema["properties"]["action"]["enum"] == ["squeeze", "push_grasp"]
    assert set(DOCUMENTS) == {"part", "analysis", "plan", "validation", "request", "run", "job", "error", "sim-state",
                              "fences"}
