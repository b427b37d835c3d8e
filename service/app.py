"""The HTTP service (FastAPI, served by uvicorn): analyses, plans, runs, batch jobs.

Compute runs in worker processes (``service.executor``) with a time limit per request,
so the event loop only parses, caches and stores. Same-input requests are answered
from an LRU cache keyed by the canonical hash of the body and the algrasp version.
"""

from __future__ import annotations

import asyncio
import importlib.metadata
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from dataclasses import dataclass
from typing import Annotated, Any

from cachetools import LRUCache
from fastapi import APIRouter, Depends, FastAPI, File, Form, Header, HTTPException, Path, Query, Request, UploadFile
from fastapi.responses import FileResponse, JSONResponse, PlainTextResponse, Response
from prometheus_client import CONTENT_TYPE_LATEST, generate_latest

from algrasp.errors import AlgraspError, ConfigError
from service.catalogue import canonical_hash
from service.executor import Executor, make_executor
from service.jobs import JobRunner, RunnerConfig
from service.middleware import BodyLimit, Metrics, MetricsMiddleware, check_key, install_error_handlers
from service.models import LIMIT, OFFSET, PlanBody
from service.settings import Settings
from service.store import Store
from service.work import analysis_task, figure_task, import_task, plan_task

RUN_ID = r"^[0-9]{8}T[0-9]{6}Z-[0-9a-f]{8}$"
VERSION = importlib.metadata.version("algrasp")


@dataclass
class ServiceState:
    settings: Settings
    store: Store
    executor: Executor  # interactive requests
    runner: JobRunner  # batch jobs, on their own executor
    metrics: Metrics
    cache: LRUCache[str, Any]


def state(request: Request) -> ServiceState:
    return request.app.state.svc  # type: ignore[no-any-return]


def require_key(request: Request, authorization: str | None = Header(None)) -> None:
    """Every endpoint but ``/healthz``: ``Authorization: Bearer KEY`` when keys are configured."""
    if not check_key(authorization, state(request).settings.keys):
        raise HTTPException(401, "missing or wrong API key (Authorization: Bearer KEY)", {"WWW-Authenticate": "Bearer"})


async def run_task(svc: ServiceState, fn: Any, *args: Any, timeout_s: float, stage: str) -> Any:
    """Run ``fn`` in a worker with a time limit; store its run; raise its user error."""
    fut = svc.executor.submit(fn, *args, timeout_s=timeout_s, stage=stage)
    out = await asyncio.wrap_future(fut)
    if not isinstance(out, tuple):
        return out
    response, run, err = out
    await asyncio.to_thread(svc.store.add_run, run)
    if err is not None:
        raise err
    return response


def _limits(svc: ServiceState, body: PlanBody) -> None:
    if body.validate_ is not None and body.validate_.samples > svc.settings.max_samples:
        raise ConfigError("validate.samples", f"at most {svc.settings.max_samples} samples per request")
    if body.gripper is not None:
        from optimisation.profile import profile_from_dict

        if not body.optimise:
            raise ConfigError("gripper", "a gripper profile needs optimise: true")
        profile_from_dict(body.gripper)


def build_state(settings: Settings, metrics: Metrics) -> ServiceState:
    settings.log_dir.mkdir(parents=True, exist_ok=True)
    store = Store(settings.db_url)
    job_exec = make_executor(settings.scheduler, settings.workers)
    limit = settings.plan_time_limit_s + settings.validation_time_limit_s
    runner = JobRunner(store, job_exec, RunnerConfig(str(settings.log_dir), settings.sim_workers, limit, 2 * settings.workers))
    return ServiceState(settings, store, make_executor("", settings.workers), runner, metrics,
                        LRUCache(maxsize=max(1, settings.cache_entries)))


