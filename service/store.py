"""Durable store of runs, jobs and job parts (SQLAlchemy; SQLite by default).

Finishing a part is one conditional UPDATE (``… WHERE status = 'pending'``), so a part
finished twice — a resumed job racing a late result — is stored once; ``attempts``
counts dispatches that ended on a worker (an outcome, or the worker dying on the part):
a dispatch cut short by the server's own death costs the part nothing.
"""

from __future__ import annotations

import time
import uuid
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, cast

from sqlalchemy import (
    JSON,
    Float,
    ForeignKey,
    Index,
    Integer,
    String,
    Table,
    UniqueConstraint,
    bindparam,
    create_engine,
    delete,
    event,
    func,
    insert,
    select,
    update,
)
from sqlalchemy.engine import Connection
from sqlalchemy.orm import DeclarativeBase, Mapped, Session, mapped_column, sessionmaker

UNFINISHED = ("queued", "running")


class Base(DeclarativeBase):
    pass


class RunRow(Base):
    __tablename__ = "runs"
    run_id: Mapped[str] = mapped_column(String(64), primary_key=True)
    created_at: Mapped[float] = mapped_column(Float, index=True)
    command: Mapped[str] = mapped_column(String(32))
    part_name: Mapped[str | None] = mapped_column(String(256))
    action: Mapped[str | None] = mapped_column(String(32))
    steps: Mapped[int | None] = mapped_column(Integer)
    agreement: Mapped[float | None] = mapped_column(Float)
    cycle_time_s: Mapped[float | None] = mapped_column(Float)
    status: Mapped[str] = mapped_column(String(16))
    error: Mapped[dict[str, Any] | None] = mapped_column(JSON)
    job_id: Mapped[str | None] = mapped_column(String(32), index=True)
    owner: Mapped[str | None] = mapped_column(String(40), index=True)


class HealthRow(Base):
    __tablename__ = "health"
    id: Mapped[int] = mapped_column(Integer, primary_key=True)
    checked_at: Mapped[float] = mapped_column(Float)


class JobRow(Base):
    __tablename__ = "jobs"
    id: Mapped[str] = mapped_column(String(32), primary_key=True)
    created_at: Mapped[float] = mapped_column(Float)
    updated_at: Mapped[float] = mapped_column(Float)
    state: Mapped[str] = mapped_column(String(16), index=True)
    options: Mapped[dict[str, Any]] = mapped_column(JSON)
    total: Mapped[int] = mapped_column(Integer)
    catalogue_hash: Mapped[str | None] = mapped_column(String(64), index=True)
    owner: Mapped[str | None] = mapped_column(String(40), index=True)


class PartRow(Base):
    __tablename__ = "job_parts"
    # (job_id, status): progress counts read this index, not the rows (whose documents
    # and results lie before and after the status: SQLite would read their pages too).
    __table_args__ = (UniqueConstraint("job_id", "idx"), Index("ix_job_parts_job_status", "job_id", "status", "idx"))
    id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=True)
    job_id: Mapped[str] = mapped_column(ForeignKey("jobs.id"), index=True)
    idx: Mapped[int] = mapped_column(Integer)
    name: Mapped[str] = mapped_column(String(256))
    document: Mapped[dict[str, Any]] = mapped_column(JSON)
    status: Mapped[str] = mapped_column(String(16), default="pending")
    attempts: Mapped[int] = mapped_column(Integer, default=0)
    result: Mapped[dict[str, Any] | None] = mapped_column(JSON)
    error: Mapped[dict[str, Any] | None] = mapped_column(JSON)
    run_id: Mapped[str | None] = mapped_column(String(64))
    finished_at: Mapped[float | None] = mapped_column(Float)
    claimed_by: Mapped[str | None] = mapped_column(String(32))
    claimed_until: Mapped[float | None] = mapped_column(Float)


@dataclass(frozen=True)
class Outcome:
    """A batch part's outcome: status "done" (``result``) or "failed" (``error``), and
    the run row that recorded it (None when no run was recorded)."""

    idx: int
    status: str
    result: dict[str, Any] | None = None
    error: dict[str, Any] | None = None
    run: dict[str, Any] | None = None

    @property
    def run_id(self) -> str | None:
        return None if self.run is None else str(self.run["run_id"])


