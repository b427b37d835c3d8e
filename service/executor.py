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
from collections.abc import Callable
from typing import Any, Protocol

from algrasp.errors import ConfigError, TimeLimitError


class Executor(Protocol):
    name: str

    def submit(self, fn: Callable[..., Any], *args: Any, timeout_s: float, stage: str) -> cf.Future[Any]: ...

    def shutdown(self) -> None: ...


def _warm() -> None:
    # The imports every task needs, once per worker (numpy/scipy/casadi ≈ 1 s cold).
    import algrasp.pipeline  # noqa: F401
    import optimisation.execution  # noqa: F401


class LocalExecutor:
    """``workers`` spawned processes (spawn: the parent may hold threads and sockets)."""

    name = "local"

    def __init__(self, workers: int) -> None:
        from pebble import ProcessPool

        self._pool = ProcessPool(max_workers=workers, initializer=_warm, context=multiprocessing.get_context("spawn"))

    def submit(self, fn: Callable[..., Any], *args: Any, timeout_s: float, stage: str) -> cf.Future[Any]:
        out: cf.Future[Any] = cf.Future()
        inner = self._pool.schedule(fn, args=args, timeout=timeout_s)
        inner.add_done_callback(lambda f: _settle(out, f, stage, timeout_s))
        out.add_done_callback(lambda f: inner.cancel() if f.cancelled() else None)
        return out

    def shutdown(self) -> None:
        self._pool.stop()
        self._pool.join(timeout=5)


class DaskExecutor:
    """Tasks on a Dask distributed cluster; the time limit is enforced by the caller's
    wait (a Dask worker cannot be interrupted, so a late task is cancelled instead)."""

    name = "dask"

    def __init__(self, address: str) -> None:
        try:
            from distributed import Client

            self._client = Client(address, timeout="10s", set_as_default=False)
        except (OSError, TimeoutError, ValueError) as exc:
            raise ConfigError("scheduler", f"cannot reach the Dask scheduler at {address!r}: {exc}") from None

    def submit(self, fn: Callable[..., Any], *args: Any, timeout_s: float, stage: str) -> cf.Future[Any]:
        import threading

        out: cf.Future[Any] = cf.Future()
        inner = self._client.submit(fn, *args, pure=False)
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
                _fail(out, exc)

        inner.add_done_callback(done)
        out.add_done_callback(lambda f: inner.cancel() if f.cancelled() else None)
        return out

    def shutdown(self) -> None:
        self._client.close()


def make_executor(scheduler: str, workers: int) -> Executor:
    """Dask when a scheduler address is configured, else the local pool."""
    return DaskExecutor(scheduler) if scheduler else LocalExecutor(workers)


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
        _fail(out, exc)
    else:
        _resolve(out, inner.result())


def _resolve(out: cf.Future[Any], value: Any) -> None:
    with contextlib.suppress(cf.InvalidStateError):  # cancelled meanwhile
        out.set_result(value)


def _fail(out: cf.Future[Any], exc: BaseException) -> None:
    with contextlib.suppress(cf.InvalidStateError):
        out.set_exception(exc)
