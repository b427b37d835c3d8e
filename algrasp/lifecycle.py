"""Worker process lifecycle: a worker never outlives the process that started it.

``kill -9`` of the service cannot run any clean-up, so each worker (the service's pools,
the Drake validation pool) watches its own parent: when the parent dies the worker is
re-parented (its parent pid changes) and exits within a second. No orphans are left.
"""

from __future__ import annotations

import os
import threading
import time

WATCH_PERIOD_S = 1.0
"""How often a worker checks that its parent is alive."""


def exit_with_parent(period_s: float = WATCH_PERIOD_S) -> None:
    """Start a daemon thread that ends this process when its parent dies."""
    parent = os.getppid()

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(period_s)
        os._exit(1)  # the parent is gone: nobody waits for our result

    threading.Thread(target=watch, name="parent-watch", daemon=True).start()
