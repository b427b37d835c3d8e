"""Store.finish_parts and assign_run_ids (one executemany each) leave the database as
the previous row-by-row ORM code did (written here): part outcomes, attempts, run ids and
run rows, including a part finished twice (kept) and a run written again (overwritten)."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

from sqlalchemy import select, update

from service.store import JobRow, Outcome, PartRow, RunRow, Store, _count, _run_row


def _finish_orm(store: Store, job_id: str, outcomes: list[Outcome], tried: list[int] = []) -> None:  # noqa: B006
    """The previous finish_parts: a merge per run and an ORM update per part."""
    now = time.time()
    with store._session.begin() as s:
        _count(s, job_id, list(tried))
        owner = s.scalar(select(JobRow.owner).where(JobRow.id == job_id))
        for o in outcomes:
            if o.run is not None:
                s.merge(_run_row(job_id, {**o.run, "owner": owner}))
            s.execute(update(PartRow).where(PartRow.job_id == job_id, PartRow.idx == o.idx, PartRow.status == "pending")
                      .values(status=o.status, result=o.result, error=o.error, run_id=o.run_id, finished_at=now))


def _assign_orm(store: Store, job_id: str, idxs: list[int], make: Any) -> dict[int, str]:
    with store._session.begin() as s:
        have = dict(s.execute(select(PartRow.idx, PartRow.run_id).where(PartRow.job_id == job_id, PartRow.idx.in_(idxs))).all())
        out = {i: have.get(i) or make() for i in idxs}
        for i in idxs:
            if not have.get(i):
                s.execute(update(PartRow).where(PartRow.job_id == job_id, PartRow.idx == i).values(run_id=out[i]))
        return out


def _run(i: int, status: str = "ok", steps: int | None = 3) -> dict[str, Any]:
    return {"run_id": f"run-{i}", "command": "design", "part_name": f"p{i}", "action": "squeeze", "steps": steps,
            "agreement": None, "cycle_time_s": 1.5, "status": status, "error": None if status == "ok" else {"type": "x"}}


def _state(store: Store, job_id: str) -> tuple[list[Any], list[Any]]:
    with store._session() as s:
        parts = s.execute(select(PartRow.idx, PartRow.status, PartRow.attempts, PartRow.result, PartRow.error, PartRow.run_id)
                          .where(PartRow.job_id == job_id).order_by(PartRow.idx)).all()
        runs = s.execute(select(RunRow.run_id, RunRow.command, RunRow.part_name, RunRow.action, RunRow.steps, RunRow.status,
                                RunRow.error, RunRow.job_id == job_id, RunRow.owner, RunRow.cycle_time_s)
                         .order_by(RunRow.run_id)).all()
    return [tuple(p) for p in parts], [tuple(r) for r in runs]


def test_finish_parts_equals_the_row_by_row_orm(tmp_path: Path) -> None:
    results = {}
    for name in ("fast", "orm"):
        store = Store(f"sqlite:///{tmp_path / name}.db")
        job = store.create_job({}, [(f"p{i}", {"i": i}, None) for i in range(6)], owner="key-a")
        ids = iter(f"id-{k}" for k in range(100))
        assign = store.assign_run_ids if name == "fast" else (lambda j, x, m, st=store: _assign_orm(st, j, x, m))
        finish = store.finish_parts if name == "fast" else (lambda j, o, tried=(), st=store: _finish_orm(st, j, o, list(tried)))
        got = [assign(job, [0, 1, 2], ids.__next__), assign(job, [1, 2, 3], ids.__next__)]
        finish(job, [Outcome(0, "done", result={"ok": 0}, run=_run(0)), Outcome(1, "failed", error={"type": "e"},
                                                                                    run=_run(1, "error", None))], [0, 1, 4])
        finish(job, [Outcome(0, "failed", error={"late": True}, run=_run(0, "error", 9)),  # no longer pending: kept
                     Outcome(2, "done", result={"ok": 2})], [2])
        finish(job, [], [3])
        results[name] = (got, _state(store, job))
    assert results["fast"] == results["orm"]
    parts, runs = results["fast"][1]
    assert parts[0][1:4] == ("done", 1, {"ok": 0}) and parts[4][2] == 1 and parts[3][2] == 1
    assert runs[0][0] == "run-0" and runs[0][4] == 9 and runs[0][8] == "key-a"  # the run written again is overwritten
