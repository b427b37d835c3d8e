"""Run-record retention: records do not grow without bound.

At start-up every ``*.mcap.partial`` in the record directory is removed (no worker of a
previous process can still be writing it). Then, once a ``retention_period_s``, records
older than ``ALGRASP_RECORD_MAX_AGE`` are deleted, and the oldest go while the total
is over ``ALGRASP_RECORD_MAX_BYTES``; their run rows go with them (``/v1/runs/{id}``
answers 404). Jobs keep their results. Complexity: one directory listing per sweep.
"""

from __future__ import annotations

import asyncio
import contextlib
import time
from pathlib import Path
from typing import Any

from algrasp.io.record.recorder import PARTIAL_SUFFIX
from service.settings import Settings

ORPHAN_AGE_S = 300.0
"""A record without a run row is reconciled by the periodic sweep once this old (a run in
flight is indexed by its own request within seconds); at start-up, at any age."""


def clean_partials(log_dir: Path) -> int:
    """Remove every partial record (start-up only); returns how many."""
    n = 0
    for p in log_dir.glob(f"*{PARTIAL_SUFFIX}") if log_dir.is_dir() else ():
        with contextlib.suppress(OSError):
            p.unlink()
            n += 1
    return n


def sweep(log_dir: Path, max_age_s: float, max_bytes: float, now: float | None = None) -> list[str]:
    """Delete records past the age or total-size limit (0: no limit); returns their run ids."""
    now = time.time() if now is None else now
    files = []
    for p in log_dir.glob("*.mcap"):
        with contextlib.suppress(OSError):
            st = p.stat()
            files.append((st.st_mtime, st.st_size, p))
    files.sort()  # oldest first
    total = sum(size for _, size, _ in files)
    gone = []
    for mtime, size, p in files:
        too_old = max_age_s > 0 and now - mtime > max_age_s
        too_big = max_bytes > 0 and total > max_bytes
        if not (too_old or too_big):
            break
        with contextlib.suppress(OSError):
            p.unlink()
            gone.append(p.stem)
            total -= size
    return gone


def reconcile_records(log_dir: Path, store: Any, min_age_s: float = 0.0, now: float | None = None) -> dict[str, int]:
    """Records on disk without a run row (a request that failed or timed out after its
    worker wrote the record, a row that waited in memory when the server died): a readable
    run is indexed from its ``/run`` summary; a batch part's record is left to its job
    (resume records it again) if the part is pending, else removed, as is a damaged one.
    Only files older than ``min_age_s`` (runs in flight are indexed by their request).
    Returns ``{"indexed", "removed"}``. O(records) directory listing, O(orphans) reads."""
    from algrasp.errors import AlgraspError
    from algrasp.io.record.replay import summary

    now = time.time() if now is None else now
    files = {p.stem: p for p in log_dir.glob("*.mcap") if _age(p, now) >= min_age_s}
    out = {"indexed": 0, "removed": 0}
    for start in range(0, len(files), 500):
        ids = sorted(files)[start:start + 500]
        unknown, held = store.unknown_runs(ids)
        rows = []
        for run_id in sorted(unknown - held):
            try:
                s = summary(files[run_id])
            except AlgraspError:
                s = {"command": "design"}  # unreadable: nothing to index
            if s.get("command") == "design" or s.get("run_id") != run_id:
                with contextlib.suppress(OSError):
                    files[run_id].unlink()
                    out["removed"] += 1
                continue
            rows.append({"run_id": run_id, **{k: s.get(k) for k in ("command", "part_name", "action", "steps",
                                                                      "agreement", "cycle_time_s", "status", "error")}})
        store.add_runs(rows)
        out["indexed"] += len(rows)
    return out


def _age(p: Path, now: float) -> float:
    try:
        return now - p.stat().st_mtime
    except OSError:
        return -1.0


async def retention_loop(settings: Settings, store: Any) -> None:
    """Sweep now and every ``retention_period_s`` until cancelled."""
    while True:
        try:
            gone = await asyncio.to_thread(sweep, settings.log_dir, settings.record_max_age_s,
                                           settings.record_max_total_bytes)
            if gone:
                await asyncio.to_thread(store.delete_runs, gone)
            await asyncio.to_thread(reconcile_records, settings.log_dir, store, ORPHAN_AGE_S)
        except Exception as exc:  # noqa: BLE001 - a failed sweep (read-only DB…) is retried next period
            print(f"algrasp: record retention: {type(exc).__name__}: {exc}", flush=True)
        await asyncio.sleep(settings.retention_period_s)
