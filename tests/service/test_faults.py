"""Faults (issue 18): a worker killed mid-request, a full disk, a read-only database, the
server killed or stopped with work in flight. Each ends in a clean 503 (or a retry), no
half-written record, no orphaned process, and recovery once the fault is gone."""

from __future__ import annotations

import os
import resource
import signal
import threading
import time
from pathlib import Path
from typing import Any

import httpx
import psutil
import pytest

from algrasp.geometry.shapes import bezier_blob
from tests.service.conftest import start_server

SQUARE = {"name": "sq", "units": "mm", "boundary": [[0, 0], [4, 0], [4, 3], [0, 3]]}


def _workers(pid: int) -> list[psutil.Process]:
    """The server's pool workers (spawned interpreters; not the resource tracker)."""
    return [p for p in psutil.Process(pid).children(recursive=True) if "spawn_main" in " ".join(p.cmdline())]


def _wait_busy(pid: int, before: dict[int, float], cpu_s: float = 0.3, limit_s: float = 60.0) -> None:
    """Until some worker has used ``cpu_s`` more CPU than in ``before`` (an event, not a
    wall-clock guess: a loaded machine only makes it later)."""
    deadline = time.monotonic() + limit_s
    while time.monotonic() < deadline:
        if any(p.cpu_times().user - before.get(p.pid, 0.0) >= cpu_s for p in _workers(pid)):
            return
        time.sleep(0.02)
    raise AssertionError("no worker started the request")


def _plan(c: httpx.Client, name: str) -> httpx.Response:
    return c.post("/v1/plans", json={"part": {**SQUARE, "name": name}}, timeout=60)


def test_worker_killed_mid_request_is_503_then_the_service_goes_on(tmp_path: Path) -> None:
    s = start_server(tmp_path, ALGRASP_FAST_WORKERS="1")
    try:
        with s.client() as c:
            assert _plan(c, "warm").status_code == 200
            out: dict[str, Any] = {}
            before = {p.pid: p.cpu_times().user for p in _workers(s.proc.pid)}
            slow = threading.Thread(target=lambda: out.update(r=c.post("/v1/analyses", json=bezier_blob(12000, 3))))
            slow.start()
            _wait_busy(s.proc.pid, before)  # a worker is computing the request: kill it mid-request
            for p in _workers(s.proc.pid):
                p.kill()
            slow.join(60)
            r = out["r"]
            assert r.status_code == 503 and r.json()["error"]["reason"] == "worker_lost", r.text
            assert r.headers["Retry-After"]
            assert _plan(c, "after").status_code == 200
            assert not list(tmp_path.glob("*.partial"))
    finally:
        s.kill()


def _limit_writes(pid: int, max_bytes: int) -> None:
    """RLIMIT_FSIZE on the server and its workers: writes past ``max_bytes`` fail with
    EFBIG, as on a full disk (Python ignores SIGXFSZ, so the write itself fails)."""
    for p in [psutil.Process(pid), *psutil.Process(pid).children(recursive=True)]:
        _, hard = resource.prlimit(p.pid, resource.RLIMIT_FSIZE)
        resource.prlimit(p.pid, resource.RLIMIT_FSIZE, (max_bytes, hard))  # the soft limit: can be lifted again


def test_full_disk_is_503_with_nothing_half_written_then_recovers(tmp_path: Path) -> None:
    s = start_server(tmp_path)
    try:
        with s.client() as c:
            assert _plan(c, "warm").status_code == 200
            before = set(tmp_path.glob("*.mcap"))
            _limit_writes(s.proc.pid, 1024)
            r = _plan(c, "on-a-full-disk")
            assert r.status_code == 503, r.text
            err = r.json()["error"]
            assert err["type"] == "storage_error" and err["reason"] == "records" and r.headers["Retry-After"]
            assert set(tmp_path.glob("*.mcap")) == before and not list(tmp_path.glob("*.partial"))
            _limit_writes(s.proc.pid, resource.RLIM_INFINITY)
            r = _plan(c, "on-a-full-disk")
            assert r.status_code == 200 and (tmp_path / f"{r.json()['run_id']}.mcap").is_file()
            assert c.get("/readyz").status_code == 200
    finally:
        s.kill()


def test_read_only_database_is_503_and_the_run_is_indexed_later(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from fastapi.testclient import TestClient
    from sqlalchemy.exc import OperationalError

    from service.app import create_app
    from service.settings import Settings
    from service.store import Store

    def read_only(*_: Any, **__: Any) -> None:
        raise OperationalError("INSERT", {}, Exception("attempt to write a readonly database"))

    with TestClient(create_app(Settings(log_dir=tmp_path, workers=1, fast_workers=1))) as c:
        with monkeypatch.context() as m:
            m.setattr(Store, "add_runs", read_only)
            m.setattr(Store, "check", read_only)
            r = c.post("/v1/plans", json={"part": SQUARE})
            assert r.status_code == 503 and r.json()["error"]["reason"] == "database", r.text
            lost = r.json()["error"]["message"].split()[2]  # "the run <id> is recorded …"
            ready = c.get("/readyz")
            assert ready.status_code == 503 and ready.json()["error"]["reason"] == "database"
        assert c.get("/readyz").status_code == 200  # the fault is gone: the waiting run is indexed
        assert c.get(f"/v1/runs/{lost}").status_code == 200


def test_kill_9_leaves_no_orphans(tmp_path: Path) -> None:
    s = start_server(tmp_path)
    with s.client() as c:
        assert c.get("/readyz").status_code == 200  # every pool has started its workers
    workers = _workers(s.proc.pid)
    assert len(workers) >= 3
    os.kill(s.proc.pid, signal.SIGKILL)
    s.proc.wait(10)
    _, alive = psutil.wait_procs(workers, timeout=10)
    assert not alive, [p.pid for p in alive]


def test_sigterm_with_work_in_flight_stops_promptly(tmp_path: Path) -> None:
    s = start_server(tmp_path)
    try:
        workers = _workers(s.proc.pid)
        threading.Thread(target=lambda: httpx.post(f"{s.url}/v1/analyses", json=bezier_blob(6000, 3), timeout=60),
                         daemon=True).start()
        time.sleep(1.0)
        t0 = time.perf_counter()
        s.proc.send_signal(signal.SIGTERM)
        s.proc.wait(20)
        assert time.perf_counter() - t0 < 15
        _, alive = psutil.wait_procs(workers, timeout=10)
        assert not alive
    finally:
        s.kill()
