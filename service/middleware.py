"""HTTP plumbing: the one error mapping (AlgraspError → status), the body-size limit,
API-key authentication and Prometheus metrics. Error bodies are always
``{"error": {"type", "message", "field"?, ..}}``."""

from __future__ import annotations

import asyncio
import hmac
import json
import time
from collections.abc import Awaitable, Callable, Coroutine
from typing import Any

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse, Response
from fastapi.routing import APIRoute
from prometheus_client import CollectorRegistry, Counter, Gauge, Histogram
from sqlalchemy.exc import SQLAlchemyError
from starlette.exceptions import HTTPException as StarletteHTTPException

from algrasp.errors import AlgraspError, AmbiguousRequestError, LimitExceededError, SlowRequestError, StorageError
from service.store import cause

ASGIApp = Callable[[dict[str, Any], Callable[[], Awaitable[dict[str, Any]]], Callable[[dict[str, Any]], Awaitable[None]]],
                   Awaitable[None]]


def error_response(status: int, error: dict[str, Any], headers: dict[str, str] | None = None) -> JSONResponse:
    return JSONResponse({"error": error}, status_code=status, headers=headers)


def install_error_handlers(app: FastAPI) -> None:
    @app.exception_handler(AlgraspError)
    async def _algrasp(_: Request, exc: AlgraspError) -> JSONResponse:
        # Each error class knows its status (the request's fault: 422; full or faulty:
        # 503/429 with Retry-After); a body or archive too large is 413, a document past
        # a segment/degree limit a validation failure.
        too_large = isinstance(exc, LimitExceededError) and exc.field.startswith(("body", "archive"))
        retry = getattr(exc, "retry_after_s", None)
        headers = None if retry is None else {"Retry-After": str(max(1, round(retry)))}
        return error_response(413 if too_large else exc.http_status, exc.to_dict(), headers)

    @app.exception_handler(RequestValidationError)
    async def _invalid(_: Request, exc: RequestValidationError) -> JSONResponse:
        errors = [{"field": ".".join(str(x) for x in e.get("loc", ())), "problem": str(e.get("msg", ""))} for e in exc.errors()]
        first = errors[0] if errors else {"field": "body", "problem": "invalid request"}
        return error_response(422, {"type": "request_validation", "message": f"{first['field']}: {first['problem']}",
                                    "field": first["field"], "errors": errors[:20]})

    @app.exception_handler(StarletteHTTPException)
    async def _http(_: Request, exc: StarletteHTTPException) -> JSONResponse:
        kind = {401: "unauthorized", 404: "not_found", 405: "method_not_allowed", 409: "conflict"}.get(exc.status_code, "http_error")
        return error_response(exc.status_code, {"type": kind, "message": str(exc.detail)}, dict(exc.headers or {}))

    @app.exception_handler(SQLAlchemyError)
    async def _database(_: Request, exc: SQLAlchemyError) -> JSONResponse:
        err = StorageError("database", f"the database cannot be used now ({type(cause(exc)).__name__}: read-only, "
                           "full or gone?)", 30.0)
        return error_response(503, err.to_dict(), {"Retry-After": "30"})

    @app.exception_handler(Exception)
    async def _internal(_: Request, exc: Exception) -> JSONResponse:  # never expected: the fuzz test looks for these
        return error_response(500, {"type": "internal_error", "message": f"{type(exc).__name__}"})


SINGLE_HEADERS = frozenset({b"content-type", b"content-length", b"transfer-encoding", b"authorization", b"host"})
"""Headers a request may carry at most once (RFC 9110 §5.3: they are not lists)."""


PARSED_JSON = "algrasp.parsed_json"
"""The ASGI scope key of the JSON body as the guard parsed it (:class:`ParsedJsonRoute`
hands it to the framework, so a body is parsed once)."""


class ParsedJsonRoute(APIRoute):
    """A route whose JSON body is the one :class:`RequestGuard` already parsed: FastAPI
    reads ``Request.json()``, which answers from ``_json`` when it is set (Starlette's
    cache), instead of decoding the bytes a second time."""

    def get_route_handler(self) -> Callable[[Request], Coroutine[Any, Any, Response]]:
        handler = super().get_route_handler()

        async def route(request: Request) -> Response:
            if PARSED_JSON in request.scope:
                request._json = request.scope[PARSED_JSON]
            return await handler(request)

        return route


