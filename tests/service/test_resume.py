"""Durability: kill the service (and its workers) mid-job, restart it, and the job
finishes with every part stored once and nothing finished before the kill redone."""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from pathlib import Path

import httpx
import pytest

from algrasp.testing.shapes import rectangle
from service.store import Store
from tests.service.conftest import paused, refuse_writes, start_server, wait_job

PARTS = 12
ROUND = 2  # parts that cannot be oriented: small run records, designed before the kill
GUARD_S = 120.0  # a hang guard on each wait, not a performance bound


def _round(i: int) -> dict[str, object]:
    """A regular 40-gon (and up): no plan orients it, so its run record is small."""
    n, r = 40 + i, 5.0 + i
    return {"name": f"round-{i}", "polygon": [[r * math.cos(2 * math.pi * k / n), r * math.sin(2 * math.pi * k / n)]
                                              for k in range(n)]}


def _record_sizes(c: httpx.Client, tmp_path: Path, parts: list[dict[str, object]]) -> list[int]:
    """The run-record sizes (bytes) of ``parts`` designed in a job of their own."""
    job_id = c.post("/v1/jobs", json={"parts": parts}).json()["id"]
    assert wait_job(c, job_id)["state"] == "done"
    rows = Store(f"sqlite:///{tmp_path / 'algrasp.db'}").results(job_id)
    return [(tmp_path / f"{r['run_id']}.mcap").stat().st_size for r in rows]


def _until(ready: Callable[[], bool], what: str) -> None:
    deadline = time.monotonic() + GUARD_S
    while not ready():
        assert time.monotonic() < deadline, what
        time.sleep(0.02)


