"""No task waits for ever on a pool a worker's death left wedged or broken (pebble issue
#163; seen in the 100-fault durability test): the tasks fail as 503 ``pool_lost`` and the
next task runs on a new pool."""

from __future__ import annotations

import concurrent.futures as cf
import os
from collections.abc import Iterator

import pytest

from algrasp.errors import UnavailableError
from service.executor import LocalExecutor, ping

GUARD_S = 120.0  # a hang guard on each wait, not a performance bound


def die_holding_the_channel() -> None:
    """Run in a pool worker: take pebble's worker-channel locks and die holding them, as
    a worker killed between taking a task and acknowledging it does."""
    import gc

    channel = next(o for o in gc.get_objects() if type(o).__name__ == "WorkerChannel")
    assert channel.mutex.acquire(block=True, timeout=GUARD_S)
    os._exit(9)


def _lost(fut: cf.Future[object]) -> UnavailableError:
    exc = fut.exception(timeout=GUARD_S)
    assert isinstance(exc, UnavailableError), exc
    return exc


@pytest.fixture
def executor() -> Iterator[LocalExecutor]:
    ex = LocalExecutor(1)
    yield ex
    ex.shutdown()


def test_a_worker_that_dies_holding_the_channel_wedges_nothing(executor: LocalExecutor) -> None:
    first = executor.submit(ping, timeout_s=GUARD_S, stage="ping").result(timeout=GUARD_S)
    wedged = executor._pool
    assert _lost(executor.submit(die_holding_the_channel, timeout_s=GUARD_S, stage="t")).reason == "worker_lost"
    # pebble starts a new worker, which waits on the dead one's locks: without the watch
    # this task would never run nor fail
    exc = _lost(executor.submit(ping, timeout_s=GUARD_S, stage="ping"))
    assert exc.reason == "pool_lost" and exc.http_status == 503 and "wedged" in exc.message
    assert executor._pool is not wedged
    again = executor.submit(ping, timeout_s=GUARD_S, stage="ping").result(timeout=GUARD_S)
    assert again != first  # a new worker of the new pool


def test_a_broken_pools_stranded_task_is_settled(executor: LocalExecutor) -> None:
    """A task the broken pool never registered (so pebble never fails it) is failed by
    the watch; here the pool breaks while the task waits behind taken locks."""
    from pebble.pool.base_pool import PoolStatus

    executor.submit(ping, timeout_s=GUARD_S, stage="ping").result(timeout=GUARD_S)
    pool = executor._pool
    channel = pool._pool_manager.worker_manager.workers_channel
    assert channel.mutex.acquire(block=True, timeout=GUARD_S)  # no worker can take the task
    try:
        fut = executor.submit(ping, timeout_s=GUARD_S, stage="ping")
        pool._context.status = PoolStatus.ERROR  # its manager gave up, as on "all workers expired"
        executor.watch.check()
        assert _lost(fut).reason == "pool_lost"  # ("wedged" instead, if the watch saw the locks first)
    finally:
        channel.mutex.release()
    assert executor.submit(ping, timeout_s=GUARD_S, stage="ping").result(timeout=GUARD_S) > 0
