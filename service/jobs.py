"""Running batch jobs: dispatch a job's pending parts to the executor (local pool or
Dask — the same code), store each outcome as it arrives, resume unfinished jobs after a
restart, cancel on request.

Durability: the store is the truth. A part is dispatched only while ``pending`` and
stored once (``Store.finish_parts``: the outcomes that arrived together, in one
transaction), so a restart re-dispatches exactly the parts without a stored outcome:
nothing is lost, nothing finished is redone. A part keeps the run id it was first sent
with, so it has one record and one run row however often it is sent; on resume the
records an earlier process left under a pending part's id are removed. An attempt counts
only when a worker ended on the part (an outcome, or the worker died on it); a server
restart costs nothing, and a record-store or database fault pauses the job and retries.
Progress callbacks are throttled and count with one query, so a 10,000-part job is not
slowed by its own bookkeeping.
"""

from __future__ import annotations

import concurrent.futures as cf
import hashlib
import socket
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from sqlalchemy.exc import SQLAlchemyError

from algrasp.errors import AlgraspError, StorageError, UnavailableError
from algrasp.io.record.recorder import discard_partial, discard_record, new_run_id
from service.executor import Executor
from service.store import Outcome, Store
from service.work import design_chunk, design_task

STORE_RETRY_S = 5.0
"""A job whose database cannot be written waits this long before trying again."""
MAX_ATTEMPTS = 3
"""Dispatches of one part without an outcome before it is failed (not resumed forever)."""
LEASE_S = 30.0
"""A part sent by one service instance is held by it this long, renewed at every step
while it is in flight; an instance that dies lets its parts go to the others after it."""
REPORT_EVERY_S = 0.25
"""Progress callbacks are throttled to this interval (plus one when the job ends)."""
Item = tuple[int, dict[str, Any], str]  # (part index, part document, run id)
Progress = Callable[[str, int, int], None]  # (job_id, finished parts, total)


@dataclass(frozen=True)
class RunnerConfig:
    record_dir: str
    sim_workers: int
    part_time_limit_s: float
    window: int  # parts in flight at once (bounded, so ``attempts`` counts real dispatches)
    chunk: int = 1  # parts sent to a worker in one task
    holder: str = ""  # who holds parts in the store: this instance (stable across its restarts)

    def __post_init__(self) -> None:
        if not self.holder:  # one instance = one host and record directory
            key = f"{socket.gethostname()}:{Path(self.record_dir).resolve()}"
            object.__setattr__(self, "holder", hashlib.sha256(key.encode()).hexdigest()[:32])

    @classmethod
    def for_workers(cls, record_dir: str, sim_workers: int, part_time_limit_s: float, workers: int,
                    chunk: int) -> RunnerConfig:
        """Two chunks per worker in flight: each worker has its next chunk waiting."""
        return cls(record_dir, sim_workers, part_time_limit_s, 2 * workers * chunk, chunk)