def create_app(settings: Settings | None = None, warmup: dict[str, Any] | None = None, url: str | None = None) -> FastAPI:
    """The app. ``warmup``: a part document planned once at start-up (``make run``);
    ``url``: printed with the docs address once the service is ready."""
    settings = settings or Settings()
    metrics = Metrics()
    _ = settings.keys  # a missing key file fails at start-up, not on the first request

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        svc = build_state(settings, metrics)
        app.state.svc = svc
        svc.runner.resume_all()
        if warmup is not None:
            plan = await run_task(svc, plan_task, warmup, {"action": "push_grasp", "optimise": True}, str(settings.log_dir),
                                  settings.sim_workers, timeout_s=settings.plan_time_limit_s, stage="plan")
            print(f"planned the example part {warmup.get('name')!r}: {len(plan['steps'])}-step push-grasp plan, "
                  f"cycle {plan['cycle_time_s']:.2f} s, run {plan['run_id']}", flush=True)
        if url:
            print(f"algrasp service ready: API docs at {url}/docs", flush=True)
        yield
        svc.executor.shutdown()
        svc.runner.executor.shutdown()

    app = FastAPI(title="algrasp", version=VERSION, lifespan=lifespan,
                  description="Sensorless orienting plans for planar parts with a parallel-jaw gripper.")
    install_error_handlers(app)
    app.add_middleware(BodyLimit, max_bytes=settings.max_body_bytes)  # type: ignore[arg-type]
    app.add_middleware(MetricsMiddleware, metrics=metrics)  # type: ignore[arg-type]
    app.include_router(router)
    from service.routes_jobs import router as jobs_router

    app.include_router(jobs_router, dependencies=[Depends(require_key)])
    return app


router = APIRouter()
AUTH = [Depends(require_key)]


@router.get("/healthz", tags=["service"])
async def healthz(request: Request) -> dict[str, Any]:
    svc = state(request)
    return {"status": "ok", "version": VERSION, "executor": svc.runner.executor.name}

@router.get("/metrics", tags=["service"], dependencies=AUTH, response_class=PlainTextResponse)
async def metrics(request: Request) -> Response:
    svc = state(request)
    counts = await asyncio.to_thread(svc.store.counts)
    for k, n in counts["jobs"].items():
        svc.metrics.jobs.labels(k).set(n)
    for k, n in counts["parts"].items():
        svc.metrics.parts.labels(k).set(n)
    return Response(generate_latest(svc.metrics.registry), media_type=CONTENT_TYPE_LATEST)

@router.post("/v1/analyses", tags=["plans"], dependencies=AUTH)
async def analyses(request: Request, part: dict[str, Any],
                   exact: bool = Query(False, description="the paper's exact frictionless model (no dead band)")) -> JSONResponse:
    """Part document → the analysis object of ``algrasp analyze --json`` (robust model
    with the default physics, or ``?exact=true``)."""
    svc = state(request)
    key = canonical_hash(["analysis", VERSION, part, exact])
    cached = key in svc.cache
    if not cached:
        svc.cache[key] = await run_task(svc, analysis_task, part, str(svc.settings.log_dir), {"exact": exact},
                                        timeout_s=svc.settings.analysis_time_limit_s, stage="analysis")
    svc.metrics.analyses.labels(str(cached).lower()).inc()
    return JSONResponse(svc.cache[key], headers={"X-Cache": "hit" if cached else "miss"})

@router.post("/v1/plans", tags=["plans"], dependencies=AUTH)
async def plans(request: Request, body: PlanBody) -> JSONResponse:
    """The shortest plan (plus optimised execution and Drake validation when asked
    for) and its ``run_id``; a same-input request is answered from the cache."""
    svc = state(request)
    _limits(svc, body)
    key = canonical_hash(["plan", VERSION, body.model_dump(by_alias=True)])
    cached = key in svc.cache
    if not cached:
        limit = svc.settings.plan_time_limit_s + (svc.settings.validation_time_limit_s if body.validate_ else 0.0)
        svc.cache[key] = await run_task(svc, plan_task, body.part, body.request(), str(svc.settings.log_dir),
                                        svc.settings.sim_workers, timeout_s=limit, stage="plan")
        if body.validate_ is not None:
            svc.metrics.validations.inc()
            svc.metrics.samples.inc(body.validate_.samples)
    svc.metrics.plans.labels(body.action, str(cached).lower()).inc()
    return JSONResponse(svc.cache[key], headers={"X-Cache": "hit" if cached else "miss"})

