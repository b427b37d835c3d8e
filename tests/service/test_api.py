"""The HTTP API over a real uvicorn server: results checked against closed forms and the
paper's pie part, caching, runs and records, errors, limits, metrics."""

from __future__ import annotations

import io
import math
import zipfile
from pathlib import Path
from typing import Any

import pytest

from algrasp.io.record.replay import read_record
from algrasp.testing.shapes import rectangle
from tests.service.conftest import Server, wait_job


def test_analysis_of_the_pie_has_the_papers_steps(server: Server, pie: dict[str, Any]) -> None:
    with server.client() as c:
        r = c.post("/v1/analyses", json=pie)
    assert r.status_code == 200
    sq = r.json()["squeeze"]
    # conventions §6: two steps of 70° and a 40° ramp per 180°
    widths = sorted(s["end_deg"] - s["start_deg"] for s in sq["steps"])
    assert widths == pytest.approx([70.0, 70.0], abs=1e-6)
    assert [r["end_deg"] - r["start_deg"] for r in sq["ramps"]] == pytest.approx([40.0], abs=1e-6)


def test_plan_is_recorded_cached_and_replayable(server: Server, pie: dict[str, Any], tmp_path: Path) -> None:
    body = {"part": pie, "action": "push_grasp", "optimise": True}
    with server.client() as c:
        first = c.post("/v1/plans", json=body)
        second = c.post("/v1/plans", json=body)
        assert first.status_code == second.status_code == 200
        assert (first.headers["x-cache"], second.headers["x-cache"]) == ("miss", "hit")
        plan = first.json()
        assert second.json() == plan
        assert len(plan["final_orientations_deg"]) == 1  # push-grasp: T = 360°
        run_id = plan["run_id"]
        listed = [r["run_id"] for r in c.get("/v1/runs", params={"limit": 1000}).json()["runs"]]
        assert run_id in listed
        summary = c.get(f"/v1/runs/{run_id}").json()
        assert summary["steps"] == len(plan["steps"]) and summary["record"]["status"] == "ok"
        mcap = c.get(f"/v1/runs/{run_id}/record")
        svg = c.get(f"/v1/runs/{run_id}/figure.svg")
    assert mcap.status_code == 200
    # Not in the server's record directory: a file there without a run row is an orphan
    # its retention sweep removes after ORPHAN_AGE_S, under another test's feet.
    path = tmp_path / "downloaded.mcap"
    path.write_bytes(mcap.content)
    recorded = read_record(path, {"/plan"})["/plan"][0]
    assert recorded["cycle_time_s"] == pytest.approx(plan["cycle_time_s"], rel=1e-12)
    assert svg.status_code == 200 and svg.headers["content-type"].startswith("image/svg+xml") and b"<svg" in svg.content


def test_squeeze_of_the_pie_leaves_two_orientations(server: Server, pie: dict[str, Any]) -> None:
    with server.client() as c:
        plan = c.post("/v1/plans", json={"part": pie}).json()
    finals = plan["final_orientations_deg"]
    assert len(finals) == 2 and (finals[1] - finals[0]) == pytest.approx(180.0, abs=1e-6)  # T = 180°


@pytest.mark.parametrize(("body", "field"), [
    ({"part": {"boundary": []}}, "boundary"),
    ({"part": {"polygon": [[0, 0], [1, 0], [1, 1], [0, 1]]}, "action": "spin"}, "body.action"),
    ({"part": {"polygon": [[0, 0], [1, 0], [1, 1], [0, 1]]}, "colour": "red"}, "body.colour"),
    ({"part": {"polygon": [[0, 0], [1, 0], [1, 1], [0, 1]]}, "min_margin_deg": -1}, "body.min_margin_deg"),
    ({"part": {"polygon": [[0, 0], [1, 0], [1, 1], [0, 1]]}, "validate": {"samples": 100000}}, "validate.samples"),
    ({"part": {"polygon": [[0, 0], [1, 0], [1, 1], [0, 1]]}, "optimise": True, "gripper": {"jaw_max_speed": 1}},
     "jaw_max_speed"),
])
def test_bad_requests_get_422_naming_the_field(server: Server, body: dict[str, Any], field: str) -> None:
    with server.client() as c:
        r = c.post("/v1/plans", json=body)
    assert r.status_code == 422, r.text
    assert field in r.json()["error"]["message"]


