"""A real Dask cluster (issue 31): scheduler and workers as separate processes (the
``dask`` command line, as a deployment runs them). Fail fast with a clear message when
the scheduler is unreachable, malformed or has no workers; the service refuses jobs
while no worker can take them; small catalogues are spread over workers; a worker killed
mid-job loses no part and runs none twice."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import psutil
import pytest

from algrasp.testing.shapes import rectangle
from service.launch import free_port
from service.store import Store
from tests.service.conftest import start_server, wait_job

pytest.importorskip("distributed")
DASK = str(Path(sys.executable).with_name("dask"))
GUARD_S = 120.0


def _spawn(*argv: str, log: Path) -> subprocess.Popen[bytes]:
    with open(log, "ab") as f:
        return subprocess.Popen([DASK, *argv], stdout=f, stderr=subprocess.STDOUT, start_new_session=True,
                                env={**os.environ, "DASK_DISTRIBUTED__WORKER__DAEMON": "False"})


def _stop(proc: subprocess.Popen[bytes]) -> None:
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(30)


def _wait_for(log: Path, text: str, proc: subprocess.Popen[bytes]) -> None:
    deadline = time.monotonic() + GUARD_S
    while text not in log.read_text(errors="replace"):
        assert proc.poll() is None and time.monotonic() < deadline, log.read_text(errors="replace")[-2000:]
        time.sleep(0.05)


@pytest.fixture
def scheduler(tmp_path: Path) -> Iterator[str]:
    port = free_port()
    log = tmp_path / "scheduler.log"
    proc = _spawn("scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard", log=log)
    try:
        _wait_for(log, "Scheduler at", proc)
        yield f"tcp://127.0.0.1:{port}"
    finally:
        _stop(proc)


def _worker(address: str, log: Path) -> subprocess.Popen[bytes]:
    proc = _spawn("worker", address, "--nthreads", "1", "--nworkers", "1", "--no-dashboard", log=log)
    _wait_for(log, "Registered to", proc)
    return proc


def _batch(tmp_path: Path, *args: str) -> subprocess.CompletedProcess[str]:
    cat = tmp_path / "cat"
    cat.mkdir(exist_ok=True)
    for i in range(3):
        (cat / f"r{i}.json").write_text(json.dumps(dict(rectangle(4.0 + i, 2.0), name=f"r{i}")))
    return subprocess.run([sys.executable, "-m", "algrasp.cli", "batch", str(cat), "--out", str(tmp_path / "out"), *args],
                          capture_output=True, text=True, timeout=GUARD_S)


def test_a_scheduler_without_workers_fails_fast(tmp_path: Path, scheduler: str) -> None:
    out = _batch(tmp_path, "--scheduler", scheduler, "--wait-for-workers-s", "1")
    assert out.returncode == 3 and "has no workers" in out.stderr and "Traceback" not in out.stderr, out.stderr[-1500:]


@pytest.mark.parametrize("address", ["not an address", "tcp://", "http://x:1:2", "tcp://127.0.0.1:99999"])
def test_a_malformed_scheduler_address_is_refused_at_once(tmp_path: Path, address: str) -> None:
    t0 = time.monotonic()
    out = _batch(tmp_path, "--scheduler", address)
    assert out.returncode == 2 and "scheduler" in out.stderr and "Traceback" not in out.stderr, out.stderr[-1500:]
    assert time.monotonic() - t0 < GUARD_S


def test_an_unreachable_scheduler_is_a_clear_error(tmp_path: Path) -> None:
    out = _batch(tmp_path, "--scheduler", f"tcp://127.0.0.1:{free_port()}")
    assert out.returncode == 3 and "cannot reach the Dask scheduler" in out.stderr, out.stderr[-1500:]
    assert "Traceback" not in out.stderr and "__del__" not in out.stderr, out.stderr[-1500:]


def test_the_service_refuses_jobs_while_the_scheduler_has_no_workers(tmp_path: Path, scheduler: str) -> None:
    s = start_server(tmp_path, ALGRASP_SCHEDULER=scheduler)
    try:
        with s.client() as c:
            r = c.post("/v1/jobs", json={"parts": [rectangle(4.0, 2.0)]})
            assert r.status_code == 503 and r.json()["error"]["reason"] == "no_workers", r.text
            assert c.get("/readyz").status_code == 503
            worker = _worker(scheduler, tmp_path / "worker.log")
            try:
                r = c.post("/v1/jobs", json={"parts": [rectangle(4.0, 2.0)]})
                assert r.status_code == 202, r.text
                assert wait_job(c, r.json()["id"])["done"] == 1
            finally:
                _stop(worker)
    finally:
        s.kill()


def test_a_small_catalogue_is_spread_over_the_workers() -> None:
    from service.jobs import JobRunner, RunnerConfig

    class TwoWorkers:
        name = "fake"
        alive = True

        def capacity(self) -> int:
            return 2

    runner = JobRunner(None, TwoWorkers(), RunnerConfig.for_workers("/tmp", 1, 10.0, 2, 8))  # type: ignore[arg-type]
    chunks = runner._chunks("job", [(i, {}) for i in range(5)], {i: f"run{i}" for i in range(5)})
    assert sorted(len(c) for c in chunks) == [2, 3]
    # Mid-job, the room one finished chunk made (8 parts) goes out as one full chunk: with
    # 100 parts still to send, splitting it over both workers would halve every chunk in
    # turn, down to one part per dispatch. The job's last parts are spread again.
    eight = [(i, {}) for i in range(8)]
    ids = {i: f"run{i}" for i in range(8)}
    assert [len(c) for c in runner._chunks("job", eight, ids, left=100)] == [8]
    assert sorted(len(c) for c in runner._chunks("job", eight[:5], ids, left=5)) == [2, 3]


def test_a_dask_worker_killed_mid_job_loses_nothing(tmp_path: Path, scheduler: str) -> None:
    workers = [_worker(scheduler, tmp_path / f"worker{k}.log") for k in range(2)]
    s = start_server(tmp_path, ALGRASP_SCHEDULER=scheduler, ALGRASP_BATCH_CHUNK="2")
    parts = [dict(rectangle(5.0 + 0.1 * i, 2.0), name=f"r{i}") for i in range(60)]
    try:
        with s.client() as c:
            job_id = c.post("/v1/jobs", json={"parts": parts}).json()["id"]
            deadline = time.monotonic() + GUARD_S
            while c.get(f"/v1/jobs/{job_id}").json()["done"] < 5:  # the event: the job is under way
                assert time.monotonic() < deadline
                time.sleep(0.02)
            for p in [psutil.Process(workers[0].pid), *psutil.Process(workers[0].pid).children(recursive=True)]:
                p.kill()  # the nanny too: the worker is gone for good, its tasks go to the other
            job = wait_job(c, job_id, timeout_s=300)
            runs = c.get("/v1/runs", params={"limit": 1000}).json()["runs"]
    finally:
        s.kill()
        for w in workers:
            _stop(w)
    rows = Store(f"sqlite:///{tmp_path / 'algrasp.db'}").results(job_id)
    assert job["state"] == "done" and [r["status"] for r in rows] == ["done"] * len(parts)
    assert sorted(r["run_id"] for r in runs if r["job_id"] == job_id) == sorted(r["run_id"] for r in rows)
    assert {p.stem for p in tmp_path.glob("*.mcap")} == {r["run_id"] for r in rows}
    assert [r["result"]["name"] for r in rows] == [p["name"] for p in parts]
