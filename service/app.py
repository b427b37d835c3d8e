"""The HTTP service (FastAPI, served by uvicorn): analyses, plans, runs, batch jobs.

Compute runs in worker processes (``service.executor``) with a time limit per request,
so the event loop only parses, caches and stores. Cheap and expensive work run on
separate pools behind admission control (``service.admission``); bodies are bounded and
checked before any work (``algrasp.io.jsonguard``). Same-input requests are answered from a
cache bounded in bytes, keyed by the canonical hash of the body and the algrasp version.
"""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager, suppress
from pathlib import PurePath
from typing import TYPE_CHECKING, Annotated, Any

from cachetools import LRUCache
from fastapi import APIRouter, Depends, FastAPI, File, Form, Query, Request, UploadFile
from fastapi.responses import Response
from fastapi_offline import FastAPIOffline

from algrasp.errors import ConfigError
from algrasp.planning.sampled import MAX_SAMPLES
from service.admission import FAST_COST, Gate, estimated_cost
from service.catalogue import canonical_hash
from service.contract import ERRORS, IMPORTED, NOT_FOUND, AnalysisOut, FencesOut, PlanOut, ok, typed
from service.executor import make_executor
from service.jobs import JobRunner, RunnerConfig
from service.middleware import Metrics, MetricsMiddleware, ParsedJsonRoute, RequestGuard, install_error_handlers
from service.models import FencesBody, PartJson, PlanBody
from service.runtime import AUTH, VERSION, ServiceState, check_samples, encoded, require_key, run_task, state, who
from service.settings import Settings
from service.store import Store
from service.work import analysis_task, fences_task, fences_validate_task, import_task, plan_task

if TYPE_CHECKING:  # the planning stack loads in the route, on first use
    from algrasp.pipeline import PlanRequest

DRAWING_TYPES = {"svg": "image/svg+xml", "dxf": "application/dxf"}
"""Media types of the fence drawings ``POST /v1/fences`` answers."""
SLOW_NICENESS = 5
"""The slow pool's workers (and the job pool's) run at this OS niceness: on a loaded
machine the cheap requests get the CPU first."""


def _cheap(body: PlanBody) -> bool:
    """A plan for the fast pool: no optimisation, no validation, a part of modest size."""
    return not body.optimise and body.validate_ is None and estimated_cost(body.part) <= FAST_COST


def _plan_request(svc: ServiceState, body: PlanBody) -> PlanRequest:
    """The request's options, checked before any work is queued and built once: the
    worker gets this object (with its model), not the body to parse again."""
    check_samples(svc.settings, body.validate_, "validate.samples")
    from algrasp.pipeline import PlanRequest

    req = PlanRequest(**body.request(svc.settings.cell_physics))
    _ = req.model  # built here, pickled with the request
    return req


def build_state(settings: Settings, metrics: Metrics) -> ServiceState:
    settings.log_dir.mkdir(parents=True, exist_ok=True)
    store = Store(settings.db_url, settings.db_busy_timeout_s)
    job_exec = make_executor(settings.scheduler, settings.workers, SLOW_NICENESS)
    limit = settings.plan_time_limit_s + settings.validation_time_limit_s
    runner = JobRunner(store, job_exec, RunnerConfig.for_workers(str(settings.log_dir), settings.sim_workers, limit,
                                                              settings.workers, settings.batch_chunk))
    pools = {"fast": make_executor("", settings.fast_workers), "slow": make_executor("", settings.workers, SLOW_NICENESS)}
    gate = Gate({"fast": settings.fast_workers + settings.queue_depth, "slow": settings.workers + settings.queue_depth},
                settings.max_inflight_per_client)
    return ServiceState(settings, store, pools, runner, metrics, gate,
                        LRUCache(maxsize=max(1, settings.cache_bytes), getsizeof=len))


