"""Where work runs: a local pool of worker processes (default, no set-up) or a Dask
distributed cluster (``scheduler`` address). Both hand back ``concurrent.futures.Future``
objects, so the service and the batch runner have one code path.

The local pool is pebble's ``ProcessPool``: unlike the standard executor it kills a
worker whose task runs past its time limit, so a runaway request cannot hold a worker.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import multiprocessing
import pickle
import re
import threading
from collections.abc import Callable
from typing import Any, Protocol

from algrasp.errors import AlgraspError, ConfigError, PartDocumentError, TimeLimitError, UnavailableError


class Executor(Protocol):
    name: str

    @property
    def alive(self) -> bool: ...

    def capacity(self) -> int:
        """Tasks that can run at once (0: no worker to run anything)."""
        ...

    def submit(self, fn: Callable[..., Any], *args: Any, timeout_s: float, stage: str) -> cf.Future[Any]: ...

    def shutdown(self) -> None: ...


def _warm(niceness: int = 0) -> None:
    # Expensive work yields the CPU to cheap work (admission control's second half).
    if niceness:
        import os

        os.nice(niceness)
    # The imports every task needs, once per worker (numpy, the core, the optimiser).
    import optimisation.execution  # noqa: F401
    from algrasp.lifecycle import exit_with_parent
    from algrasp.pipeline import warm_up

    exit_with_parent()
    warm_up()  # the first request is then as fast as the next


def _call(payload: bytes) -> Any:
    """Run a pre-pickled ``(fn, args)`` in the worker."""
    fn, args = pickle.loads(payload)
    return fn(*args)


def pickled(fn: Callable[..., Any], args: tuple[Any, ...], out: cf.Future[Any]) -> bytes | None:
    """``(fn, args)`` pickled in the caller, so a task that cannot be sent fails alone
    (pickling inside the pool's scheduler thread would break the pool for good): None,
    with ``out`` failed, when it cannot be sent."""
    try:
        return pickle.dumps((fn, args), protocol=pickle.HIGHEST_PROTOCOL)
    except (pickle.PicklingError, RecursionError, TypeError, ValueError, AttributeError) as exc:
        _fail(out, PartDocumentError("body", f"the request cannot be sent to a worker ({type(exc).__name__})"))
        return None


class LocalExecutor:
    """``workers`` spawned processes (spawn: the parent may hold threads and sockets)."""

    name = "local"

    def __init__(self, workers: int, niceness: int = 0) -> None:
        from service.pool_watch import PoolWatch

        self.workers = workers
        self.niceness = niceness
        self._pool = self._new_pool()
        self._closed = False
        self._swap = threading.Lock()
        self.watch = PoolWatch(lambda: self._pool, self._replace)

    def _new_pool(self) -> Any:
        from pebble import ProcessPool

        return ProcessPool(max_workers=self.workers, initializer=_warm, initargs=(self.niceness,),
                           context=multiprocessing.get_context("spawn"))

    @property
    def alive(self) -> bool:
        return bool(self._pool.active)

    def capacity(self) -> int:
        return 0 if self._closed else self.workers

    def submit(self, fn: Callable[..., Any], *args: Any, timeout_s: float, stage: str) -> cf.Future[Any]:
        out: cf.Future[Any] = cf.Future()
        payload = pickled(fn, args, out)
        if payload is None:
            return out
        pool = self._pool
        if not pool.active:  # a broken pool is replaced, not kept
            pool = self._replace(pool)
        try:
            inner = pool.schedule(_call, args=(payload,), timeout=timeout_s)
        except RuntimeError:  # shutting down
            _fail(out, UnavailableError("shutting_down", "the service is shutting down", 5.0))
            return out
        self.watch.track(out, pool)  # pebble can lose a task when a worker dies at a bad moment
        inner.add_done_callback(lambda f: _settle(out, f, stage, timeout_s))
        out.add_done_callback(lambda f: inner.cancel() if f.cancelled() else None)
        return out

    def _replace(self, old: Any) -> Any:
        """A new pool in place of ``old`` (broken or wedged), unless another thread has
        replaced it already or the executor is closed; returns the current pool."""
        from service.pool_watch import discard

        with self._swap:
            if self._pool is old and not self._closed:
                self._pool = self._new_pool()
                discard(old)
            return self._pool

    def shutdown(self) -> None:
        """Stop at once: work in flight is cancelled and its workers are killed."""
        self._closed = True
        self.watch.stop()
        self._pool.stop()
        self._pool.join(timeout=5)


DASK_ADDRESS = re.compile(r"^(?:(?:tcp|tls|ws|wss|ucx)://)?(?:[A-Za-z0-9_.-]+|\[[0-9A-Fa-f:]+\]):[0-9]{1,5}$")
"""What a Dask scheduler address looks like (``tcp://host:8786``, ``host:8786``)."""
CONNECT_S = 10.0
"""How long to wait for the scheduler to answer."""


class DaskExecutor:
    """Tasks on a Dask distributed cluster; the time limit is enforced by the caller's
    wait (a Dask worker cannot be interrupted, so a late task is cancelled instead).
    ``wait_for_workers_s``: wait this long for a first worker, then refuse (the batch CLI);
    None: connect only (the service, whose readiness and job admission ask for workers)."""

    name = "dask"

    def __init__(self, address: str, wait_for_workers_s: float | None = None) -> None:
        if not DASK_ADDRESS.match(address) or not 0 < int(address.rsplit(":", 1)[1]) < 65536:
            raise ConfigError("scheduler", f"{address!r} is not a Dask scheduler address (tcp://host:port)")
        from distributed import Client

        try:
            self._client = Client(address, timeout=f"{CONNECT_S:g}s", set_as_default=False)
        except (OSError, TimeoutError, ValueError) as exc:
            raise UnavailableError("scheduler", f"cannot reach the Dask scheduler at {address!r} within "
                                   f"{CONNECT_S:g} s ({type(exc).__name__})", CONNECT_S) from None
        self.address = address
        if wait_for_workers_s is not None and not self.capacity():
            try:
                self._client.wait_for_workers(1, timeout=wait_for_workers_s)
            except (TimeoutError, OSError):
                self._client.close()
                raise UnavailableError("no_workers", f"the Dask scheduler at {address!r} has no workers (waited "
                                       f"{wait_for_workers_s:g} s): start some with `dask worker {address}`",
                                       wait_for_workers_s) from None

    def capacity(self) -> int:
        try:
            workers = self._client.scheduler_info().get("workers", {})
        except (OSError, TimeoutError, AttributeError):
            return 0
        return sum(int(w.get("nthreads", 1)) for w in workers.values())

    def submit(self, fn: Callable[..., Any], *args: Any, timeout_s: float, stage: str) -> cf.Future[Any]:
        import threading

        out: cf.Future[Any] = cf.Future()
        payload = pickled(fn, args, out)
        if payload is None:
            return out
        inner = self._client.submit(_call, payload, pure=False)
        def late() -> None:
            inner.cancel()
            _fail(out, TimeLimitError(stage, timeout_s))

        timer = threading.Timer(timeout_s, late)
        timer.daemon = True
        timer.start()

        def done(f: Any) -> None:
            timer.cancel()
            if out.done():
                return
            try:
                _resolve(out, f.result())
            except BaseException as exc:  # noqa: BLE001 - handed to the caller's future
                _fail(out, _as_error(exc, stage))

        inner.add_done_callback(done)
        out.add_done_callback(lambda f: inner.cancel() if f.cancelled() else None)
        return out

    @property
    def alive(self) -> bool:
        return self._client.status == "running"

    def shutdown(self) -> None:
        self._client.close()


def make_executor(scheduler: str, workers: int, niceness: int = 0, wait_for_workers_s: float | None = None) -> Executor:
    """Dask when a scheduler address is configured, else the local pool."""
    return DaskExecutor(scheduler, wait_for_workers_s) if scheduler else LocalExecutor(workers, niceness)


def _settle(out: cf.Future[Any], inner: cf.Future[Any], stage: str, timeout_s: float) -> None:
    if out.done():
        return
    if inner.cancelled():
        out.cancel()
        return
    exc = inner.exception()
    if isinstance(exc, cf.TimeoutError):
        _fail(out, TimeLimitError(stage, timeout_s))
    elif exc is not None:
        _fail(out, _as_error(exc, stage))
    else:
        _resolve(out, inner.result())


def _as_error(exc: BaseException, stage: str) -> BaseException:
    """What the caller sees of a task's exception: user errors as they are; a worker that
    died (killed, out of memory) is a 503 to retry; anything else stays an internal error
    but never a StopIteration, which cannot cross into asyncio (the await would hang)."""
    from concurrent.futures import BrokenExecutor

    from pebble import ProcessExpired

    if isinstance(exc, AlgraspError):
        return exc
    if isinstance(exc, ProcessExpired):
        return UnavailableError("worker_lost", f"the worker running this {stage} died (exit code {exc.exitcode}); "
                                "the service goes on: send the request again", 1.0)
    if type(exc).__name__ == "KilledWorker":  # Dask: the workers running the task died (after its own retries)
        return UnavailableError("worker_lost", f"the Dask workers running this {stage} died; the service goes on: "
                                "send the request again", 1.0)
    if isinstance(exc, BrokenExecutor):  # a process pool inside the task (Drake's) lost a worker
        return UnavailableError("worker_lost", f"a worker of this {stage} died; the service goes on: send the "
                                "request again", 1.0)
    if isinstance(exc, (StopIteration, StopAsyncIteration)):
        return RuntimeError(f"{type(exc).__name__} escaped the {stage} task")
    return exc


def _resolve(out: cf.Future[Any], value: Any) -> None:
    with contextlib.suppress(cf.InvalidStateError):  # cancelled meanwhile
        out.set_result(value)


def _fail(out: cf.Future[Any], exc: BaseException) -> None:
    with contextlib.suppress(cf.InvalidStateError):
        out.set_exception(exc)


def ping() -> int:
    """A task that proves a worker answers (readiness)."""
    import os

    return os.getpid()