def test_restart_resumes_without_losing_or_redoing(tmp_path: Path) -> None:
    """The kill lands mid-job by construction, not by timing: the job's worker may write no
    file past a size that the round parts' records fit and the rectangles' do not (a disk
    full for those), so the round parts finish and every rectangle waits."""
    parts = [_round(i) for i in range(ROUND)]
    parts += [dict(rectangle(10.0 + i, 3.0 + 0.1 * i), name=f"rect-{i}") for i in range(PARTS - ROUND)]
    server = start_server(tmp_path, ALGRASP_BATCH_CHUNK="1")
    try:
        with server.client() as c:
            small, big = _record_sizes(c, tmp_path, [_round(9), dict(rectangle(9.0, 2.0), name="probe")])
            assert 2 * small < big, (small, big)  # the limit below tells them apart
            refuse_writes(server, (small + big) // 2)  # on the job pool's worker, started by the probe
            job_id = c.post("/v1/jobs", json={"parts": parts}).json()["id"]
            store = Store(f"sqlite:///{tmp_path / 'algrasp.db'}")
            _until(lambda: paused(server) > 0 and sum(r["status"] == "done" for r in store.results(job_id)) >= ROUND,
                   "the round parts never finished, or the rectangles never met the limit")
    finally:
        server.kill()
    before = {r["index"]: r for r in store.results(job_id) if r["status"] == "done"}
    assert sorted(before) == list(range(ROUND)), "exactly the round parts were done before the kill"

    server = start_server(tmp_path)  # resumes unfinished jobs at start-up
    try:
        with server.client() as c:
            job = wait_job(c, job_id)
            runs = c.get("/v1/runs", params={"limit": 1000}).json()["runs"]
    finally:
        server.kill()
    after = store.results(job_id)
    assert job["state"] == "done" and [r["status"] for r in after] == ["done"] * PARTS
    for i, r in before.items():  # finished before the kill: same result, dispatched once
        assert after[i]["run_id"] == r["run_id"] and after[i]["result"] == r["result"] and after[i]["attempts"] == 1
    job_runs = [r["run_id"] for r in runs if r["job_id"] == job_id]
    assert sorted(job_runs) == sorted(r["run_id"] for r in after)  # one stored run per part: no duplicates
    assert [r["result"]["name"] for r in after] == [p["name"] for p in parts]


class _DyingExecutor:
    """Every task's worker dies (as a part that crashes its interpreter would make it)."""

    name = "dying"
    alive = True

    def capacity(self) -> int:
        return 1

    def submit(self, fn: object, *args: object, timeout_s: float, stage: str) -> object:
        import concurrent.futures as cf

        from algrasp.errors import UnavailableError

        fut: cf.Future[object] = cf.Future()
        fut.set_exception(UnavailableError("worker_lost", "the worker died"))
        return fut

    def shutdown(self) -> None:
        pass


def test_a_part_that_keeps_killing_workers_fails_and_is_not_resumed_forever(tmp_path: Path) -> None:
    from service.jobs import MAX_ATTEMPTS, JobRunner, RunnerConfig

    store = Store(f"sqlite:///{tmp_path / 'jobs.db'}")
    job_id = store.create_job({}, [("poison", rectangle(2.0, 1.0), None), ("also", rectangle(3.0, 1.0), None)])
    runner = JobRunner(store, _DyingExecutor(), RunnerConfig(str(tmp_path), 1, 10.0, 2))  # type: ignore[arg-type]
    runner.run(job_id)
    rows = store.results(job_id)
    assert [(r["status"], r["attempts"]) for r in rows] == [("failed", MAX_ATTEMPTS)] * 2
    assert all(r["error"]["reason"] == "worker_lost" for r in rows)
    assert store.job(job_id).state == "done"  # type: ignore[union-attr]
    # a job left "running" by a server that died on its parts' attempts is failed on resume
    job2 = store.create_job({}, [("p", rectangle(2.0, 1.0), None)])
    for _ in range(MAX_ATTEMPTS):
        store.finish_parts(job2, [], tried=[0])
    runner.run(job2)
    assert store.results(job2)[0]["status"] == "failed" and store.results(job2)[0]["attempts"] == MAX_ATTEMPTS


class _QuickExecutor(_DyingExecutor):
    """Every part designs at once (no worker)."""

    def submit(self, fn: object, *args: object, timeout_s: float, stage: str) -> object:
        import concurrent.futures as cf

        run_id = str(args[-1])
        run = {"run_id": run_id, "command": "design", "part_name": "p", "action": None, "steps": None, "agreement": None,
               "cycle_time_s": None, "status": "ok", "error": None}
        fut: cf.Future[object] = cf.Future()
        fut.set_result(({"orientable": True}, run, None))
        return fut


class _WedgingExecutor(_QuickExecutor):
    """The first ``lost`` tasks are lost with a wedged pool (``service.pool_watch``)."""

    def __init__(self, lost: int) -> None:
        self.lost = lost

    def submit(self, fn: object, *args: object, timeout_s: float, stage: str) -> object:
        import concurrent.futures as cf

        from algrasp.errors import UnavailableError

        if self.lost <= 0:
            return super().submit(fn, *args, timeout_s=timeout_s, stage=stage)
        self.lost -= 1
        fut: cf.Future[object] = cf.Future()
        fut.set_exception(UnavailableError("pool_lost", "the task was lost: the pool wedged"))
        return fut


def test_tasks_lost_with_a_wedged_pool_are_sent_again_uncounted(tmp_path: Path) -> None:
    from service.jobs import MAX_ATTEMPTS, JobRunner, RunnerConfig

    store = Store(f"sqlite:///{tmp_path / 'jobs.db'}")
    job_id = store.create_job({}, [(f"p{i}", rectangle(2.0 + i, 1.0), None) for i in range(2)])
    ex = _WedgingExecutor(lost=2 * MAX_ATTEMPTS)  # more losses than a part may have attempts
    JobRunner(store, ex, RunnerConfig(str(tmp_path), 1, 10.0, 2)).run(job_id)  # type: ignore[arg-type]
    rows = store.results(job_id)
    assert ex.lost == 0 and [(r["status"], r["attempts"]) for r in rows] == [("done", 1)] * 2


def test_a_read_only_database_pauses_a_job_and_loses_nothing(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from sqlalchemy.exc import OperationalError

    import service.jobs as jobs
    from service.jobs import JobRunner, RunnerConfig

    store = Store(f"sqlite:///{tmp_path / 'jobs.db'}")
    job_id = store.create_job({}, [(f"p{i}", rectangle(2.0 + i, 1.0), None) for i in range(3)])
    real, faults = Store.finish_parts, {"left": 4}

    def flaky(self: Store, *a: object, **k: object) -> None:
        if faults["left"] > 0:
            faults["left"] -= 1
            raise OperationalError("UPDATE", {}, Exception("attempt to write a readonly database"))
        return real(self, *a, **k)  # type: ignore[arg-type]

    monkeypatch.setattr(Store, "finish_parts", flaky)
    monkeypatch.setattr(jobs, "STORE_RETRY_S", 0.01)
    JobRunner(store, _QuickExecutor(), RunnerConfig(str(tmp_path), 1, 10.0, 2)).run(job_id)  # type: ignore[arg-type]
    rows = store.results(job_id)
    assert faults["left"] == 0 and [r["status"] for r in rows] == ["done"] * 3
    assert [r["attempts"] for r in rows] == [1, 1, 1]  # paused, not redone


class _PoisonChunkExecutor(_DyingExecutor):
    """Really runs the tasks in-process, except that any task holding the part named
    "poison" loses its worker (as a part that crashes the interpreter would)."""

    def __init__(self) -> None:
        self.chunks: list[int] = []

    def submit(self, fn: object, *args: object, timeout_s: float, stage: str) -> object:
        import concurrent.futures as cf

        from algrasp.errors import UnavailableError

        docs = [d for d, _ in args[0]] if isinstance(args[0], list) else [args[0]]  # type: ignore[index]
        self.chunks.append(len(docs))
        fut: cf.Future[object] = cf.Future()
        if any(d.get("name") == "poison" for d in docs):  # type: ignore[attr-defined]
            fut.set_exception(UnavailableError("worker_lost", "the worker died"))
        else:
            fut.set_result(fn(*args))  # type: ignore[operator]
        return fut


def test_a_lost_chunk_is_retried_part_by_part(tmp_path: Path) -> None:
    """Parts go to workers in chunks; when a chunk's worker dies, its parts are sent one
    by one, so only the part that kills workers fails and the others are designed."""
    from service.jobs import MAX_ATTEMPTS, JobRunner, RunnerConfig

    store = Store(f"sqlite:///{tmp_path / 'jobs.db'}")
    parts = [(f"p{i}", dict(rectangle(2.0 + i, 1.0), name=f"p{i}"), None) for i in range(5)]
    parts.insert(2, ("poison", dict(rectangle(9.0, 1.0), name="poison"), None))
    job_id = store.create_job({}, parts)
    ex = _PoisonChunkExecutor()
    JobRunner(store, ex, RunnerConfig.for_workers(str(tmp_path), 1, 10.0, 1, 3)).run(job_id)  # type: ignore[arg-type]
    rows = store.results(job_id)
    assert [r["status"] for r in rows] == ["done", "done", "failed", "done", "done", "done"]
    assert rows[2]["attempts"] == MAX_ATTEMPTS and rows[2]["error"]["reason"] == "worker_lost"
    # p0, p1 shared the poison's chunk: a lost chunk counts for none of its parts (whose fault was it?)
    assert [r["attempts"] for i, r in enumerate(rows) if i != 2] == [1, 1, 1, 1, 1]
    assert ex.chunks[:2] == [3, 3] and all(r["result"]["orientable"] for r in rows if r["status"] == "done")


def test_records_without_a_run_row_are_reconciled(tmp_path: Path) -> None:
    """Issue 31: requests that failed after their worker wrote the record left orphans.
    At start-up a readable orphan is indexed from its summary; a batch part's orphan that
    no pending part holds, and a damaged file, are removed."""
    from algrasp.io.record.session import recording
    from service.retention import reconcile_records

    store = Store(f"sqlite:///{tmp_path / 'jobs.db'}")
    doc = dict(rectangle(2.0, 1.0), name="orphan")
    with recording(True, tmp_path, "plan", doc, {"action": "squeeze"}) as plan_rec:
        pass
    with recording(True, tmp_path, "design", doc, {"design": {}}) as design_rec:
        pass
    (tmp_path / "20261202T000000Z-deadbeef.mcap").write_bytes(b"\x89MCAP0\r\n garbage")
    assert reconcile_records(tmp_path, store) == {"indexed": 1, "removed": 2}
    row = store.run(plan_rec.run_id)
    assert row is not None and row["command"] == "plan" and row["part_name"] == "orphan" and row["status"] == "ok"
    assert {p.stem for p in tmp_path.glob("*.mcap")} == {plan_rec.run_id}
    assert design_rec.run_id != plan_rec.run_id
    assert reconcile_records(tmp_path, store) == {"indexed": 0, "removed": 0}  # idempotent
