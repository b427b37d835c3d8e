"""The typed HTTP contract (issue 19): the part document's JSON Schema is published and
kept equal to the model, accepts every example and real drawing we import, refuses what
the core refuses by shape; every operation documents its typed error responses."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import pytest

from algrasp.io.cad import import_bytes
from service.contract import part_schema
from tests.service.conftest import Server

ROOT = Path(__file__).resolve().parents[2]
SCHEMA_FILE = ROOT / "algrasp" / "schemas" / "part.schema.json"


def test_schema_file_is_the_model() -> None:
    assert json.loads(SCHEMA_FILE.read_text()) == part_schema()


def test_schema_accepts_examples_and_imported_drawings() -> None:
    docs = [json.loads(p.read_text()) for p in (ROOT / "algrasp" / "examples").glob("*.json")]
    docs += [import_bytes(p.name, p.read_bytes()) for p in sorted((ROOT / "tests" / "data" / "real").glob("koppi-*1[258].dxf"))]
    assert len(docs) >= 4
    for doc in docs:
        jsonschema.validate(doc, part_schema())


@pytest.mark.parametrize("bad", [
    {"boundary": [{"type": "spline", "points": []}]},
    {"boundary": [{"type": "arc", "center": [0, 0], "radius": -1, "start_deg": 0, "end_deg": 90}]},
    {"boundary": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]},
    {"polygon": [[0, 0], [1, 0]]},
    {"boundary": [[0, 0], [1, 0], [0, 1]], "colour": "red"},
])
def test_schema_refuses_malformed_documents(bad: dict[str, object]) -> None:
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(bad, part_schema())


def test_every_operation_documents_typed_errors(server: Server) -> None:
    with server.client() as c:
        spec = c.get("/openapi.json").json()
        assert c.get("/v1/schemas/part").json() == part_schema()
    assert "ErrorBody" in spec["components"]["schemas"]
    for path, ops in spec["paths"].items():
        for method, op in ops.items():
            for code in ("422", "429", "503", "500"):
                ref = op["responses"][code]["content"]["application/json"]["schema"]["$ref"]
                assert ref.endswith("/ErrorBody"), (method, path, code)


def test_every_document_schema_is_published(server: Server) -> None:
    """``/v1/schemas/{name}``: each typed document's schema (the same one the records
    carry); an unknown name is a 404 naming the ones there are."""
    from algrasp.io.documents import DOCUMENTS, json_schema
    from algrasp.io.record.schemas import TOPICS

    with server.client() as c:
        names = c.get("/v1/schemas").json()["schemas"]
        assert names == sorted(DOCUMENTS)
        for name in names:
            r = c.get(f"/v1/schemas/{name}")
            assert r.status_code == 200 and r.headers["content-type"] == "application/schema+json"
            assert r.json() == json_schema(DOCUMENTS[name])
        plan = c.get("/v1/schemas/plan").json()
        missing = c.get("/v1/schemas/plans")
    assert {k: v for k, v in TOPICS["/plan"].items() if k != "title"} == {k: v for k, v in plan.items() if k != "title"}
    assert missing.status_code == 404 and "plan, request" in missing.json()["error"]["message"]