class Store:
    """All database access of the service and the batch runner. Thread-safe: one short
    session per call."""

    def __init__(self, url: str, busy_timeout_s: float = 2.0) -> None:
        sqlite = url.startswith("sqlite")
        # A short busy timeout: a write-locked database is a fast 503 (and a paused job),
        # not a request held 30 s. WAL (below) keeps readers from blocking the writer.
        args = {"check_same_thread": False, "timeout": busy_timeout_s} if sqlite else {}
        self.engine = create_engine(url, connect_args=args)
        if sqlite:
            event.listen(self.engine, "connect", _sqlite_pragmas)
        Base.metadata.create_all(self.engine)
        _add_missing_columns(self.engine)
        self._session = sessionmaker(self.engine, expire_on_commit=False)

    # ------------------------------------------------------------------ runs
    def add_runs(self, runs: list[dict[str, Any]], job_id: str | None = None) -> None:
        """Several run rows in one transaction (all or none)."""
        with self._session.begin() as s:
            for run in runs:
                s.merge(_run_row(job_id, run))

    def unknown_runs(self, run_ids: list[str]) -> tuple[set[str], set[str]]:
        """Of ``run_ids``: those with no run row, and among them those a pending job part
        holds (a part that will record again under its id)."""
        with self._session() as s:
            known = set(s.scalars(select(RunRow.run_id).where(RunRow.run_id.in_(run_ids))))
            held = set(s.scalars(select(PartRow.run_id).where(PartRow.run_id.in_(run_ids), PartRow.status == "pending")))
        unknown = set(run_ids) - known
        return unknown, unknown & held

    def delete_runs(self, run_ids: list[str]) -> None:
        """Forget runs whose records retention deleted."""
        with self._session.begin() as s:
            s.execute(delete(RunRow).where(RunRow.run_id.in_(run_ids)))

    def check(self) -> None:
        """A write and a read (readiness): raises SQLAlchemyError when the database cannot
        take writes (read-only, full, gone)."""
        with self._session.begin() as s:
            s.merge(HealthRow(id=1, checked_at=time.time()))

    def runs(self, limit: int, offset: int, owner: str | None = None) -> tuple[int, list[dict[str, Any]]]:
        """A page of runs, newest first (``owner``: only that owner's; None: all)."""
        mine = [] if owner is None else [RunRow.owner == owner]
        with self._session() as s:
            total = s.scalar(select(func.count()).select_from(RunRow).where(*mine)) or 0
            rows = s.scalars(select(RunRow).where(*mine).order_by(RunRow.created_at.desc()).limit(limit).offset(offset)).all()
            return total, [_run_dict(r) for r in rows]

    def run(self, run_id: str, owner: str | None = None) -> dict[str, Any] | None:
        """One run (None when unknown or, with ``owner``, someone else's)."""
        with self._session() as s:
            r = s.get(RunRow, run_id)
            return None if r is None or (owner is not None and r.owner != owner) else _run_dict(r)

    # ------------------------------------------------------------------ jobs
    def create_job(self, options: dict[str, Any], parts: list[tuple[str, dict[str, Any], dict[str, Any] | None]],
                   catalogue_hash: str | None = None, owner: str | None = None) -> str:
        """A queued job; a part given with an error (a file that could not be read) is
        stored as failed at once."""
        job_id = uuid.uuid4().hex
        now = time.time()
        with self._session.begin() as s:
            s.add(JobRow(id=job_id, created_at=now, updated_at=now, state="queued", options=options, total=len(parts),
                         catalogue_hash=catalogue_hash, owner=owner))
            s.add_all(PartRow(job_id=job_id, idx=i, name=n[:256], document=d, status="failed" if e else "pending", attempts=0,
                              error=e, finished_at=now if e else None) for i, (n, d, e) in enumerate(parts))
        return job_id

    def find_job(self, catalogue_hash: str) -> str | None:
        """The newest job made from the same catalogue and options (the batch CLI resumes it)."""
        with self._session() as s:
            return s.scalar(select(JobRow.id).where(JobRow.catalogue_hash == catalogue_hash).order_by(JobRow.created_at.desc()))

    def job(self, job_id: str) -> JobRow | None:
        with self._session() as s:
            return s.get(JobRow, job_id)

    def owns_job(self, job_id: str, owner: str | None) -> bool:
        """Whether the job exists and ``owner`` may see it (None: anyone)."""
        job = self.job(job_id)
        return job is not None and (owner is None or job.owner == owner)

    def set_state(self, job_id: str, state: str, only_if: tuple[str, ...] = UNFINISHED) -> bool:
        with self._session.begin() as s:
            res = s.execute(update(JobRow).where(JobRow.id == job_id, JobRow.state.in_(only_if))
                            .values(state=state, updated_at=time.time()))
            return bool(res.rowcount)  # type: ignore[attr-defined]

    def unfinished_jobs(self) -> list[str]:
        with self._session() as s:
            return list(s.scalars(select(JobRow.id).where(JobRow.state.in_(UNFINISHED)).order_by(JobRow.created_at)))

    def attempts(self, job_id: str, idx: int) -> int:
        with self._session() as s:
            return int(s.scalar(select(PartRow.attempts).where(PartRow.job_id == job_id, PartRow.idx == idx)) or 0)

    def claim(self, job_id: str, idxs: list[int], holder: str, lease_s: float) -> list[int]:
        """Of ``idxs``, the pending parts ``holder`` may now send: those nobody holds, or
        whose holder's lease ran out (a dead service instance), or its own — held for
        ``lease_s`` more. One conditional UPDATE: two instances on one database never hold
        one part at once (on PostgreSQL the second UPDATE waits for the first and re-reads)."""
        if not idxs:
            return []
        with self.engine.begin() as conn:
            return self._claim(conn, job_id, idxs, holder, lease_s)

    def _claim(self, conn: Connection, job_id: str, idxs: list[int], holder: str, lease_s: float) -> list[int]:
        now = time.time()
        args = {"b_job": job_id, "b_idxs": idxs, "b_holder": holder, "b_now": now, "b_until": now + lease_s}
        if self.engine.dialect.update_returning:  # the parts it holds now: those the UPDATE touched
            return sorted(int(i) for i in conn.execute(_CLAIM.returning(_PARTS.c.idx), args).scalars())
        conn.execute(_CLAIM, args)
        return sorted(int(i) for i in conn.execute(_HELD, args).scalars())

    def dispatch(self, job_id: str, idxs: list[int], held: list[int], holder: str, lease_s: float,
                 make: Callable[[], str]) -> dict[int, str]:
        """:meth:`claim` of ``idxs`` (parts to send) and ``held`` (parts in flight: their
        lease renewed), then :meth:`assign_run_ids` of the claimed ``idxs``, in one
        transaction. Returns the run id of each part of ``idxs`` that may be sent."""
        if not idxs and not held:
            return {}
        with self.engine.begin() as conn:
            claimed = set(self._claim(conn, job_id, idxs + held, holder, lease_s))
            return _assign(conn, job_id, [i for i in idxs if i in claimed], make)

    def claimable(self, job_id: str, holder: str) -> list[tuple[int, dict[str, Any], int, str | None]]:
        """``(index, document, attempts so far, run id given at an earlier dispatch)`` of
        each pending part that no other live holder holds."""
        now = time.time()
        with self._session() as s:
            free = (PartRow.claimed_by.is_(None)) | (PartRow.claimed_by == holder) | (PartRow.claimed_until < now)
            rows = s.execute(select(PartRow.idx, PartRow.document, PartRow.attempts, PartRow.run_id)
                             .where(PartRow.job_id == job_id, PartRow.status == "pending", free).order_by(PartRow.idx))
            return [(int(i), dict(d), int(a), r) for i, d, a, r in rows]

    def pending_count(self, job_id: str) -> int:
        with self._session() as s:
            return int(s.scalar(select(func.count()).select_from(PartRow)
                                .where(PartRow.job_id == job_id, PartRow.status == "pending")) or 0)

    def assign_run_ids(self, job_id: str, idxs: list[int], make: Callable[[], str]) -> dict[int, str]:
        """The run id of each part: the one given at an earlier dispatch, else a new one
        (``make()``), stored before the part is sent. So a part dispatched again — after a
        lost worker or a server restart — records under one id: one record, one run row."""
        if not idxs:
            return {}
        with self.engine.begin() as conn:
            return _assign(conn, job_id, idxs, make)

    def finish_parts(self, job_id: str, outcomes: list[Outcome], tried: Sequence[int] = ()) -> None:
        """Several parts' outcomes and their runs in one transaction (all or none), with
        one more attempt counted for each index in ``tried``; a part no longer pending
        keeps its stored outcome."""
        if not outcomes and not tried:
            return
        now = time.time()
        with self.engine.begin() as conn:
            _count(conn, job_id, list(tried))
            owner = conn.execute(_OWNER, {"b_job": job_id}).scalar()
            _put_runs(conn, [{"job_id": job_id, "created_at": time.time(), **o.run, "owner": owner}
                             for o in outcomes if o.run is not None])
            if outcomes:
                conn.execute(_FINISH, [{"b_job": job_id, "b_idx": o.idx, "b_status": o.status, "b_result": o.result,
                                        "b_error": o.error, "b_run": o.run_id, "b_at": now} for o in outcomes])

    def cancel_pending(self, job_id: str) -> int:
        with self._session.begin() as s:
            res = s.execute(update(PartRow).where(PartRow.job_id == job_id, PartRow.status == "pending")
                            .values(status="cancelled", finished_at=time.time()))
            return int(res.rowcount)  # type: ignore[attr-defined]

    def progress(self, job_id: str) -> dict[str, Any] | None:
        """``{"id", "state", "total", "done", "failed", "cancelled", "pending", "parts": [..]}``."""
        with self._session() as s:
            job = s.get(JobRow, job_id)
            if job is None:
                return None
            rows = s.execute(select(PartRow.idx, PartRow.name, PartRow.status, PartRow.attempts, PartRow.error, PartRow.run_id)
                             .where(PartRow.job_id == job_id).order_by(PartRow.idx)).all()
        parts = [{"index": i, "name": n, "status": st, "attempts": a, "error": e, "run_id": r} for i, n, st, a, e, r in rows]
        counts = {k: sum(p["status"] == k for p in parts) for k in ("done", "failed", "cancelled", "pending")}
        return {"id": job.id, "state": job.state, "total": job.total, **counts, "options": job.options,
                "created_at": job.created_at, "updated_at": job.updated_at, "parts": parts}

    def finished(self, job_id: str) -> tuple[int, int]:
        """(parts no longer pending, all parts) of a job: one counting query, for progress
        bars (``progress`` reads every part)."""
        with self._session() as s:  # grouped by status itself: PostgreSQL refuses a bound parameter in GROUP BY
            rows = dict(s.execute(select(PartRow.status, func.count()).where(PartRow.job_id == job_id)
                                  .group_by(PartRow.status)).all())
        total = sum(int(n) for n in rows.values())
        return total - int(rows.get("pending", 0)), total

    def counts(self) -> dict[str, dict[str, int]]:
        """Jobs by state and parts by status (for /metrics)."""
        with self._session() as s:
            jobs = dict(s.execute(select(JobRow.state, func.count()).group_by(JobRow.state)).all())
            parts = dict(s.execute(select(PartRow.status, func.count()).group_by(PartRow.status)).all())
        return {"jobs": {k: int(v) for k, v in jobs.items()}, "parts": {k: int(v) for k, v in parts.items()}}

    def jobs(self, limit: int, offset: int, owner: str | None = None) -> list[dict[str, Any]]:
        """A page of jobs, newest first (``owner``: only that owner's; None: all)."""
        mine = [] if owner is None else [JobRow.owner == owner]
        with self._session() as s:
            rows = s.scalars(select(JobRow).where(*mine).order_by(JobRow.created_at.desc()).limit(limit).offset(offset)).all()
            return [{"id": j.id, "state": j.state, "total": j.total, "created_at": j.created_at} for j in rows]

    def results(self, job_id: str) -> list[dict[str, Any]]:
        with self._session() as s:
            rows = s.scalars(select(PartRow).where(PartRow.job_id == job_id).order_by(PartRow.idx)).all()
            return [{"index": r.idx, "name": r.name, "status": r.status, "run_id": r.run_id, "attempts": r.attempts,
                     "result": r.result, "error": r.error} for r in rows]


