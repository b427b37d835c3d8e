"""Tenancy (issue 31): runs and jobs belong to the key that made them (an admin key sees
all), keys configured but empty refuse to start, the public endpoints are exactly the
documented ones, and the per-client limit is keyed on the normalised key."""

from __future__ import annotations

import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from service.admission import client_id
from service.middleware import bearer_key
from tests.service.conftest import Server, start_server, wait_job

SQUARE = {"name": "sq", "units": "mm", "boundary": [[0, 0], [4, 0], [4, 3], [0, 3]]}
A, B, ADMIN = ({"Authorization": f"Bearer {k}"} for k in ("alice", "bob", "root"))


@pytest.fixture(scope="module")
def tenants(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    s = start_server(tmp_path_factory.mktemp("tenants"), ALGRASP_API_KEYS="alice,bob", ALGRASP_ADMIN_KEYS="root")
    yield s
    s.kill()


def test_runs_belong_to_their_key(tenants: Server) -> None:
    with tenants.client() as c:
        r = c.post("/v1/plans", json={"part": {**SQUARE, "name": "alice-part"}}, headers=A)
        assert r.status_code == 200, r.text
        run_id = r.json()["run_id"]
        for suffix in ("", "/record", "/playback", "/figure.svg"):
            assert c.get(f"/v1/runs/{run_id}{suffix}", headers=A).status_code == 200, suffix
            assert c.get(f"/v1/runs/{run_id}{suffix}", headers=B).status_code == 404, suffix
            assert c.get(f"/v1/runs/{run_id}{suffix}", headers=ADMIN).status_code == 200, suffix
        assert run_id in {x["run_id"] for x in c.get("/v1/runs", headers=A).json()["runs"]}
        assert run_id not in {x["run_id"] for x in c.get("/v1/runs", headers=B).json()["runs"]}
        assert run_id in {x["run_id"] for x in c.get("/v1/runs", headers=ADMIN).json()["runs"]}
        # The same key written differently is the same tenant.
        assert c.get(f"/v1/runs/{run_id}", headers={"Authorization": "bearer   alice"}).status_code == 200


def test_jobs_belong_to_their_key(tenants: Server) -> None:
    with tenants.client() as c:
        r = c.post("/v1/jobs", json={"parts": [SQUARE]}, headers=A)
        assert r.status_code == 202, r.text
        job_id = r.json()["id"]
        for suffix in ("", "/results", "/gripper"):
            assert c.get(f"/v1/jobs/{job_id}{suffix}", headers=B).status_code == 404, suffix
        assert c.delete(f"/v1/jobs/{job_id}", headers=B).status_code == 404
        assert job_id not in {j["id"] for j in c.get("/v1/jobs", headers=B).json()["jobs"]}
        assert job_id in {j["id"] for j in c.get("/v1/jobs", headers=ADMIN).json()["jobs"]}
        c.headers.update(A)
        done = wait_job(c, job_id)
        run_id = done["parts"][0]["run_id"]
        assert run_id and c.get(f"/v1/runs/{run_id}", headers=A).status_code == 200
        assert c.get(f"/v1/runs/{run_id}", headers=B).status_code == 404  # the job's runs are the job owner's


def test_the_public_endpoints_are_exactly_the_documented_ones(tenants: Server) -> None:
    public = {"/healthz", "/readyz", "/", "/docs", "/redoc", "/openapi.json", "/ui/app.js"}
    keyed = {"/v1/schemas/part", "/v1/examples", "/v1/layouts/foxglove.json", "/metrics", "/v1/runs", "/v1/jobs"}
    with tenants.client() as c:
        for path in public:
            assert c.get(path).status_code == 200, path
        for path in keyed:
            assert c.get(path).status_code == 401, path
            assert c.get(path, headers=A).status_code == 200, path
        spec = c.get("/openapi.json").json()
        for path in spec["paths"]:
            if "{" in path:
                continue
            for method in spec["paths"][path]:
                if method == "get" and path not in public:
                    assert c.get(path).status_code == 401, path


@pytest.mark.parametrize("env", [{"ALGRASP_API_KEYS": ","}, {"ALGRASP_API_KEYS": " , "}, {"file": "# only comments\n\n"}])
def test_keys_configured_but_empty_refuse_to_start(tmp_path: Path, env: dict[str, str]) -> None:
    import os

    if "file" in env:
        (tmp_path / "keys").write_text(env["file"])
        env = {"ALGRASP_API_KEYS_FILE": str(tmp_path / "keys")}
    out = subprocess.run([sys.executable, "-m", "algrasp.cli", "serve", "--no-example", "--port", "1"],
                         env={**os.environ, "ALGRASP_LOG_DIR": str(tmp_path), **env},
                         capture_output=True, text=True, timeout=120)
    assert out.returncode != 0 and "Traceback" not in out.stderr
    assert "ALGRASP_API_KEYS" in out.stderr and "none is given" in out.stderr, out.stderr


def test_the_client_of_the_rate_limit_is_the_normalised_key() -> None:
    assert bearer_key("Bearer k1") == bearer_key("bearer   k1  ") == bearer_key("  BEARER k1") == "k1"
    assert bearer_key("k1") is None and bearer_key("Basic k1") is None and bearer_key("Bearer ") is None
    assert client_id(bearer_key("Bearer  k1 "), "1.2.3.4") == client_id("k1", "5.6.7.8")
    assert client_id(None, "1.2.3.4") == "addr:1.2.3.4"


def test_the_cost_of_a_request_is_estimated_from_its_size() -> None:
    from algrasp.testing.shapes import bezier_blob
    from service.admission import FAST_COST, estimated_cost

    square = {"polygon": [[0, 0], [1, 0], [1, 1], [0, 1]]}
    assert estimated_cost(square) == 4 and estimated_cost(square, 360) == 8
    blob = bezier_blob(6000, 3)
    assert estimated_cost(blob) == 3 * 6000 > FAST_COST  # control points - 1 per cubic piece
    assert estimated_cost({"boundary": "x", "holes": 3}) == 0 and estimated_cost([1]) == 0  # malformed: no crash


def test_costly_analyses_do_not_hold_the_cheap_plans(tmp_path: Path) -> None:
    """Issue 31: three clients analysing a 6,000-piece Bezier part with samples=3600 made
    cheap plans wait 21 s. Now they go to the slow pool: every cheap plan is answered while
    the costly analyses are still in flight (an ordering of events, not a time bound)."""
    import threading

    from algrasp.testing.shapes import bezier_blob

    s = start_server(tmp_path)
    try:
        blob = bezier_blob(6000, 3)
        heavy = [threading.Thread(target=lambda k=k: s.client().post("/v1/analyses", json={**blob, "name": f"h{k}"},
                                                                      params={"samples": 3600}, timeout=300))
                 for k in range(3)]
        for t in heavy:
            t.start()
        while not list(tmp_path.glob("*.mcap.partial")):  # the event: a costly analysis is being computed
            assert all(t.is_alive() for t in heavy)
            time.sleep(0.01)
        with s.client() as c:
            for k in range(5):
                r = c.post("/v1/plans", json={"part": {**SQUARE, "name": f"cheap{k}"}})
                assert r.status_code == 200, r.text
        assert all(t.is_alive() for t in heavy), "a cheap plan waited for a costly analysis to end"
        for t in heavy:
            t.join(300)
    finally:
        s.kill()
