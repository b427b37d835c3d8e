"""Service health and recorded runs: ``/healthz`` (alive), ``/readyz`` (pools, database,
record directory), ``/metrics``, and ``/v1/runs`` with their records and figures.

A damaged record never makes a 500: its summary is ``null`` with the reason, its figure
a 422 naming the record."""

from __future__ import annotations

import asyncio
import os
import shutil
import stat
import uuid
from collections.abc import Iterator
from contextlib import suppress
from pathlib import Path as FilePath
from typing import Any

from fastapi import APIRouter, HTTPException, Path, Query, Request
from fastapi.responses import JSONResponse, PlainTextResponse, Response, StreamingResponse
from prometheus_client import CONTENT_TYPE_LATEST, generate_latest

from algrasp.errors import AlgraspError
from service.catalogue import canonical_hash
from service.contract import BINARY, HealthOut, PlaybackOut, ReadyOut, RunDetailOut, RunsOut, media, ok
from service.executor import ping
from service.middleware import ParsedJsonRoute
from service.models import LIMIT, OFFSET
from service.runtime import AUTH, VERSION, ServiceState, index_run, run_task, sees, state, who
from service.store import cause
from service.work import figure_task

router = APIRouter(route_class=ParsedJsonRoute)
RUN_ID = r"^[0-9]{8}T[0-9]{6}Z-[0-9a-f]{8}$"
MIN_FREE_BYTES = 50_000_000
"""Below this much free space in the record directory the service is not ready."""


@router.get("/healthz", tags=["service"], response_model=None, responses=ok(HealthOut))
async def healthz(request: Request) -> dict[str, Any]:
    """Alive: the process answers (says nothing of its pools or storage: see ``/readyz``);
    ``auth_required``: whether the other endpoints need an API key."""
    svc = state(request)
    return {"status": "ok", "version": VERSION, "executor": svc.runner.executor.name, "auth_required": bool(svc.settings.keys)}


@router.get("/v1/schemas", tags=["service"], dependencies=AUTH)
async def schemas_index() -> dict[str, list[str]]:
    """The names of the published document schemas (``/v1/schemas/{name}``)."""
    from algrasp.io.documents import DOCUMENTS

    return {"schemas": sorted(DOCUMENTS)}


@router.get("/v1/schemas/{name}", tags=["service"], dependencies=AUTH,
            responses=media("JSON Schema (draft 2020-12)", {"application/schema+json": {"type": "object"}}))
async def schema_endpoint(name: str = Path(description="a document: part, analysis, plan, validation, request, "
                                                       "run, job, error, sim-state, fences")) -> JSONResponse:
    """A document's JSON Schema (docs/conventions.md §4–§6), derived from the typed
    documents the service and the run records use; ``part`` is the file
    ``algrasp/schemas/part.schema.json``."""
    from algrasp.io.documents import DOCUMENTS, json_schema

    if name not in DOCUMENTS:
        raise HTTPException(404, f"no schema {name!r}: one of {', '.join(sorted(DOCUMENTS))}")
    return JSONResponse(json_schema(DOCUMENTS[name]), media_type="application/schema+json")


@router.get("/readyz", tags=["service"], responses=ok(ReadyOut))
async def readyz(request: Request) -> JSONResponse:
    """Ready: every pool answers a task, the database takes a write, the record directory
    takes a file and has room. 503 names the failing part."""
    svc = state(request)
    checks = dict(zip(("pool.fast", "pool.slow", "pool.jobs", "database", "records"), await asyncio.gather(
        _pool(svc, svc.pools["fast"]), _pool(svc, svc.pools["slow"]), _pool(svc, svc.runner.executor),
        asyncio.to_thread(_database, svc), asyncio.to_thread(_records, svc.settings.log_dir))))
    if checks["database"] == "ok" and svc.unindexed:
        try:
            await index_run(svc, svc.unindexed.pop())
        except AlgraspError as exc:
            checks["database"] = exc.message
    failing = [k for k, v in checks.items() if v != "ok"]
    if not failing:
        return JSONResponse({"status": "ready", "checks": checks, "load": svc.gate.load()})
    error = {"type": "unavailable", "reason": failing[0], "message": f"{failing[0]}: {checks[failing[0]]}",
             "checks": checks}
    return JSONResponse({"error": error}, status_code=503, headers={"Retry-After": "5"})


async def _pool(svc: ServiceState, pool: Any) -> str:
    try:
        await asyncio.wait_for(asyncio.wrap_future(pool.submit(ping, timeout_s=10.0, stage="readiness")), 15.0)
    except Exception as exc:  # noqa: BLE001 - whatever stops a pool is what readiness reports
        return f"no worker answered ({type(exc).__name__}: {getattr(exc, 'message', exc)})"
    return "ok"


def _database(svc: ServiceState) -> str:
    from sqlalchemy.exc import SQLAlchemyError

    try:
        svc.store.check()
    except SQLAlchemyError as exc:
        return f"cannot write ({type(cause(exc)).__name__}: {str(cause(exc))[:200]})"
    return "ok"