_NO_SYNC = {"synchronize_session": False}
"""For ORM updates in a session that has loaded no row they touch: nothing to synchronise
(the default evaluates the criteria in Python for every update)."""
_PARTS, _RUNS = cast(Table, PartRow.__table__), cast(Table, RunRow.__table__)
_ONE_PART = (_PARTS.c.job_id == bindparam("b_job")) & (_PARTS.c.idx == bindparam("b_idx"))
_FINISH = update(_PARTS).where(_ONE_PART, _PARTS.c.status == "pending").values(
    status=bindparam("b_status"), result=bindparam("b_result", type_=_PARTS.c.result.type),
    error=bindparam("b_error", type_=_PARTS.c.error.type), run_id=bindparam("b_run"), finished_at=bindparam("b_at"))
"""A finished part's outcome, one executemany for the outcomes that arrived together
(a Core statement: the ORM's per-row update and session synchronisation cost the batch
process ~5 ms a part)."""
_SET_RUN_ID = update(_PARTS).where(_ONE_PART).values(run_id=bindparam("b_run"))
_SOME_PARTS = (_PARTS.c.job_id == bindparam("b_job")) & _PARTS.c.idx.in_(bindparam("b_idxs", expanding=True))
_FREE = (_PARTS.c.claimed_by.is_(None) | (_PARTS.c.claimed_by == bindparam("b_holder"))
         | (_PARTS.c.claimed_until < bindparam("b_now")))
