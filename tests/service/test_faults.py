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

from algrasp.testing.shapes import bezier_blob
from tests.service.conftest import pool_workers, start_server

SQUARE = {"name": "sq", "units": "mm", "boundary": [[0, 0], [4, 0], [4, 3], [0, 3]]}


def _idle(c: httpx.Client, pid: int) -> dict[int, float]:
    """Every pool has answered a readiness ping (one worker each: all warm, none busy);
    then each worker's CPU so far."""
    assert c.get("/readyz").status_code == 200
    return {p.pid: p.cpu_times().user for p in pool_workers(pid)}


def _wait_busy(pid: int, before: dict[int, float], cpu_s: float = 0.3, limit_s: float = 120.0) -> psutil.Process:
    """The worker that has used ``cpu_s`` more CPU than in ``before`` (taken when all were
    idle): the one computing the request — whichever pool its cost sent it to (an event,
    not a wall-clock guess: a loaded machine only makes it later; ``limit_s`` only guards
    against a hang)."""
    deadline = time.monotonic() + limit_s
    while time.monotonic() < deadline:
        for p in pool_workers(pid):
            if p.cpu_times().user - before.get(p.pid, 0.0) >= cpu_s:
                return p
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
            before = _idle(c, s.proc.pid)
            slow = threading.Thread(target=lambda: out.update(r=c.post("/v1/analyses", json=bezier_blob(12000, 3))))
            slow.start()
            _wait_busy(s.proc.pid, before).kill()  # the worker computing the request, mid-request
            slow.join(120)
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
    workers = pool_workers(s.proc.pid)
    assert len(workers) >= 3
    os.kill(s.proc.pid, signal.SIGKILL)
    s.proc.wait(10)
    _, alive = psutil.wait_procs(workers, timeout=10)
    assert not alive, [p.pid for p in alive]


def test_sigterm_with_work_in_flight_stops_promptly(tmp_path: Path) -> None:
    """SIGTERM while a request that needs several seconds is computing: the server waits
    at most its grace (1 s) and stops — the request is cut, not finished — and no worker
    is left. Synchronised on events (the worker busy, the process exit), not on sleeps."""
    s = start_server(tmp_path, ALGRASP_SHUTDOWN_GRACE_S="1", ALGRASP_ANALYSIS_TIME_LIMIT_S="600",
                     ALGRASP_FAST_WORKERS="1")
    try:
        with s.client() as c:
            before = _idle(c, s.proc.pid)
        workers = pool_workers(s.proc.pid)
        out: dict[str, Any] = {}

        def slow() -> None:
            try:
                out["status"] = httpx.post(f"{s.url}/v1/analyses", json=bezier_blob(12000, 3), timeout=600).status_code
            except httpx.TransportError as exc:
                out["status"] = type(exc).__name__

        t = threading.Thread(target=slow, daemon=True)
        t.start()
        _wait_busy(s.proc.pid, before)
        s.proc.send_signal(signal.SIGTERM)
        s.proc.wait(120)  # a hang guard only
        t.join(120)
        assert out["status"] != 200, out  # the server did not wait for the work
        _, alive = psutil.wait_procs(workers, timeout=30)
        assert not alive
    finally:
        s.kill()


def _sim_workers(pid: int) -> list[psutil.Process]:
    """Drake's simulation workers: spawned by a pool worker (grandchildren of the server)."""
    return [p for p in pool_workers(pid) if p.ppid() != pid]


