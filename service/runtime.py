"""What every route shares: the service state, authentication, client identity, running
a task on a pool under admission control, indexing its run, bounded response bodies."""

from __future__ import annotations

import asyncio
import importlib.metadata
import json
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Annotated, Any, TypeVarTuple

from cachetools import LRUCache
from fastapi import Depends, HTTPException, Request
from fastapi.security import HTTPBearer

from algrasp.errors import ConfigError, LimitExceededError, StorageError, TimeLimitError
from algrasp.io.record.recorder import discard_partial
from service.admission import Gate, client_id
from service.executor import Executor
from service.jobs import JobRunner
from service.middleware import Metrics, bearer_key, check_key
from service.settings import Settings
from service.store import Store, cause

VERSION = importlib.metadata.version("algrasp")
LATE_S = 5.0
"""Grace past a task's own time limit before the server stops waiting for its worker."""
Ts = TypeVarTuple("Ts")
"""A task's positional arguments: :func:`run_task` checks them against the task's own."""


@dataclass
class ServiceState:
    settings: Settings
    store: Store
    pools: dict[str, Executor]  # "fast": cheap interactive requests, "slow": the rest
    runner: JobRunner  # batch jobs, on their own executor
    metrics: Metrics
    gate: Gate
    cache: LRUCache[str, bytes]
    unindexed: list[dict[str, Any]] = field(default_factory=list)  # runs the database could not take yet


def state(request: Request) -> ServiceState:
    return request.app.state.svc  # type: ignore[no-any-return]


BEARER = HTTPBearer(auto_error=False, scheme_name="bearer",
                    description="an API key of ALGRASP_API_KEYS (needed only when keys are configured)")
"""Declares the Bearer scheme in the OpenAPI document (Swagger's Authorize button, the
generated client's ``AuthenticatedClient``); the key itself is checked below."""


def require_key(request: Request, _declared: Annotated[Any, Depends(BEARER)] = None) -> None:
    """Every endpoint but ``/healthz``/``/readyz``: ``Authorization: Bearer KEY`` when keys are configured."""
    if not check_key(request.headers.get("authorization"), state(request).settings.keys):
        raise HTTPException(401, "missing or wrong API key (Authorization: Bearer KEY)", {"WWW-Authenticate": "Bearer"})


def who(request: Request) -> str:
    """The admission client: the key's owner id when keys are configured, else the address."""
    key = bearer_key(request.headers.get("authorization")) if state(request).settings.keys else None
    return client_id(key, request.client.host if request.client else None)


def owner(client: str) -> str | None:
    """The owner stored with a run or job made by ``client`` (None: authentication off)."""
    return client if client.startswith("key:") else None


def sees(request: Request) -> str | None:
    """Whose runs and jobs the caller may read: its own (an owner id), or all (None) for an
    admin key or when authentication is off."""
    settings = state(request).settings
    key = bearer_key(request.headers.get("authorization"))
    if not settings.keys or (key is not None and settings.is_admin(key)):
        return None
    return owner(who(request)) or "key:none"


async def run_task(svc: ServiceState, pool: str, client: str, fn: Callable[[*Ts], Any], *args: *Ts, timeout_s: float,
                   stage: str, run_id: str | None = None) -> Any:
    """Run ``fn`` on ``pool`` with a time limit that always fires; index its run; raise
    its user error. Refused at once (503/429) when the pool or the client is full."""
    with svc.gate.admit(pool, client):
        fut = svc.pools[pool].submit(fn, *args, *(() if run_id is None else (run_id,)), timeout_s=timeout_s, stage=stage)
        try:
            out = await asyncio.wait_for(asyncio.wrap_future(fut), timeout_s + LATE_S)
        except TimeoutError:
            fut.cancel()
            _drop_partial(svc, run_id)
            raise TimeLimitError(stage, timeout_s) from None
        except BaseException:
            _drop_partial(svc, run_id)
            raise
    if not isinstance(out, tuple):
        return out
    response, run, err = out
    await index_run(svc, {**run, "owner": owner(client)})
    if err is not None:
        raise err
    return response


def _drop_partial(svc: ServiceState, run_id: str | None) -> None:
    """The worker was killed (time limit, crash): its half-written record goes too."""
    if run_id is not None:
        discard_partial(svc.settings.log_dir, run_id)


async def index_run(svc: ServiceState, run: dict[str, Any]) -> None:
    """Store a run row (with any the database refused before). If the database cannot
    take it, the record is kept and the row waits in memory for the next write or
    ``/readyz``: a 503 says so, and the run is not lost."""
    from sqlalchemy.exc import SQLAlchemyError

    rows = [*svc.unindexed, run]
    try:
        await asyncio.to_thread(svc.store.add_runs, rows)
    except SQLAlchemyError as exc:
        svc.unindexed[:] = rows[-10_000:]
        raise StorageError("database", f"the run {run['run_id']} is recorded but the database cannot be written "
                           f"({type(cause(exc)).__name__}: read-only or full?); it is indexed once the database "
                           "is writable", 30.0) from None
    svc.unindexed.clear()


def encoded(svc: ServiceState, value: Any, option: str) -> bytes:
    """The JSON body of a response, bounded by ``max_response_bytes`` (``option``: what to lower)."""
    body = json.dumps(value, allow_nan=False, separators=(",", ":")).encode()
    if len(body) > svc.settings.max_response_bytes:
        raise LimitExceededError(option, f"the response would be {len(body)} bytes (at most "
                                 f"{svc.settings.max_response_bytes}): lower {option}")
    return body



def check_samples(settings: Settings, validate: Any, field: str) -> None:
    """``validate.samples`` within ``ALGRASP_MAX_SAMPLES`` (plans and jobs alike)."""
    if validate is not None and validate.samples > settings.max_samples:
        raise ConfigError(field, f"at most {settings.max_samples} samples per part")


AUTH = [Depends(require_key)]