_CLAIM = update(_PARTS).where(_SOME_PARTS, _PARTS.c.status == "pending", _FREE).values(
    claimed_by=bindparam("b_holder"), claimed_until=bindparam("b_until"))
_HELD = select(_PARTS.c.idx).where(_SOME_PARTS, _PARTS.c.status == "pending", _PARTS.c.claimed_by == bindparam("b_holder"))
_RUN_IDS = select(_PARTS.c.idx, _PARTS.c.run_id).where(_SOME_PARTS)
_COUNT = update(_PARTS).where(_SOME_PARTS).values(attempts=_PARTS.c.attempts + 1)
_OWNER = select(JobRow.__table__.c.owner).where(JobRow.__table__.c.id == bindparam("b_job"))
_KNOWN_RUNS = select(_RUNS.c.run_id).where(_RUNS.c.run_id.in_(bindparam("b_runs", expanding=True)))
"""The statements of a dispatch step, built once (building a statement cost the batch
process more than running it)."""


def _assign(conn: Connection, job_id: str, idxs: list[int], make: Callable[[], str]) -> dict[int, str]:
    """:meth:`Store.assign_run_ids` in the transaction of ``conn``."""
    if not idxs:
        return {}
    have = dict(conn.execute(_RUN_IDS, {"b_job": job_id, "b_idxs": idxs}).all())
    out = {i: have.get(i) or make() for i in idxs}
    fresh = [{"b_job": job_id, "b_idx": i, "b_run": out[i]} for i in idxs if not have.get(i)]
    if fresh:
        conn.execute(_SET_RUN_ID, fresh)
    return out


