"""Nothing leaked, nothing ambiguous (issue 31): duplicate headers are refused, damaged
records never make a 500 (API, replay, runs, playback), no server path in any response,
links in the record directory are not followed, a tiny response cache still answers."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from mcap.reader import make_reader
from mcap.writer import Writer

from tests.service.conftest import Server, start_server

SQUARE = {"name": "sq", "units": "mm", "boundary": [[0, 0], [4, 0], [4, 3], [0, 3]]}


@pytest.fixture(scope="module")
def srv(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    s = start_server(tmp_path_factory.mktemp("leaks"), ALGRASP_CACHE_BYTES="0")
    yield s
    s.kill()


def _raw_request(server: Server, head: str, body: bytes) -> tuple[int, bytes]:
    """One HTTP/1.1 request written by hand (httpx merges repeated headers)."""
    host, port = server.url.removeprefix("http://").split(":")
    with socket.create_connection((host, int(port)), timeout=60) as s:
        s.sendall(head.replace("\n", "\r\n").encode() + b"\r\n" + body)
        data = b""
        while b"\r\n\r\n" not in data or len(data) < data.index(b"\r\n\r\n") + 4 + _length(data):
            chunk = s.recv(65536)
            if not chunk:
                break
            data += chunk
    return int(data.split(b" ", 2)[1]), data.split(b"\r\n\r\n", 1)[1]


def _length(data: bytes) -> int:
    for line in data.split(b"\r\n\r\n", 1)[0].split(b"\r\n"):
        if line.lower().startswith(b"content-length:"):
            return int(line.split(b":", 1)[1])
    return 0


@pytest.mark.parametrize("value", ["NaN", "Infinity", "1e400", "9" * 400, '"\\ud800"'])
def test_two_content_types_are_refused_before_any_parsing(srv: Server, value: str) -> None:
    body = ('{"part": {"name": ' + (value if value.startswith('"') else '"x"') + ', "boundary": [[0, 0], ['
            + (value if not value.startswith('"') else "1") + ', 0], [1, 1]]}}').encode()
    head = (f"POST /v1/plans HTTP/1.1\nHost: x\nContent-Type: application/json\nContent-Type: text/plain\n"
            f"Content-Length: {len(body)}\nConnection: close\n")
    status, out = _raw_request(srv, head, body)
    assert status == 400, out
    err = json.loads(out)["error"]
    assert err["type"] == "ambiguous_request" and err["field"] == "content-type"


def test_two_authorization_headers_are_refused(srv: Server) -> None:
    head = "GET /v1/runs HTTP/1.1\nHost: x\nAuthorization: Bearer a\nAuthorization: Bearer b\nConnection: close\n"
    status, out = _raw_request(srv, head, b"")
    assert status == 400 and json.loads(out)["error"]["field"] == "authorization"


def _plan(srv: Server, name: str) -> str:
    with srv.client() as c:
        r = c.post("/v1/plans", json={"part": {**SQUARE, "name": name}})
        assert r.status_code == 200, r.text
        return str(r.json()["run_id"])


def _rewrite(path: Path, replace: dict[str, bytes]) -> None:
    """Copy a record with the payload of each topic in ``replace`` swapped (written with
    the mcap library itself, not the project's recorder)."""
    with open(path, "rb") as f:
        messages = [(ch.topic, ch.message_encoding, sc, m.log_time, m.data) for sc, ch, m in make_reader(f).iter_messages()]
    with open(path, "wb") as f:
        w = Writer(f)
        w.start()
        channels: dict[str, int] = {}
        for topic, enc, schema, t, data in messages:
            if topic not in channels:
                sid = w.register_schema(schema.name, schema.encoding, schema.data) if schema else 0
                channels[topic] = w.register_channel(topic, enc, sid)
            w.add_message(channels[topic], t, replace.get(topic, data), t)
        w.finish()


DAMAGE = {
    "run is a list": {"/run": b"[1, 2]"},
    "run is a string": {"/run": b'"ok"'},
    "run is null": {"/run": b"null"},
    "run agreement is a string": {"/run": b'{"run_id": "x", "command": "plan", "status": "ok", "started_unix_s": 1, '
                                          b'"timings_s": {}, "versions": {}, "agreement": "lots"}'},
    "NaN in the run": {"/run": b'{"run_id": "x", "command": "plan", "status": "ok", "started_unix_s": NaN, '
                                b'"timings_s": {}, "versions": {}}'},
    "lone surrogate in the run": {"/run": b'{"run_id": "\\ud800", "command": "plan", "status": "ok", '
                                            b'"started_unix_s": 1, "timings_s": {}, "versions": {}}'},
    "NaN in the request": {"/request": b'{"run_id": "x", "command": "plan", "part": {"boundary": [[NaN, 0]]}, '
                                       b'"options": {}}'},
    "request is a list": {"/request": b"[]"},
    "plan steps not a list": {"/plan": b'{"action": "squeeze", "symmetry_period_deg": 90, "steps": 3, '
                                       b'"final_orientations_deg": [], "verified": true}'},
}


@pytest.mark.parametrize("case", sorted(DAMAGE))
def test_damaged_records_are_never_a_500(srv: Server, case: str) -> None:
    run_id = _plan(srv, f"damaged-{case}")
    path = srv.log_dir / f"{run_id}.mcap"
    _rewrite(path, DAMAGE[case])
    with srv.client() as c:
        for suffix in ("", "/playback", "/figure.svg", "/record"):
            r = c.get(f"/v1/runs/{run_id}{suffix}")
            assert r.status_code < 500, (suffix, r.status_code, r.text[:300])
        detail = c.get(f"/v1/runs/{run_id}").json()
        if "/run" in DAMAGE[case]:
            assert detail["record"] is None and "damaged" in detail["record_error"], detail
        assert c.get("/v1/runs").status_code == 200
    for argv in (["replay", str(path)], ["runs", "--dir", str(srv.log_dir)], ["runs", "--json", "--dir", str(srv.log_dir)]):
        out = subprocess.run([sys.executable, "-m", "algrasp.cli", *argv], capture_output=True, text=True, timeout=120)
        assert "Traceback" not in out.stderr, (argv, out.stderr[-2000:])
        assert out.returncode in (0, 2), (argv, out.returncode, out.stderr[-500:])


def _no_paths(value: Any, forbidden: str) -> None:
    text = json.dumps(value)
    assert forbidden not in text and "record_path" not in text, text[:500]


def test_no_server_path_in_any_response(srv: Server) -> None:
    run_id = _plan(srv, "paths")
    root = str(srv.log_dir.resolve())
    with srv.client() as c:
        for url in ("/v1/runs", f"/v1/runs/{run_id}", f"/v1/runs/{run_id}/playback", "/readyz", "/healthz"):
            r = c.get(url)
            assert r.status_code == 200, (url, r.text)
            _no_paths(r.json(), root)
    os.chmod(srv.log_dir, 0o500)  # a read-only record directory: the 503s must not say where it is
    try:
        with srv.client() as c:
            if os.geteuid() != 0:  # root writes anyway: the readiness probe would pass
                r = c.get("/readyz")
                assert r.status_code == 503 and root not in r.text
                r = c.post("/v1/plans", json={"part": {**SQUARE, "name": "paths-ro"}})
                assert r.status_code == 503 and root not in r.text, r.text
    finally:
        os.chmod(srv.log_dir, 0o700)


def test_links_in_the_record_directory_are_not_followed(srv: Server, tmp_path: Path) -> None:
    run_id = _plan(srv, "link")
    path = srv.log_dir / f"{run_id}.mcap"
    secret = tmp_path / "secret.txt"
    secret.write_text("root:x:0:0:secret\n")
    path.unlink()
    path.symlink_to(secret)
    with srv.client() as c:
        for suffix in ("", "/record", "/playback", "/figure.svg"):
            r = c.get(f"/v1/runs/{run_id}{suffix}")
            assert r.status_code == 404 and "secret" not in r.text, (suffix, r.status_code)


def test_a_zero_byte_cache_still_draws_figures(srv: Server) -> None:
    run_id = _plan(srv, "figure-no-cache")
    with srv.client() as c:
        for _ in range(2):
            r = c.get(f"/v1/runs/{run_id}/figure.svg")
            assert r.status_code == 200 and r.text.lstrip().startswith(("<?xml", "<svg")), r.text[:200]
        r = c.get(f"/v1/runs/{run_id}/record")
        assert r.status_code == 200 and r.content.startswith(b"\x89MCAP")


def test_job_results_are_paged_within_the_response_bound(tmp_path: Path) -> None:
    from tests.service.conftest import wait_job

    s = start_server(tmp_path, ALGRASP_MAX_RESPONSE_BYTES="10000")
    try:
        with s.client() as c:
            parts = [{**SQUARE, "name": f"sq{i}", "boundary": [[0, 0], [4 + i, 0], [4 + i, 3], [0, 3]]} for i in range(20)]
            job_id = c.post("/v1/jobs", json={"parts": parts}).json()["id"]
            wait_job(c, job_id)
            r = c.get(f"/v1/jobs/{job_id}/results")
            assert r.status_code == 422 and r.json()["error"]["field"] == "limit", r.text[:300]
            url, names = f"/v1/jobs/{job_id}/results?limit=2", []
            while url:
                r = c.get(url)
                assert r.status_code == 200 and len(r.content) <= 10000 and r.headers["X-Total-Count"] == "20"
                names += [json.loads(line)["name"] for line in r.text.splitlines()]
                link = r.headers.get("Link")
                url = link.split(">")[0].lstrip("<") if link else ""
            assert names == [p["name"] for p in parts]
    finally:
        s.kill()
