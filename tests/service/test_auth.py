"""API keys: with keys configured every endpoint but /healthz needs a valid bearer key."""

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