def _put_runs(s: Connection | Session, rows: list[dict[str, Any]]) -> None:
    """Insert run rows, or overwrite every given column of those already stored (a part
    dispatched again records under its run id): what ``Session.merge`` did row by row,
    in one query and at most two executemanys."""
    if not rows:
        return
    have = set(s.execute(_KNOWN_RUNS, {"b_runs": [r["run_id"] for r in rows]}).scalars())
    new = [r for r in rows if r["run_id"] not in have]
    if new:
        s.execute(insert(_RUNS), new)
    for r in (r for r in rows if r["run_id"] in have):
        s.execute(update(_RUNS).where(_RUNS.c.run_id == r["run_id"]).values(**r))


def _count(s: Connection | Session, job_id: str, idxs: list[int]) -> None:
    """One more attempt for each part of ``idxs``."""
    if idxs:
        s.execute(_COUNT, {"b_job": job_id, "b_idxs": idxs})


def _run_dict(r: RunRow) -> dict[str, Any]:
    return {"run_id": r.run_id, "created_at": r.created_at, "command": r.command, "part_name": r.part_name,
            "action": r.action, "steps": r.steps, "agreement": r.agreement, "cycle_time_s": r.cycle_time_s,
            "status": r.status, "error": r.error, "job_id": r.job_id}


def _run_row(job_id: str | None, run: dict[str, Any]) -> RunRow:
    """The index row of a recorded run (``job_id`` None: not part of a job)."""
    return RunRow(job_id=job_id, created_at=time.time(), **run)


def _add_missing_columns(engine: Any) -> None:
    """Columns and indexes added since a database was created (``owner``), added in place:
    a store made by an older version opens, its rows owned by no key (admin keys see them)."""
    from sqlalchemy import inspect, text

    added = {"runs": {"owner": "VARCHAR(40)"}, "jobs": {"owner": "VARCHAR(40)"},
             "job_parts": {"claimed_by": "VARCHAR(32)", "claimed_until": "FLOAT"}}
    have = {t: {c["name"] for c in inspect(engine).get_columns(t)} for t in added}
    with engine.begin() as conn:
        for table, columns in added.items():
            for name, kind in columns.items():
                if name not in have[table]:
                    conn.execute(text(f"ALTER TABLE {table} ADD COLUMN {name} {kind}"))
        for index in _PARTS.indexes:  # indexes added since (create_all makes only missing tables)
            index.create(conn, checkfirst=True)


def _sqlite_pragmas(conn: Any, _record: Any) -> None:
    # WAL: readers (GET /v1/jobs) do not block the job runner's writes.
    cur = conn.cursor()
    cur.execute("PRAGMA journal_mode=WAL")
    cur.execute("PRAGMA synchronous=NORMAL")
    cur.close()


def cause(exc: BaseException) -> BaseException:
    """The driver's exception behind a SQLAlchemy error (what to tell the user)."""
    orig = getattr(exc, "orig", None)
    return orig if isinstance(orig, BaseException) else exc