class JobRunner:
    """Runs jobs in background threads (service) or in the caller's thread (CLI)."""

    def __init__(self, store: Store, executor: Executor, cfg: RunnerConfig, on_progress: Progress | None = None) -> None:
        self.store = store
        self.executor = executor
        self.cfg = cfg
        self.on_progress = on_progress
        self._cancel: dict[str, threading.Event] = {}
        self._threads: dict[str, threading.Thread] = {}
        self._stopping = threading.Event()
        self._reported_at: dict[str, float] = {}
        self._solo: set[tuple[str, int]] = set()  # parts of a lost chunk: sent alone from now on

    def start(self, job_id: str) -> None:
        """Run the job in a background thread."""
        self._cancel[job_id] = threading.Event()
        t = threading.Thread(target=self.run, args=(job_id,), name=f"job-{job_id[:8]}", daemon=True)
        self._threads[job_id] = t
        t.start()

    def resume_all(self) -> list[str]:
        """Start every unfinished job not running here: those a previous process left
        queued or running, and — called periodically — those another instance on the same
        database started (this one helps, and takes over if that one dies)."""
        jobs = [j for j in self.store.unfinished_jobs() if not (j in self._threads and self._threads[j].is_alive())]
        for job_id in jobs:
            if not self._stopping.is_set():
                self.start(job_id)
        return jobs

    def cancel(self, job_id: str) -> bool:
        """Cancel a queued or running job: pending parts become ``cancelled``."""
        if not self.store.set_state(job_id, "cancelled"):
            return False
        self.store.cancel_pending(job_id)
        self._cancel.setdefault(job_id, threading.Event()).set()
        return True

    def stop_all(self) -> None:
        """Shutdown: every job thread stops dispatching and drops its work in flight; the
        jobs stay ``running`` in the store and resume on the next start."""
        self._stopping.set()
        for t in list(self._threads.values()):
            t.join(timeout=5)

    def run(self, job_id: str) -> None:
        """Dispatch the pending parts, at most ``window`` at a time, and store outcomes;
        with other instances on the same database, only the parts this one holds."""
        job = self.store.job(job_id)
        if job is None or not self.store.set_state(job_id, "running"):
            return
        stop = self._cancel.setdefault(job_id, threading.Event())
        waiting = stop if stop.is_set() else self._stopping
        todo: list[tuple[int, dict[str, Any]]] = []
        inflight: dict[cf.Future[Any], list[Item]] = {}
        while not (stop.is_set() or self._stopping.is_set()):
            try:
                if not todo and not inflight:
                    todo = self._claimable(job_id)
                    if not todo:
                        if not self.store.pending_count(job_id):
                            break
                        waiting.wait(LEASE_S / 8)  # another instance holds the rest: take over if it dies
                        continue
                if self._step(job_id, job.options, todo, inflight):
                    print(f"algrasp: job {job_id[:8]}: run records cannot be written; retrying in {STORE_RETRY_S:g} s",
                          flush=True)
                    waiting.wait(STORE_RETRY_S)
            except SQLAlchemyError as exc:  # read-only or full database: outcomes wait in memory, retried
                print(f"algrasp: job {job_id[:8]}: the database cannot be written ({type(exc).__name__}); "
                      f"retrying in {STORE_RETRY_S:g} s", flush=True)
                waiting.wait(STORE_RETRY_S)
        for fut in inflight:
            fut.cancel()
        if not self._stopping.is_set():
            self.store.set_state(job_id, "done", only_if=("running",))
        self._report(job_id, final=True)

    def _claimable(self, job_id: str) -> list[tuple[int, dict[str, Any]]]:
        """Pending parts no other live instance holds, in dispatch order (reversed: popped
        from the end). Their records from an earlier holder (a dead process) are removed:
        they are recorded again under the same run ids."""
        rows = self.store.claimable(job_id, self.cfg.holder)
        for _, _, _, run_id in rows:
            if run_id:
                discard_record(Path(self.cfg.record_dir), run_id)
        return [(i, d) for i, d, a, _ in rows if not self._given_up(job_id, i, a)][::-1]

    def _step(self, job_id: str, options: dict[str, Any], todo: list[tuple[int, dict[str, Any]]],
              inflight: dict[cf.Future[Any], list[Item]]) -> bool:
        """Dispatch up to the window (in chunks), then store what finished. A finished part
        leaves ``inflight`` only once its outcome is stored, so a storage fault loses
        nothing. Returns whether a record-store fault asks the job to pause."""
        free = self.cfg.window - sum(len(g) for g in inflight.values())
        batch = todo[len(todo) - min(len(todo), max(free, 0)):][::-1]
        del todo[len(todo) - len(batch):]
        held = [idx for g in inflight.values() for idx, _, _ in g]
        run_ids = self.store.dispatch(job_id, [idx for idx, _ in batch], held, self.cfg.holder, LEASE_S, new_run_id)
        batch = [(idx, doc) for idx, doc in batch if idx in run_ids]  # the rest: another instance has them
        for group in self._chunks(job_id, batch, run_ids, left=len(batch) + len(todo)):
            inflight[self._submit(options, group)] = group
        done, _ = cf.wait(inflight, timeout=0.5, return_when=cf.FIRST_COMPLETED)
        step = _Step()
        for fut in done:
            self._collect(job_id, fut, inflight[fut], step)
        # One transaction for everything that finished since the last step, attempts included.
        self.store.finish_parts(job_id, step.outcomes, step.tried)
        for fut in done:
            del inflight[fut]
        todo.extend(step.retry)
        self._report(job_id)
        return step.paused

    def _chunks(self, job_id: str, batch: list[tuple[int, dict[str, Any]]], run_ids: dict[int, str],
                left: int | None = None) -> list[list[Item]]:
        """Chunks of at most ``cfg.chunk`` parts, each with its run id; parts of a lost chunk
        alone. ``left``: the parts still to send, these included (default: these)."""
        items = [(idx, doc, run_ids[idx]) for idx, doc in batch]
        alone = [[it] for it in items if (job_id, it[0]) in self._solo]
        rest = [it for it in items if (job_id, it[0]) not in self._solo]
        # The last parts of a job are spread over every worker, not sent as one chunk to one
        # of them; before that, full chunks (sized by what is left to send, not by the room
        # one finished chunk made in the window: that shrank every chunk to one part).
        spread = len(rest) if left is None else max(len(rest), left - len(alone))
        size = max(1, min(self.cfg.chunk, -(-spread // max(1, self.executor.capacity()))))
        return alone + [rest[i:i + size] for i in range(0, len(rest), size)]

    def _submit(self, options: dict[str, Any], group: list[Item]) -> cf.Future[Any]:
        cfg = self.cfg
        if len(group) == 1:
            _, doc, run_id = group[0]
            return self.executor.submit(design_task, doc, options, cfg.record_dir, cfg.sim_workers, run_id,
                                        timeout_s=cfg.part_time_limit_s, stage="part")
        return self.executor.submit(design_chunk, [(doc, run_id) for _, doc, run_id in group], options, cfg.record_dir,
                                    cfg.sim_workers, timeout_s=cfg.part_time_limit_s * len(group), stage="part")

    def _collect(self, job_id: str, fut: cf.Future[Any], group: list[Item], step: _Step) -> None:
        """The outcomes of a finished task into ``step``: parts to dispatch again go to
        ``retry``; a record-store fault retries the whole task, uncounted, after a pause;
        a task lost with its pool (``pool_lost``), uncounted at once."""
        exc = fut.exception()
        pool_lost = isinstance(exc, UnavailableError) and exc.reason == "pool_lost"
        if isinstance(exc, StorageError) or pool_lost:  # a full disk, a wedged pool: not the parts' fault
            for idx, doc, run_id in group:
                discard_partial(Path(self.cfg.record_dir), run_id)
                step.retry.append((idx, doc))
            step.paused = not pool_lost
            return
        if len(group) == 1:
            idx, doc, run_id = group[0]
            step.tried.append(idx)
            outcome = self._outcome(job_id, idx, fut, run_id)
            if outcome is None:
                step.retry.append((idx, doc))  # its worker died: another worker tries it
            else:
                step.outcomes.append(outcome)
            return
        if exc is not None:  # a chunk lost (worker died, time limit): each part alone, uncounted (whose fault?)
            for idx, doc, run_id in group:
                discard_partial(Path(self.cfg.record_dir), run_id)
                self._solo.add((job_id, idx))
                step.retry.append((idx, doc))
            return
        step.tried += [idx for idx, _, _ in group]
        step.outcomes.extend(_finished(idx, result) for (idx, _, _), result in zip(group, fut.result()))

    def _given_up(self, job_id: str, idx: int, attempts: int) -> bool:
        """A part on which workers died MAX_ATTEMPTS times fails, so the job cannot loop
        forever (a server that died meanwhile counted nothing)."""
        if attempts < MAX_ATTEMPTS:
            return False
        self.store.finish_parts(job_id, [_exhausted(idx, attempts)])
        return True

    def _outcome(self, job_id: str, idx: int, fut: cf.Future[Any], run_id: str) -> Outcome | None:
        """A finished part's outcome; None when it should be tried again (worker lost)."""
        try:
            result = fut.result()
        except AlgraspError as exc:  # worker lost, time limit, a request that cannot be sent
            discard_partial(Path(self.cfg.record_dir), run_id)
            lost = isinstance(exc, UnavailableError) and exc.reason == "worker_lost"
            if lost and self.store.attempts(job_id, idx) + 1 < MAX_ATTEMPTS:  # + 1: this one, counted with the step
                return None
            if lost:
                return _exhausted(idx, MAX_ATTEMPTS)
            return Outcome(idx, "failed", error=exc.to_dict())
        except Exception as exc:  # noqa: BLE001 - a crashed worker must not stop the job
            return Outcome(idx, "failed", error={"type": "internal_error", "message": repr(exc)})
        return _finished(idx, result)

    def _report(self, job_id: str, final: bool = False) -> None:
        """Progress to the callback, at most every REPORT_EVERY_S (counting costs a query)."""
        now = time.monotonic()
        if self.on_progress is None or (not final and now - self._reported_at.get(job_id, -REPORT_EVERY_S) < REPORT_EVERY_S):
            return
        self._reported_at[job_id] = now
        done, total = self.store.finished(job_id)
        self.on_progress(job_id, done, total)


@dataclass
class _Step:
    """What one dispatch step collected: outcomes to store, parts tried (one attempt
    each), parts to send again, and whether a record-store fault asks for a pause."""

    outcomes: list[Outcome] = field(default_factory=list)
    tried: list[int] = field(default_factory=list)
    retry: list[tuple[int, dict[str, Any]]] = field(default_factory=list)
    paused: bool = False


def _exhausted(idx: int, attempts: int) -> Outcome:
    """The outcome of a part on which workers died ``attempts`` times."""
    return Outcome(idx, "failed", error=UnavailableError(
        "worker_lost", f"no outcome after {attempts} attempts: the worker died on the part each time "
        "(a part that crashes its worker?)").to_dict())


def _finished(idx: int, result: Any) -> Outcome:
    """The outcome of a part whose design task returned ``(response, run, error)``."""
    response, run, err = result
    if err is not None:
        return Outcome(idx, "failed", error=err.to_dict(), run=run)
    return Outcome(idx, "done", result=response, run=run)