def _records(log_dir: FilePath) -> str:
    probe = log_dir / f".ready-{uuid.uuid4().hex}"
    try:
        probe.write_bytes(b"ok")
        probe.unlink()
        free = shutil.disk_usage(log_dir).free
    except OSError as exc:
        return f"cannot write in the record directory: {exc.strerror or type(exc).__name__}"
    return "ok" if free >= MIN_FREE_BYTES else f"only {free // 1_000_000} MB free in the record directory"


@router.get("/metrics", tags=["service"], dependencies=AUTH, response_class=PlainTextResponse)
async def metrics(request: Request) -> Response:
    svc = state(request)
    counts = await asyncio.to_thread(svc.store.counts)
    for k, n in counts["jobs"].items():
        svc.metrics.jobs.labels(k).set(n)
    for k, n in counts["parts"].items():
        svc.metrics.parts.labels(k).set(n)
    return Response(generate_latest(svc.metrics.registry), media_type=CONTENT_TYPE_LATEST)


@router.get("/v1/runs", tags=["runs"], dependencies=AUTH, response_model=None, responses=ok(RunsOut))
async def runs(request: Request, limit: int = LIMIT, offset: int = OFFSET) -> dict[str, Any]:
    total, rows = await asyncio.to_thread(state(request).store.runs, limit, offset, sees(request))
    return {"total": total, "limit": limit, "offset": offset, "runs": rows}


@router.get("/v1/runs/{run_id}", tags=["runs"], dependencies=AUTH, response_model=None, responses=ok(RunDetailOut))
async def run(request: Request, run_id: str = Path(pattern=RUN_ID)) -> dict[str, Any]:
    """The stored run and its record's summary (``record: null`` and ``record_error``
    when the record is damaged)."""
    from algrasp.io.record.replay import summary

    row, path = _run_file(request, run_id)
    try:
        return {**row, "record": await asyncio.to_thread(summary, path)}
    except AlgraspError as exc:
        return {**row, "record": None, "record_error": exc.message}


@router.get("/v1/runs/{run_id}/record", tags=["runs"], dependencies=AUTH, response_class=StreamingResponse,
            responses=media("the MCAP record", {"application/octet-stream": BINARY}))
async def record(request: Request, run_id: str = Path(pattern=RUN_ID)) -> StreamingResponse:
    _, path = _run_file(request, run_id)
    try:  # O_NOFOLLOW: a link put in the record directory is not followed (to /etc/passwd, say)
        f = os.fdopen(os.open(path, os.O_RDONLY | os.O_NOFOLLOW), "rb")
    except OSError:
        raise HTTPException(404, f"no run {run_id!r}") from None
    size = os.fstat(f.fileno()).st_size
    return StreamingResponse(_chunks(f), media_type="application/octet-stream",
                             headers={"Content-Disposition": f'attachment; filename="{path.name}"',
                                      "Content-Length": str(size)})


def _chunks(f: Any, size: int = 1 << 20) -> Iterator[bytes]:
    with f:
        while chunk := f.read(size):
            yield chunk


@router.get("/v1/runs/{run_id}/playback", tags=["runs"], dependencies=AUTH, response_model=None, responses=ok(PlaybackOut))
async def playback(request: Request, run_id: str = Path(pattern=RUN_ID),
                   points: int = Query(400, ge=2, le=2000, description="most states per simulated sample")) -> dict[str, Any]:
    """The recorded part, plan, validation and simulated trajectories (part unit, deg),
    for playing a run back (422 when the record is damaged)."""
    from algrasp.io.record.playback import playback as read_playback

    _, path = _run_file(request, run_id)
    return await asyncio.to_thread(read_playback, path, points)


@router.get("/v1/runs/{run_id}/figure.svg", tags=["runs"], dependencies=AUTH, response_class=Response,
            responses=media("the plan figure", {"image/svg+xml": {"type": "string"}}))
async def figure(request: Request, run_id: str = Path(pattern=RUN_ID)) -> Response:
    """The plan figure of a recorded plan run (422 when the run has no plan or its record
    is damaged)."""
    svc = state(request)
    _, path = _run_file(request, run_id)
    key = canonical_hash(["figure", VERSION, run_id, path.stat().st_mtime_ns])
    svg = svc.cache.get(key)
    if svg is None:
        svg = await run_task(svc, "slow", who(request), figure_task, str(path),
                             timeout_s=svc.settings.plan_time_limit_s, stage="figure")
        with suppress(ValueError):  # larger than the whole cache (ALGRASP_CACHE_BYTES): answered, not kept
            svc.cache[key] = svg
    return Response(svg, media_type="image/svg+xml")


def _regular(path: FilePath) -> bool:
    """A regular file itself, not a link to one (lstat)."""
    try:
        return stat.S_ISREG(os.lstat(path).st_mode)
    except OSError:
        return False


def _run_file(request: Request, run_id: str) -> tuple[dict[str, Any], FilePath]:
    """The stored run and its record path; 404 for unknown runs or missing records
    (deleted by retention). ``run_id`` matched RUN_ID, so the path stays inside the log
    directory."""
    svc = state(request)
    row = svc.store.run(run_id, sees(request))  # another key's run is "no run", as an unknown one
    path = svc.settings.log_dir / f"{run_id}.mcap"
    if row is None or not _regular(path):
        raise HTTPException(404, f"no run {run_id!r}")
    return row, path

