"""What pebble's process pool can leave pending when a worker dies at a bad moment, found
and settled, so that no caller (a request, a batch job) waits forever on a lost task.

Two faults of pebble 5.2.3 (the pinned release), both seen here when a worker was killed
between two short tasks (the 100-fault durability test, once parts took ~1 ms):

- **A wedged pool** (pebble issue #163). A worker takes its next task and acknowledges it
  holding the channel's process-shared locks; killed in between, it never releases them.
  The pool stays "running", its replacement worker waits on the locks for ever, and every
  task queued on it stays pending. Seen as: the locks cannot be taken for
  :data:`WEDGED_S`, while tasks are pending.
- **Orphans of a broken pool.** A pool whose manager gave up ("all workers expired")
  fails the tasks it had registered, but not one its scheduler was still handing over.

Either way the pool's unsettled tasks fail as ``pool_lost`` (503: send again; a batch
job sends them again without counting an attempt, as no part was at fault) and a new
pool takes the next task. Checked every
:data:`WATCH_S` from one daemon thread per executor, only while tasks are outstanding.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import threading
from collections.abc import Callable
from typing import Any

from algrasp.errors import UnavailableError

WATCH_S = 0.5
"""How often a pool with outstanding tasks is checked."""
WEDGED_S = 3.0
"""How long the channel locks must stay taken before the pool counts as wedged. A live
worker holds them for one hand-over (microseconds) or one result's write, which the
pool's own reader drains at once."""


def channel_taken(pool: Any) -> bool:
    """Whether pebble's worker-channel locks are held by someone now (a non-blocking
    try, as pebble's own ``maybe_stop_worker`` does). False for a pool not started yet,
    or a pebble without these internals (then only broken pools are caught)."""
    manager = getattr(pool, "_pool_manager", None)
    channel = getattr(getattr(manager, "worker_manager", None), "workers_channel", None)
    if channel is None:
        return False
    with channel.lock(block=False) as locked:
        return not locked


class PoolWatch:
    """The tasks outstanding on each pool of one executor, and the thread that settles
    them when their pool is broken or wedged. ``replace(pool)`` swaps in a new pool if
    ``pool`` is still the executor's current one, and discards ``pool`` (:func:`discard`);
    ``current()`` returns the current one."""

    def __init__(self, current: Callable[[], Any], replace: Callable[[Any], None]) -> None:
        self._current, self._replace = current, replace
        self._lock = threading.Lock()
        self._tasks: dict[cf.Future[Any], Any] = {}
        self._taken_for = 0.0
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    def track(self, out: cf.Future[Any], pool: Any) -> None:
        """``out`` runs on ``pool`` until it settles."""
        with self._lock:
            self._tasks[out] = pool
            if self._thread is None:
                self._thread = threading.Thread(target=self._run, name="pool-watch", daemon=True)
                self._thread.start()
        out.add_done_callback(self._forget)

    def stop(self) -> None:
        self._stop.set()

    def _forget(self, out: cf.Future[Any]) -> None:
        with self._lock:
            self._tasks.pop(out, None)

    def _run(self) -> None:
        while not self._stop.wait(WATCH_S):
            self.check()

    def check(self) -> None:
        """One look: replace each broken or wedged pool holding tasks, then fail its tasks
        (any thread; none once stopped: a pool the executor shuts down did not break)."""
        if self._stop.is_set():
            return
        with self._lock:
            pools = {id(p): p for p in self._tasks.values()}
        current = self._current()
        busy = any(p is current for p in pools.values())
        self._taken_for = self._taken_for + WATCH_S if busy and channel_taken(current) else 0.0
        for pool in pools.values():
            if pool is current and self._taken_for >= WEDGED_S:
                self._taken_for, why = 0.0, "a worker died handing it over and left the pool wedged"
            elif not pool.active:
                why = "its worker pool broke"
            else:
                continue
            self._replace(pool)  # first, so that the callers' retries go to the new pool
            self.settle(pool, why)

    def settle(self, pool: Any, why: str) -> int:
        """Fail ``pool``'s unsettled tasks as ``pool_lost``; returns how many."""
        with self._lock:
            lost = [out for out, p in self._tasks.items() if p is pool]
        settled = 0
        for out in lost:
            with contextlib.suppress(cf.InvalidStateError):
                out.set_exception(UnavailableError("pool_lost", f"the task was lost: {why}; the service goes on: "
                                                   "send the request again", 1.0))
                settled += 1
        if settled:
            print(f"algrasp: {settled} task(s) lost with their worker pool: {why}", flush=True)
        return settled


def discard(pool: Any) -> None:
    """Stop a replaced pool and kill its workers, in a daemon thread: a wedged pool's
    scheduler may never finish, so nothing waits on it."""
    def stop() -> None:
        with contextlib.suppress(Exception):  # noqa: BLE001 - a broken pool may fail any way while stopping
            pool.stop()
            pool.join()

    threading.Thread(target=stop, name="pool-discard", daemon=True).start()