def create_app(settings: Settings | None = None, warmup: dict[str, Any] | None = None, url: str | None = None) -> FastAPI:
    """The app. ``warmup``: a part document planned once at start-up (``make run``);
    ``url``: printed with the docs address once the service is ready."""
    from service.retention import clean_partials, reconcile_records, retention_loop

    settings = settings or Settings()
    metrics = Metrics()
    _ = settings.keys  # a missing key file fails at start-up, not on the first request

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        clean_partials(settings.log_dir)
        svc = build_state(settings, metrics)
        app.state.svc = svc
        with suppress(Exception):  # noqa: BLE001 - a database fault here is retried by the retention loop
            await asyncio.to_thread(reconcile_records, settings.log_dir, svc.store)
        svc.runner.resume_all()
        sweeper = asyncio.create_task(retention_loop(svc.settings, svc.store))
        adopter = asyncio.create_task(_adopt_jobs(svc))
        if warmup is not None:  # as a client's request: the route's body, options and task
            req = _plan_request(svc, PlanBody.model_validate({"part": warmup, "action": "push_grasp", "optimise": True}))
            plan = await run_task(svc, "slow", "warmup", plan_task, warmup, req, str(settings.log_dir),
                                  settings.sim_workers, timeout_s=settings.plan_time_limit_s, stage="plan")
            print(f"planned the example part {warmup.get('name')!r}: {len(plan['steps'])}-step push-grasp plan, "
                  f"cycle {plan['cycle_time_s']:.2f} s, run {plan['run_id']}", flush=True)
        if url:
            print(f"algrasp service ready: workbench at {url}/, API docs at {url}/docs", flush=True)
        yield
        sweeper.cancel()
        adopter.cancel()
        svc.runner.stop_all()
        for pool in (*svc.pools.values(), svc.runner.executor):
            pool.shutdown()

    # The API docs load Swagger UI and ReDoc from the package, not a CDN: /docs works offline.
    app = FastAPIOffline(title="algrasp", version=VERSION, lifespan=lifespan,
                         description="Sensorless orienting plans for planar parts with a parallel-jaw gripper.")
    install_error_handlers(app)
    app.add_middleware(RequestGuard, max_bytes=settings.max_body_bytes,  # type: ignore[arg-type]
                       body_timeout_s=settings.body_timeout_s)
    app.add_middleware(MetricsMiddleware, metrics=metrics)  # type: ignore[arg-type]
    app.include_router(router, responses=ERRORS)
    from service.routes_jobs import router as jobs_router
    from service.routes_runs import router as runs_router

    app.include_router(runs_router, responses={**ERRORS, **NOT_FOUND})
    app.include_router(jobs_router, dependencies=[Depends(require_key)], responses={**ERRORS, **NOT_FOUND})
    from service.web import mount

    mount(app)
    _typed_openapi(app)
    return app


router = APIRouter(route_class=ParsedJsonRoute)


async def _adopt_jobs(svc: ServiceState) -> None:
    """Every half lease: run the unfinished jobs of the database that no thread here runs
    (another instance's; conventions: one database, several instances)."""
    from sqlalchemy.exc import SQLAlchemyError

    from service.jobs import LEASE_S

    while True:
        await asyncio.sleep(LEASE_S / 2)
        with suppress(SQLAlchemyError):
            await asyncio.to_thread(svc.runner.resume_all)


def _typed_openapi(app: FastAPI) -> None:
    """``/openapi.json`` completed by ``contract.typed`` (part components, JSON errors)."""
    from fastapi.openapi.utils import get_openapi

    def openapi() -> dict[str, Any]:
        if app.openapi_schema is None:
            app.openapi_schema = typed(get_openapi(title=app.title, version=app.version,
                                                         description=app.description, routes=app.routes))
        return app.openapi_schema

    app.openapi = openapi  # type: ignore[method-assign]


async def _cached(request: Request, key: str, compute: Any, option: str) -> tuple[Response, bool]:
    """The cached response for ``key`` (``X-Cache``: hit/miss), computed on a miss; and
    whether it was a hit."""
    svc = state(request)
    hit = svc.cache.get(key)
    body = hit if hit is not None else encoded(svc, await compute(), option)
    if hit is None:
        with suppress(ValueError):  # larger than the whole cache: answered, not kept
            svc.cache[key] = body
    return Response(body, media_type="application/json", headers={"X-Cache": "miss" if hit is None else "hit"}), hit is not None


@router.post("/v1/analyses", tags=["plans"], dependencies=AUTH, responses=ok(AnalysisOut))
async def analyses(request: Request, part: PartJson,
                   exact: bool = Query(False, description="the paper's exact frictionless model (no dead band)"),
                   samples: int = Query(0, ge=0, le=MAX_SAMPLES, description="with samples > 0: add `geometry` (outline, "
                                        "holes, hull, centre of mass) and `curves` (d, r, Γ, p, Γ∘p at samples θ in [0, 360))"
                                        " for drawing")) -> Response:
    """Part document → the analysis object of ``algrasp analyze --json`` (robust model
    with the default physics, or ``?exact=true``), plus drawing samples when asked for."""
    from algrasp.io.record.recorder import new_run_id

    svc = state(request)
    key = canonical_hash(["analysis", VERSION, part, exact, samples])

    async def compute() -> Any:
        options = {"exact": exact, "samples": samples, "physics": svc.settings.cell_physics.to_dict()}
        pool = "fast" if estimated_cost(part, samples) <= FAST_COST else "slow"
        return await run_task(svc, pool, who(request), analysis_task, part, str(svc.settings.log_dir), options,
                              timeout_s=svc.settings.analysis_time_limit_s, stage="analysis", run_id=new_run_id())

    response, cached = await _cached(request, key, compute, "the part's size")
    svc.metrics.analyses.labels(str(cached).lower()).inc()
    return response


