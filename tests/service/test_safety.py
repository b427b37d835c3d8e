"""Safety: API keys (every endpoint but /healthz needs a valid bearer key when keys are
configured) and time limits (work past its limit is killed; the service goes on)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.service.conftest import Server, start_server


@pytest.fixture(scope="module")
def keyed(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    d = tmp_path_factory.mktemp("keyed")
    keyfile = d / "keys"
    keyfile.write_text("# operators\nfile-key\n")
    s = start_server(d, ALGRASP_API_KEYS="k1, k2", ALGRASP_API_KEYS_FILE=str(keyfile))
    yield s
    s.kill()


def test_keys_are_required(keyed: Server, tmp_path: Path) -> None:
    with keyed.client() as c:
        assert c.get("/healthz").status_code == 200
        for path in ("/v1/runs", "/metrics", "/v1/jobs"):
            r = c.get(path)
            assert r.status_code == 401 and r.json()["error"]["type"] == "unauthorized"
            assert c.get(path, headers={"Authorization": "Bearer nope"}).status_code == 401
            assert c.get(path, headers={"Authorization": "k1"}).status_code == 401
        for key in ("k1", "k2", "file-key"):
            assert c.get("/v1/runs", headers={"Authorization": f"Bearer {key}"}).status_code == 200
        assert c.post("/v1/plans", json={}).status_code == 401  # auth before validation


def test_time_limits_kill_the_work_and_the_service_goes_on(tmp_path: Path) -> None:
    from algrasp.testing.shapes import bezier_blob, rectangle

    # The limit is far above a rectangle's analysis (~0.01 s, plus a fresh worker's start on a
    # loaded machine) and far below the slow part's (~6 s for 10,000 cubic segments).
    s = start_server(tmp_path, ALGRASP_ANALYSIS_TIME_LIMIT_S="2")
    try:
        with s.client() as c:
            slow = c.post("/v1/analyses", json=bezier_blob(10_000, 3))
            assert slow.status_code == 422, slow.text
            err = slow.json()["error"]
            assert err["type"] == "time_limit_exceeded" and err["stage"] == "analysis" and err["limit_s"] == 2
            # A fresh worker answers; a limit hit may still repeat on a badly loaded machine.
            codes = []
            for _ in range(3):
                r = c.post("/v1/analyses", json=rectangle(3.0, 1.0))
                codes.append(r.status_code)
                if r.status_code == 200:
                    break
                assert r.json()["error"]["type"] == "time_limit_exceeded", r.text
            assert codes[-1] == 200, codes
    finally:
        s.kill()
