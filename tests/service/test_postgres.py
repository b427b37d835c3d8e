"""The store on a real PostgreSQL server (issue 31) that the tests start themselves
(Debian's ``postgresql`` binaries, installed by ``.ci/run``; skipped with the reason where
absent): the store's own operations, part claims between two holders, and two service
instances on one database running one job without doing a part twice."""

from __future__ import annotations

import glob
import os
import shutil
import subprocess
import tempfile
from collections.abc import Iterator
from pathlib import Path

import pytest

from algrasp.testing.shapes import rectangle
from service.launch import free_port
from service.store import Outcome, Store
from tests.service.conftest import start_server, wait_job


def _bin() -> Path | None:
    found = sorted(glob.glob("/usr/lib/postgresql/*/bin/initdb"))
    return Path(found[-1]).parent if found else None


def _as_postgres(argv: list[str]) -> list[str]:
    """PostgreSQL refuses to run as root: CI runs as root, so run it as its own user."""
    return ["runuser", "-u", "postgres", "--", *argv] if os.geteuid() == 0 else argv


@pytest.fixture(scope="module")
def server_url() -> Iterator[str]:
    bindir = _bin()
    if bindir is None:
        pytest.skip("no PostgreSQL server here (Debian's postgresql package; .ci/run installs it)")
    if os.geteuid() == 0 and shutil.which("runuser") is None:
        pytest.skip("running as root without runuser: PostgreSQL cannot be started")
    root = Path(tempfile.mkdtemp(prefix="algrasp-pg-"))
    if os.geteuid() == 0:
        shutil.chown(root, "postgres")
    data, port = root / "data", free_port()
    subprocess.run(_as_postgres([str(bindir / "initdb"), "-D", str(data), "-U", "postgres", "--auth=trust", "-E", "UTF8"]),
                   check=True, capture_output=True, timeout=120)
    opts = f"-p {port} -k {root} -c listen_addresses=127.0.0.1 -c fsync=off"
    subprocess.run(_as_postgres([str(bindir / "pg_ctl"), "-D", str(data), "-o", opts, "-l", str(root / "log"), "-w",
                                 "-t", "120", "start"]), check=True, capture_output=True, timeout=180)
    try:
        yield f"postgresql+psycopg://postgres@127.0.0.1:{port}"
    finally:
        subprocess.run(_as_postgres([str(bindir / "pg_ctl"), "-D", str(data), "-m", "immediate", "stop"]),
                       capture_output=True, timeout=120)
        shutil.rmtree(root, ignore_errors=True)


@pytest.fixture
def pg(server_url: str, request: pytest.FixtureRequest) -> str:
    """A database of its own for each test: instances resume every unfinished job of
    their database, so one test's jobs must not be another's."""
    import psycopg

    name = "t_" + "".join(ch if ch.isalnum() else "_" for ch in request.node.name)[:50].lower()
    with psycopg.connect(server_url.replace("postgresql+psycopg", "postgresql") + "/postgres", autocommit=True) as conn:
        conn.execute(f'DROP DATABASE IF EXISTS "{name}"')
        conn.execute(f'CREATE DATABASE "{name}"')
    return f"{server_url}/{name}"


def test_the_store_works_on_postgresql(pg: str) -> None:
    store = Store(pg)
    job = store.create_job({"x": 1}, [("a", rectangle(2.0, 1.0), None), ("b", rectangle(3.0, 1.0), None)], owner="key:1")
    assert store.owns_job(job, "key:1") and not store.owns_job(job, "key:2")
    ids = store.assign_run_ids(job, [0, 1], iter(["20261202T000000Z-0000000a", "20261202T000000Z-0000000b"]).__next__)
    assert store.assign_run_ids(job, [0], lambda: "other") == {0: ids[0]}  # kept: one run id per part
    run = {"run_id": ids[0], "command": "design", "part_name": "a", "action": "squeeze", "steps": 2, "agreement": None,
           "cycle_time_s": 1.5, "status": "ok", "error": None}
    store.finish_parts(job, [Outcome(0, "done", result={"ok": True}, run=run)], tried=[0])
    assert store.run(ids[0], "key:1") is not None and store.run(ids[0], "key:2") is None
    assert [(r["status"], r["attempts"]) for r in store.results(job)] == [("done", 1), ("pending", 0)]
    assert store.pending_count(job) == 1 and store.finished(job) == (1, 2)
    store.check()


def test_two_holders_never_hold_one_part(pg: str) -> None:
    store = Store(pg)
    job = store.create_job({}, [(f"p{i}", rectangle(2.0 + i, 1.0), None) for i in range(6)])
    a = store.claim(job, [0, 1, 2, 3], "instance-a", 60.0)
    b = store.claim(job, [2, 3, 4, 5], "instance-b", 60.0)
    assert a == [0, 1, 2, 3] and b == [4, 5]
    assert [i for i, *_ in store.claimable(job, "instance-b")] == [4, 5]
    assert store.claim(job, [0], "instance-a", -1.0) == [0]  # a's lease on 0 runs out (a died) …
    assert store.claim(job, [0, 1], "instance-b", 60.0) == [0]  # … and b takes it over, not 1


def test_two_service_instances_run_one_job_once(pg: str, tmp_path: Path) -> None:
    parts = [dict(rectangle(5.0 + 0.02 * i, 2.0), name=f"r{i}") for i in range(600)]
    dirs = [tmp_path / "a", tmp_path / "b"]
    for d in dirs:
        d.mkdir()
    a = start_server(dirs[0], ALGRASP_DATABASE_URL=pg, ALGRASP_BATCH_CHUNK="4")
    b = None
    try:
        with a.client() as c:
            job_id = c.post("/v1/jobs", json={"parts": parts}).json()["id"]
            b = start_server(dirs[1], ALGRASP_DATABASE_URL=pg, ALGRASP_BATCH_CHUNK="4")  # resumes the job: both run it
            job = wait_job(c, job_id, timeout_s=600)
            runs = c.get("/v1/runs", params={"limit": 1000}).json()["runs"]
    finally:
        a.kill()
        if b is not None:
            b.kill()
    rows = Store(pg).results(job_id)
    assert job["state"] == "done" and [r["status"] for r in rows] == ["done"] * len(parts)
    assert all(r["attempts"] == 1 for r in rows), [r for r in rows if r["attempts"] != 1][:3]  # no part done twice
    assert sorted(r["run_id"] for r in runs if r["job_id"] == job_id) == sorted(r["run_id"] for r in rows)
    recorded = [{p.stem for p in d.glob("*.mcap")} for d in dirs]
    assert not recorded[0] & recorded[1] and recorded[0] | recorded[1] == {r["run_id"] for r in rows}
    assert recorded[1], "the second instance took no part of the job"