@router.post("/v1/plans", tags=["plans"], dependencies=AUTH, responses=ok(PlanOut))
async def plans(request: Request, body: PlanBody) -> Response:
    """The shortest plan (plus optimised execution and Drake validation when asked
    for) and its ``run_id``; a same-input request is answered from the cache."""
    from algrasp.io.record.recorder import new_run_id

    svc = state(request)
    req = _plan_request(svc, body)
    key = canonical_hash(["plan", VERSION, body.model_dump(by_alias=True)])
    limit = svc.settings.plan_time_limit_s + (svc.settings.validation_time_limit_s if body.validate_ else 0.0)

    async def compute() -> Any:
        return await run_task(svc, "fast" if _cheap(body) else "slow", who(request), plan_task, body.part, req,
                              str(svc.settings.log_dir), svc.settings.sim_workers, timeout_s=limit, stage="plan",
                              run_id=new_run_id())

    response, cached = await _cached(request, key, compute, "gripper.sample_hz")
    if not cached and body.validate_ is not None:
        svc.metrics.validations.inc()
        svc.metrics.samples.inc(body.validate_.samples)
    svc.metrics.plans.labels(body.action, str(cached).lower()).inc()
    return response


@router.post("/v1/fences", tags=["plans"], dependencies=AUTH, responses=ok(FencesOut))
async def fences(request: Request, body: FencesBody) -> Response:
    """The fewest conveyor fences orienting the part, laid out on a belt (the document of
    ``algrasp fences --json``; with ``drawing`` its SVG or DXF); a same-input request for
    the document is answered from the cache."""
    svc = state(request)
    check_samples(svc.settings, body.validate_, "validate.samples")
    options = body.options(svc.settings.cell_physics)
    key = canonical_hash(["fences", VERSION, body.model_dump(by_alias=True)])
    if body.validate_ is not None and body.drawing is None:  # simulated: recorded, never cached
        limit = svc.settings.plan_time_limit_s + svc.settings.validation_time_limit_s
        out = await run_task(svc, "slow", who(request), fences_validate_task, body.part, options,
                             body.validate_.samples, body.validate_.seed, str(svc.settings.log_dir),
                             timeout_s=limit, stage="fences")
        svc.metrics.validations.inc()
        svc.metrics.samples.inc(body.validate_.samples)
        return Response(encoded(svc, out, "validate.samples"), media_type="application/json")
    if body.drawing is not None:
        text = await run_task(svc, "slow", who(request), fences_task, body.part, options, body.drawing,
                              timeout_s=svc.settings.plan_time_limit_s, stage="fences")
        return Response(text, media_type=DRAWING_TYPES[body.drawing])

    async def compute() -> Any:
        return await run_task(svc, "slow", who(request), fences_task, body.part, options,
                              timeout_s=svc.settings.plan_time_limit_s, stage="fences")

    response, _ = await _cached(request, key, compute, "the part's size")
    return response


@router.post("/v1/imports", tags=["plans"], dependencies=AUTH, responses=IMPORTED)
async def imports(request: Request, file: Annotated[UploadFile, File(description="DXF, SVG or STL/OBJ/PLY/OFF/GLB file")],
                  layer: Annotated[str | None, Form(max_length=256)] = None,
                  id: Annotated[str | None, Form(max_length=256)] = None,  # noqa: A002
                  pose: Annotated[int | None, Form(ge=0, le=10_000)] = None,
                  part: Annotated[int | None, Form(ge=0, le=100_000)] = None,
                  list_parts: Annotated[bool, Form(alias="list")] = False,
                  documents: Annotated[int, Form(ge=0, le=1000, description="with list=true: the part documents of "
                                                 "the first N parts too (`documents`), the drawing read once")] = 0,
                  units: Annotated[str | None, Form(pattern="^(mm|cm|m|in|um)$",
                                                    description="the drawing's unit (default: its header's)")] = None,
                  engrave_colours: Annotated[str | None, Form(max_length=256, description=(
                      "stroke colours that are engraving (#rrggbb,...; none: every colour is cut; default: judged "
                      "from the drawing, reported in the warnings)"))] = None) -> Response:
    """A CAD file → its part document (exact curves; meshes give an approximate
    polygon), ready for ``/v1/plans``; ``part`` chooses one of several parts on a sheet,
    ``list=true`` returns ``{"parts": [...], "ignored", "warnings"}`` instead. Only the file
    name's suffix is used."""
    from algrasp.io.cad.readers import is_cad, supported

    svc = state(request)
    name = (file.filename or "upload").replace("\\", "/").rsplit("/", 1)[-1].encode("utf-8", "replace").decode()
    if not is_cad(name):
        raise ConfigError("file", f"unsupported file type {PurePath(name).suffix or '(none)'}: use "
                          f"{supported(('drawing', 'mesh'))} (a part document goes to /v1/plans as JSON)")
    options = {k: v for k, v in (("layer", layer), ("element_id", id), ("pose", pose), ("part", part),
                                 ("units", units), ("engrave_colours", engrave_colours)) if v is not None}
    if list_parts:
        options["list_parts"] = True
        if documents:
            options["documents"] = documents
    data = await file.read()
    out = await run_task(svc, "slow", who(request), import_task, name, data, options,
                         timeout_s=svc.settings.analysis_time_limit_s, stage="import")
    return Response(encoded(svc, out, "the drawing's size"), media_type="application/json")

