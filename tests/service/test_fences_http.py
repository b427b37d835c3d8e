"""``POST /v1/fences``: the fence document over HTTP, the same as the API's; bad input a
422 naming the field; a disk refused with its reason; the schema published."""

from __future__ import annotations

import json
from typing import Any

import pytest

import algrasp
from algrasp.io.documents import FenceDocument
from tests.service.conftest import Server

RECT = {"name": "rect", "units": "mm", "boundary": [[0, 0], [40, 0], [40, 20], [0, 20]]}


def test_fences_answer_the_document(server: Server) -> None:
    with server.client() as c:
        r = c.post("/v1/fences", json={"part": RECT, "exact": True, "fence_friction": [0.1, 0.3]})
        again = c.post("/v1/fences", json={"part": RECT, "exact": True, "fence_friction": [0.1, 0.3]})
        schema = c.get("/v1/schemas/fences")
    assert r.status_code == 200, r.text
    doc = r.json()
    FenceDocument.model_validate(doc)
    assert doc == json.loads(json.dumps(algrasp.fences(RECT, exact=True).to_dict()))
    assert len(doc["fences"]) == 2 and again.headers["X-Cache"] == "hit"
    assert schema.status_code == 200 and "fences" in schema.json()["properties"]


@pytest.mark.parametrize(("body", "field"), [
    ({"fence_friction": [0.5, 0.1]}, "fence_friction"),
    ({"fence_friction": [0.1, 0.2, 0.3]}, "fence_friction"),
    ({"belt_width": -5}, "belt_width"),
    ({"min_margin_deg": 90}, "min_margin_deg"),
    ({"wobble": 1}, "wobble"),
    ({"validate": {"samples": 100000}}, "validate.samples"),
    ({"validate": {"samples": 0}}, "samples"),
    ({"tail": {"radius": -1}}, "radius"),
    ({"tail": {"radius": 10, "sweep_deg": 80}}, "tail"),
    ({"exit_steepness_deg": 12}, "exit_steepness_deg"),
    ({"exit_turns": "maybe"}, "exit_turns"),
    ({"same_rail": "maybe"}, "same_rail"),
])
def test_bad_input_is_422_naming_the_field(server: Server, body: dict[str, Any], field: str) -> None:
    with server.client() as c:
        r = c.post("/v1/fences", json={"part": RECT, "exact": True, **body})
    assert r.status_code == 422, r.text
    assert field in json.dumps(r.json())


def test_too_narrow_a_belt_is_422_naming_it(server: Server) -> None:
    with server.client() as c:
        r = c.post("/v1/fences", json={"part": RECT, "exact": True, "belt_width": 10})
    assert r.status_code == 422, r.text
    assert r.json()["error"]["field"] == "belt_width"


def test_disk_is_refused(server: Server) -> None:
    disk = {"name": "disk", "boundary": [{"type": "arc", "center": [0, 0], "radius": 5, "start_deg": 0, "end_deg": 360}]}
    with server.client() as c:
        r = c.post("/v1/fences", json={"part": disk})
    assert r.status_code == 422, r.text
    err = r.json()["error"]
    assert err["type"] == "not_orientable" and err["reason"] in ("no_step", "dead_band")


@pytest.mark.parametrize(("drawing", "media"), [("svg", "image/svg+xml"), ("dxf", "application/dxf")])
def test_drawings_over_http(server: Server, drawing: str, media: str, tmp_path: Any) -> None:
    import ezdxf

    with server.client() as c:
        r = c.post("/v1/fences", json={"part": RECT, "exact": True, "drawing": drawing})
    assert r.status_code == 200, r.text
    assert r.headers["content-type"].startswith(media)
    if drawing == "svg":
        assert r.text.startswith("<svg") and r.text.count('class="fence"') == 2
        return
    path = tmp_path / "belt.dxf"
    path.write_text(r.text)
    lines = list(ezdxf.readfile(path).modelspace().query('LINE[layer=="FENCES"]'))
    want = algrasp.fences(RECT, exact=True).to_dict()["fences"]
    assert [round(ln.dxf.start.x, 6) for ln in lines] == [round(f["position"], 6) for f in want]


def test_tail_is_the_apis(server: Server) -> None:
    with server.client() as c:
        r = c.post("/v1/fences", json={"part": RECT, "exact": True, "belt_width": 300, "tail": {"radius": 25}})
        dxf = c.post("/v1/fences", json={"part": RECT, "exact": True, "belt_width": 300, "tail": {"radius": 25}, "drawing": "dxf"})
    assert r.status_code == 200, r.text
    assert r.json()["tail"] == json.loads(json.dumps(algrasp.fences(RECT, exact=True, belt_width=300, tail=25.0).to_dict()["tail"]))
    assert dxf.status_code == 200 and "ARC" in dxf.text


def test_layout_dxf_imported_over_http_is_the_layout(server: Server) -> None:
    """The DXF ``POST /v1/fences`` draws, sent back to ``POST /v1/imports``: the fence
    layout (sides, angles, positions, lengths of the document), not a part."""
    with server.client() as c:
        doc = c.post("/v1/fences", json={"part": RECT, "exact": True}).json()
        dxf = c.post("/v1/fences", json={"part": RECT, "exact": True, "drawing": "dxf"})
        r = c.post("/v1/imports", files={"file": ("belt.dxf", dxf.content, "application/dxf")})
        listed = c.post("/v1/imports", files={"file": ("belt.dxf", dxf.content, "application/dxf")}, data={"list": "true"})
        spec = c.get("/openapi.json").json()
    assert r.status_code == 200, r.text
    got = r.json()
    assert got["kind"] == "fence_layout" and got["belt_width"] == pytest.approx(doc["belt_width"], rel=1e-9)
    for mine, want in zip(got["fences"], doc["fences"], strict=True):
        assert mine["side"] == want["side"]
        assert mine["angle_deg"] == pytest.approx(want["angle_deg"], abs=1e-9)
        for key in ("position", "length"):
            assert mine[key] == pytest.approx(want[key], abs=1e-9 * doc["belt_width"])
    assert "FenceLayoutOut" in spec["components"]["schemas"]
    assert listed.status_code == 200 and listed.json()["fences"] == got["fences"]


TRIANGLE = {"name": "tri", "units": "in", "boundary": [[0, 0], [5, 0], [1, 3]]}


def test_same_rail_is_the_apis_and_off_by_default(server: Server) -> None:
    """The triangle (fence friction up to 0.03: none over 0.1–0.3): refused with alternating
    fences (the refusal naming the same-rail design), designed with ``same_rail``, two
    consecutive fences on one rail, as the API's."""
    friction = [0.0, 0.03]
    with server.client() as c:
        refused = c.post("/v1/fences", json={"part": TRIANGLE, "exact": True, "fence_friction": friction})
        r = c.post("/v1/fences", json={"part": TRIANGLE, "exact": True, "same_rail": True, "fence_friction": friction})
    assert refused.status_code == 422 and "--same-rail" in refused.text
    assert r.status_code == 200, r.text
    doc = r.json()
    FenceDocument.model_validate(doc)
    assert doc == json.loads(json.dumps(algrasp.fences(TRIANGLE, exact=True, same_rail=True, fence_friction=friction).to_dict()))
    sides = [f["side"] for f in doc["fences"]]
    assert doc["same_rail"] is True and any(a == b for a, b in zip(sides, sides[1:]))