def test_not_json_and_oversized_bodies(server: Server) -> None:
    with server.client() as c:
        assert c.post("/v1/plans", content=b"{nope", headers={"content-type": "application/json"}).status_code == 422
        big = c.post("/v1/analyses", content=b" " * 9_000_000, headers={"content-type": "application/json"})
    assert big.status_code == 413 and big.json()["error"]["type"] == "limit_exceeded"


def test_no_request_names_a_path(server: Server) -> None:
    with server.client() as c:
        for rid in ("..%2F..%2Fetc%2Fpasswd", "20260101T000000Z-deadbeef", "algrasp.db"):
            assert c.get(f"/v1/runs/{rid}/record").status_code in (404, 422)
        assert c.get("/v1/jobs/../../etc").status_code == 404


def test_batch_job_designs_the_fixture(server: Server, pie: dict[str, Any]) -> None:
    rect = rectangle(30.0, 10.0)
    disk = {"name": "disk", "boundary": [{"type": "arc", "center": [0, 0], "radius": 5, "start_deg": 0, "end_deg": 360}]}
    with server.client() as c:
        r = c.post("/v1/jobs", json={"parts": [dict(rect, name="rect"), pie, disk]})
        assert r.status_code == 202
        job = wait_job(c, r.json()["id"])
        assert (job["state"], job["done"], job["failed"]) == ("done", 3, 0)
        lines = c.get(f"/v1/jobs/{job['id']}/results").text.splitlines()
        z = zipfile.ZipFile(io.BytesIO(c.get(f"/v1/jobs/{job['id']}/results", params={"format": "zip"}).content))
    assert len(lines) == 3 and sorted(z.namelist()) == ["gripper_spec.json", "report.md", "results.jsonl", "summary.csv"]
    import json

    spec = json.loads(z.read("gripper_spec.json"))
    # rectangle 30 × 10 mm: d_max = its diagonal; default profile: 2 mm clearance each side
    diag = math.hypot(30.0, 10.0)
    assert spec["jaw_opening_mm"] == pytest.approx(diag + 4.0, rel=1e-9)
    assert spec["jaw_length_mm"] == pytest.approx(diag, rel=1e-9)
    assert [p["name"] for p in spec["not_oriented"]] == ["disk"]  # constant width and radius: no step
    assert "constant" in spec["not_oriented"][0]["why"]


def test_archive_upload_and_cancel(server: Server, pie: dict[str, Any]) -> None:
    import json

    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as zf:
        for i in range(6):
            zf.writestr(f"parts/../p{i}.json", json.dumps(rectangle(10.0 + i, 4.0)))
        zf.writestr("README.txt", "not a part")
        zf.writestr("broken.json", "{")
    with server.client() as c:
        r = c.post("/v1/jobs", files={"archive": ("cat.zip", buf.getvalue(), "application/zip")},
                   data={"options": json.dumps({"min_margin_deg": 1.0})})
        assert r.status_code == 202, r.text
        assert r.json()["total"] == 7  # six parts and the broken file (failed at once), not the README
        c.delete(f"/v1/jobs/{r.json()['id']}")
        job = wait_job(c, r.json()["id"])
        assert c.delete(f"/v1/jobs/{job['id']}").status_code == 409
    assert job["state"] == "cancelled"
    assert job["done"] + job["cancelled"] + job["failed"] == 7
    broken = [p for p in job["parts"] if p["name"] == "broken"][0]
    assert broken["status"] == "failed" and "JSON" in broken["error"]["message"]


def test_metrics_count_requests_and_plans(server: Server, pie: dict[str, Any]) -> None:
    with server.client() as c:
        c.post("/v1/plans", json={"part": pie})
        text = c.get("/metrics").text
    assert 'algrasp_http_requests_total{method="POST",route="/v1/plans",status="200"}' in text
    assert 'algrasp_plans_total{action="squeeze",cached=' in text
    assert "algrasp_http_request_duration_seconds_bucket" in text and "algrasp_job_parts" in text