class RequestGuard:
    """Every request body is read whole before the app sees it: over ``max_bytes``
    (declared or streamed, chunked included) → 413; a JSON body must pass
    :func:`algrasp.io.jsonguard.parse_json` (finite numbers, bounded depth and sizes, valid
    Unicode) → else 422 naming the field. So no handler, worker or record ever sees a
    value it cannot represent."""

    def __init__(self, app: ASGIApp, max_bytes: int, body_timeout_s: float = 30.0) -> None:
        self.app = app
        self.max_bytes = max_bytes
        self.body_timeout_s = body_timeout_s

    async def __call__(self, scope: dict[str, Any], receive: Any, send: Any) -> None:
        if scope["type"] != "http":
            return await self.app(scope, receive, send)
        names = [name.lower() for name, _ in scope.get("headers", [])]
        repeated = sorted({n.decode("latin-1") for n in names if n in SINGLE_HEADERS and names.count(n) > 1})
        if repeated:  # the guard and the framework must read the same value: refuse, don't pick one
            return await _send_error(send, 400, AmbiguousRequestError(repeated[0], "given more than once: send it once"))
        headers = dict(scope.get("headers", []))
        declared = headers.get(b"content-length")
        if declared is not None and declared.isdigit() and int(declared) > self.max_bytes:
            return await _send_error(send, 413, self._too_large())
        chunks, seen, more = [], 0, True
        deadline = asyncio.get_running_loop().time() + self.body_timeout_s
        while more:
            try:
                msg = await asyncio.wait_for(receive(), deadline - asyncio.get_running_loop().time())
            except TimeoutError:
                return await _send_error(send, 408, SlowRequestError(self.body_timeout_s))
            if msg["type"] == "http.disconnect":
                return None
            chunks.append(msg.get("body", b""))
            seen += len(chunks[-1])
            if seen > self.max_bytes:
                return await _send_error(send, 413, self._too_large())
            more = msg.get("more_body", False)
        body = b"".join(chunks)
        if body and headers.get(b"content-type", b"").split(b";")[0].strip().lower().endswith(b"json"):
            from algrasp.io.jsonguard import parse_json

            try:
                scope[PARSED_JSON] = await asyncio.to_thread(parse_json, body) if len(body) > 65_536 else parse_json(body)
            except AlgraspError as exc:
                return await _send_error(send, 422, exc)
        sent = False

        async def replay() -> dict[str, Any]:
            nonlocal sent
            if sent:  # the app asks again only to learn of a disconnect
                return await receive()  # type: ignore[no-any-return]
            sent = True
            return {"type": "http.request", "body": body, "more_body": False}

        await self.app(scope, replay, send)

    def _too_large(self) -> LimitExceededError:
        return LimitExceededError("body", f"request body larger than {self.max_bytes} bytes")


async def _send_error(send: Any, status: int, exc: AlgraspError) -> None:
    # Outside the app no exception handler is in place: send the handlers' error body.
    body = json.dumps({"error": exc.to_dict()}).encode()
    await send({"type": "http.response.start", "status": status,
                "headers": [(b"content-type", b"application/json"), (b"content-length", str(len(body)).encode())]})
    await send({"type": "http.response.body", "body": body})


def bearer_key(authorization: str | None) -> str | None:
    """The key of ``Authorization: Bearer KEY`` (scheme in any case, spaces around the
    key ignored), or None. One parser for authentication and for the rate limit, so
    ``Bearer  K`` and ``Bearer K`` are one client."""
    scheme, _, key = (authorization or "").strip().partition(" ")
    return key.strip() or None if scheme.lower() == "bearer" else None


def check_key(authorization: str | None, keys: frozenset[str]) -> bool:
    """Whether ``Authorization: Bearer KEY`` names a configured key (constant-time)."""
    if not keys:
        return True
    given = bearer_key(authorization)
    return given is not None and any(hmac.compare_digest(given.encode(), k.encode()) for k in keys)


class Metrics:
    """The service's Prometheus metrics, on their own registry (one per app)."""

    def __init__(self) -> None:
        self.registry = CollectorRegistry()
        r = self.registry
        self.requests = Counter("algrasp_http_requests_total", "HTTP requests", ["method", "route", "status"], registry=r)
        self.latency = Histogram("algrasp_http_request_duration_seconds", "HTTP request latency", ["method", "route"],
                                 buckets=(0.002, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1, 2.5, 5, 10, 30, 120), registry=r)
        self.plans = Counter("algrasp_plans_total", "Plans answered", ["action", "cached"], registry=r)
        self.analyses = Counter("algrasp_analyses_total", "Analyses answered", ["cached"], registry=r)
        self.validations = Counter("algrasp_validations_total", "Drake validations run", registry=r)
        self.samples = Counter("algrasp_validation_samples_total", "Drake samples simulated", registry=r)
        self.jobs = Gauge("algrasp_jobs", "Jobs by state", ["state"], registry=r)
        self.parts = Gauge("algrasp_job_parts", "Job parts by status", ["status"], registry=r)


class MetricsMiddleware:
    """Count and time every HTTP request by route template (not raw path: bounded labels)."""

    def __init__(self, app: ASGIApp, metrics: Metrics) -> None:
        self.app = app
        self.metrics = metrics

    async def __call__(self, scope: dict[str, Any], receive: Any, send: Any) -> None:
        if scope["type"] != "http":
            return await self.app(scope, receive, send)
        t0 = time.perf_counter()
        status = [500]

        async def send_status(msg: dict[str, Any]) -> None:
            if msg["type"] == "http.response.start":
                status[0] = msg["status"]
            await send(msg)

        try:
            await self.app(scope, receive, send_status)
        finally:
            route = getattr(scope.get("route"), "path", "unmatched")
            self.metrics.requests.labels(scope["method"], route, str(status[0])).inc()
            self.metrics.latency.labels(scope["method"], route).observe(time.perf_counter() - t0)