@router.post("/v1/imports", tags=["plans"], dependencies=AUTH)
async def imports(request: Request, file: Annotated[UploadFile, File(description="DXF, SVG or STL/OBJ/PLY/OFF/GLB file")],
                  layer: Annotated[str | None, Form(max_length=256)] = None,
                  id: Annotated[str | None, Form(max_length=256)] = None,  # noqa: A002
                  pose: Annotated[int | None, Form(ge=0, le=10_000)] = None,
                  part: Annotated[int | None, Form(ge=0, le=100_000)] = None,
                  list_parts: Annotated[bool, Form(alias="list")] = False) -> dict[str, Any]:
    """A CAD file → its part document (exact curves; meshes give an approximate
    polygon), ready for ``/v1/plans``; ``part`` chooses one of several parts on a sheet,
    ``list=true`` returns ``{"parts": [...], "ignored", "warnings"}`` instead. Only the file
    name's suffix is used."""
    from algrasp.cad import CAD_SUFFIXES, is_cad

    svc = state(request)
    name = (file.filename or "upload").replace("\\", "/").rsplit("/", 1)[-1]
    if not is_cad(name):
        raise ConfigError("file", f"unsupported file type: use {', '.join(CAD_SUFFIXES)}")
    options = {k: v for k, v in (("layer", layer), ("element_id", id), ("pose", pose), ("part", part)) if v is not None}
    if list_parts:
        options["list_parts"] = True
    data = await file.read()
    return await run_task(svc, import_task, name, data, options,  # type: ignore[no-any-return]
                          timeout_s=svc.settings.analysis_time_limit_s, stage="import")

@router.get("/v1/runs", tags=["runs"], dependencies=AUTH)
async def runs(request: Request, limit: int = LIMIT, offset: int = OFFSET) -> dict[str, Any]:
    total, rows = await asyncio.to_thread(state(request).store.runs, limit, offset)
    return {"total": total, "limit": limit, "offset": offset, "runs": rows}

@router.get("/v1/runs/{run_id}", tags=["runs"], dependencies=AUTH)
async def run(request: Request, run_id: str = Path(pattern=RUN_ID)) -> dict[str, Any]:
    from algrasp.record.replay import summary

    row, path = _run_file(request, run_id)
    try:
        return {**row, "record": await asyncio.to_thread(summary, path)}
    except AlgraspError:
        return {**row, "record": None}

@router.get("/v1/runs/{run_id}/record", tags=["runs"], dependencies=AUTH, response_class=FileResponse)
async def record(request: Request, run_id: str = Path(pattern=RUN_ID)) -> FileResponse:
    _, path = _run_file(request, run_id)
    return FileResponse(path, media_type="application/octet-stream", filename=path.name)

@router.get("/v1/runs/{run_id}/figure.svg", tags=["runs"], dependencies=AUTH, response_class=Response)
async def figure(request: Request, run_id: str = Path(pattern=RUN_ID)) -> Response:
    svc = state(request)
    _, path = _run_file(request, run_id)
    key = canonical_hash(["figure", VERSION, run_id])
    if key not in svc.cache:
        try:
            svc.cache[key] = await run_task(svc, figure_task, str(path), timeout_s=svc.settings.plan_time_limit_s,
                                            stage="figure")
        except AlgraspError as exc:
            raise HTTPException(404, exc.message) from None
    return Response(svc.cache[key], media_type="image/svg+xml")


def _run_file(request: Request, run_id: str) -> tuple[dict[str, Any], Any]:
    """The stored run and its record path; 404 for unknown runs or missing records.
    ``run_id`` matched RUN_ID, so the path stays inside the log directory."""
    svc = state(request)
    row = svc.store.run(run_id)
    path = svc.settings.log_dir / f"{run_id}.mcap"
    if row is None or not path.is_file():
        raise HTTPException(404, f"no run {run_id!r}")
    return row, path