def test_cad_upload_and_cad_files_in_a_job_archive(server: Server) -> None:
    import json

    from tests.algrasp.io.cad.test_svg_mesh import SVG

    with server.client() as c:
        r = c.post("/v1/imports", files={"file": ("drawing.svg", SVG, "image/svg+xml")}, data={"id": "oval"})
        assert r.status_code == 200, r.text
        doc = r.json()
        assert {s["type"] for s in doc["boundary"]} == {"ellipse_arc"}
        plan = c.post("/v1/plans", json={"part": doc}).json()
        assert len(plan["final_orientations_deg"]) == 2  # an ellipse: squeeze period 180°, symmetry 180°
        bad = c.post("/v1/imports", files={"file": ("drawing.svg", SVG, "image/svg+xml")}, data={"id": "open"})
        assert bad.status_code == 422 and "open contour" in bad.json()["error"]["message"]
        assert c.post("/v1/imports", files={"file": ("x.exe", b"MZ", "application/octet-stream")}).status_code == 422
        buf = io.BytesIO()
        with zipfile.ZipFile(buf, "w") as zf:
            zf.writestr("drawing.svg", SVG)  # a sheet: each closed shape is its own item, the open path is set aside
            zf.writestr("rect.json", json.dumps(rectangle(5.0, 2.0)))
        job = c.post("/v1/jobs", files={"archive": ("cat.zip", buf.getvalue(), "application/zip")})
        assert job.status_code == 202
        done = wait_job(c, job.json()["id"])
    by_name = {p["name"]: p for p in done["parts"]}
    assert by_name["rect-5x2"]["status"] == "done"
    assert {n for n in by_name if n.startswith("drawing#")} == {"drawing#0", "drawing#1", "drawing#2"}
    assert all(by_name[f"drawing#{k}"]["status"] == "done" for k in range(3))


@pytest.mark.sim
def test_plan_with_drake_validation(server: Server, pie: dict[str, Any]) -> None:
    body = {"part": pie, "action": "push_grasp", "optimise": True, "validate": {"samples": 4, "seed": 3}}
    with server.client() as c:
        r = c.post("/v1/plans", json=body)
        assert r.status_code == 200, r.text
        v = r.json()["validation"]
        run = c.get(f"/v1/runs/{r.json()['run_id']}").json()
    assert len(v["samples"]) == 4 and v["optimised"] is True
    # the paper's pie under an optimised push-grasp plan: every clear sample ends at the predicted orientation
    assert v["agreement_clear"] == 1.0
    assert run["command"] == "validate" and run["agreement"] == v["agreement"]


def test_imports_list_and_choose_a_part_of_a_sheet(server: Server) -> None:
    from pathlib import Path

    sheet = (Path(__file__).parents[1] / "data" / "real" / "koppi-involute-teeth-20-multiple.dxf").read_bytes()
    with server.client() as c:
        listing = c.post("/v1/imports", files={"file": ("gears.dxf", sheet, "application/dxf")}, data={"list": "true"})
        assert listing.status_code == 200, listing.text
        assert len(listing.json()["parts"]) == 10
        one = c.post("/v1/imports", files={"file": ("gears.dxf", sheet, "application/dxf")}, data={"part": "4"})
        assert one.status_code == 200 and one.json()["name"] == "gears#4"
        many = c.post("/v1/imports", files={"file": ("gears.dxf", sheet, "application/dxf")})
        assert many.status_code == 422 and "holds 10 parts" in many.json()["error"]["message"]


def test_api_docs_need_no_internet(server: Server) -> None:
    """/docs loads Swagger UI from the service itself (FastAPI's default page pulls it
    from a CDN and is blank offline)."""
    import re

    with server.client() as c:
        for page in ("/docs", "/redoc"):
            html = c.get(page).text
            urls = re.findall(r'(?:src|href)="([^"]+)"', html) + re.findall(r"url: '([^']+)'", html)
            assert urls and all(u.startswith("/") for u in urls), (page, urls)
            for u in urls:
                r = c.get(u)
                assert r.status_code == 200 and len(r.content) > 100, u
        assert len(c.get("/static-offline-docs/swagger-ui-bundle.js").content) > 1_000_000