@pytest.mark.sim
def test_a_killed_drake_worker_is_one_503_then_validation_works_again(tmp_path: Path) -> None:
    """Issue 31: after one simulation worker was killed, every later validation on that
    pool worker failed (a broken process pool kept and reused)."""
    s = start_server(tmp_path, ALGRASP_SIM_WORKERS="2")
    body = {"part": SQUARE, "action": "squeeze", "validate": {"samples": 40, "seed": 1}}
    try:
        with s.client() as c:
            out: dict[str, Any] = {}
            t = threading.Thread(target=lambda: out.update(r=c.post("/v1/plans", json=body, timeout=600)))
            t.start()
            deadline = time.monotonic() + 300  # a hang guard: the event is the simulation workers appearing busy
            victim = None
            while victim is None and time.monotonic() < deadline:
                sims = [p for p in _sim_workers(s.proc.pid) if p.cpu_times().user > 1.0]
                victim = sims[0] if sims else None
                time.sleep(0.05)
            assert victim is not None, "no simulation worker started"
            victim.kill()
            t.join(600)
            r = out["r"]
            assert r.status_code == 503 and r.json()["error"]["reason"] == "worker_lost", r.text[:300]
            for seed in (2, 3):  # the pool is replaced: validations work again, not [200, 500, 200, 500]
                again = c.post("/v1/plans", json={**body, "validate": {"samples": 4, "seed": seed}}, timeout=600)
                assert again.status_code == 200, again.text[:300]
    finally:
        s.kill()


def test_a_write_locked_database_is_a_fast_503(tmp_path: Path) -> None:
    """Another process holds SQLite's write lock (BEGIN EXCLUSIVE): a plan is answered
    503 ``database`` within the short busy timeout (not SQLite's 30 s), and once the lock
    is gone the run is indexed."""
    import sqlite3

    s = start_server(tmp_path, ALGRASP_DB_BUSY_TIMEOUT_S="0.5")
    try:
        with s.client() as c:
            assert _plan(c, "before").status_code == 200
            lock = sqlite3.connect(tmp_path / "algrasp.db", timeout=5)
            lock.execute("BEGIN EXCLUSIVE")
            try:
                t0 = time.monotonic()
                r = _plan(c, "while-locked")
                waited = time.monotonic() - t0
                assert r.status_code == 503 and r.json()["error"]["reason"] == "database", r.text
                assert waited < 20, waited  # SQLite's default 30 s busy wait is gone (a loose bound: CI is slow)
            finally:
                lock.rollback()
                lock.close()
            assert c.get("/readyz").status_code == 200
            runs = {x["part_name"] for x in c.get("/v1/runs").json()["runs"]}
            assert "while-locked" in runs  # indexed once the database was writable again
    finally:
        s.kill()


def test_a_trickled_body_is_cut_with_408(tmp_path: Path) -> None:
    """A client that sends its body a byte at a time cannot hold the connection past the
    body timeout; the service answers others meanwhile."""
    import socket

    s = start_server(tmp_path, ALGRASP_BODY_TIMEOUT_S="1")
    try:
        host, port = s.url.removeprefix("http://").split(":")
        with socket.create_connection((host, int(port)), timeout=60) as sock:
            sock.sendall(b"POST /v1/plans HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
                         b"Content-Length: 100000\r\n\r\n{")
            with s.client() as c:
                assert _plan(c, "meanwhile").status_code == 200
            data = b""
            while b"\r\n\r\n" not in data:  # the event: the server answers (no sleep to guess when)
                chunk = sock.recv(4096)
                if not chunk:
                    break
                data += chunk
        assert data.startswith(b"HTTP/1.1 408"), data[:200]
    finally:
        s.kill()


def test_trickled_headers_are_cut(tmp_path: Path) -> None:
    """Slowloris: 50 connections that send half a request head and stop are closed by the
    server after its header timeout (the event: the socket reads end-of-file), and the
    service answers others meanwhile."""
    import socket

    s = start_server(tmp_path, ALGRASP_HEADER_TIMEOUT_S="1")
    try:
        host, port = s.url.removeprefix("http://").split(":")
        socks = [socket.create_connection((host, int(port)), timeout=120) for _ in range(50)]
        for sock in socks:
            sock.sendall(b"GET /v1/runs HTTP/1.1\r\nHost: x\r\nX-Slow: ")
        with s.client() as c:
            assert _plan(c, "meanwhile").status_code == 200
        for sock in socks:
            assert sock.recv(4096) == b""  # closed by the server, not by our timeout (that would raise)
            sock.close()
    finally:
        s.kill()
