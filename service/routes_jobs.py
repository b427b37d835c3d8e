"""Batch job endpoints: submit (JSON list of part documents, or a multipart upload of a
zip/tar archive of part files), progress, results (JSON lines or a zip with the report
and gripper specification), cancel."""

from __future__ import annotations

import asyncio
from typing import Any

from fastapi import APIRouter, HTTPException, Path, Query, Request
from fastapi.responses import JSONResponse, Response
from pydantic import ValidationError
from starlette.datastructures import UploadFile

from algrasp.errors import ConfigError, LimitExceededError, PartDocumentError, UnavailableError
from algrasp.io.documents import inline
from algrasp.io.jsonguard import parse_json
from service.catalogue import Entry, read_archive_said
from service.contract import CancelOut, GripperSpecOut, JobCreatedOut, JobOut, JobsOut, ok
from service.middleware import ParsedJsonRoute
from service.models import LIMIT, OFFSET, JobBody, JobOptions
from service.reports import report_zip, results_jsonl
from service.runtime import check_samples, owner, run_task, sees, who

router = APIRouter(prefix="/v1/jobs", tags=["jobs"], route_class=ParsedJsonRoute)
JOB_ID = r"^[0-9a-f]{32}$"
RESULTS_PAGE = 1000
"""Parts per page of ``GET /v1/jobs/{id}/results`` (jsonl) by default: ~3 MB."""


_BODY = {"required": True, "content": {"application/json": {"schema": inline(JobBody.model_json_schema(by_alias=True))}}}
_ARCHIVE = {"required": True, "content": {
    "multipart/form-data": {"schema": {"type": "object", "required": ["archive"], "properties": {
        "archive": {"type": "string", "format": "binary", "description": "zip or tar(.gz) of part files"},
        "options": {"type": "string", "description": "JobOptions as a JSON string"}}}}}}
# One media type per operation: generated clients (openapi-python-client) type one body per
# operation; ``POST /v1/jobs`` also takes the multipart form, as it always has.


def _svc(request: Request) -> Any:
    return request.app.state.svc


def _validation(exc: ValidationError, prefix: str) -> ConfigError:
    e = exc.errors()[0]
    loc = ".".join(str(x) for x in e["loc"])
    return ConfigError(f"{prefix}.{loc}" if loc else prefix, e["msg"])


async def _entries(request: Request, max_parts: int, max_bytes: int) -> tuple[list[Entry], JobOptions, list[str]]:
    ctype = request.headers.get("content-type", "")
    if ctype.startswith("multipart/form-data"):
        form = await request.form(max_files=1, max_fields=4)
        upload, raw = form.get("archive"), form.get("options")
        if not isinstance(upload, UploadFile):
            raise PartDocumentError("archive", "a multipart job needs a file field 'archive'")
        try:
            opts = JobOptions.model_validate(parse_json(raw, "options") if isinstance(raw, str) and raw else {})
        except ValidationError as exc:
            raise _validation(exc, "options") from None
        data = await upload.read()
        svc = _svc(request)  # archives are read in a time-limited worker, never in the server
        read = await run_task(svc, "slow", who(request), read_archive_said, data, max_parts, max_bytes,
                              timeout_s=svc.settings.plan_time_limit_s, stage="archive")
        return read["entries"], opts, read["skipped"]
    if not ctype.startswith("application/json"):
        raise ConfigError("content-type", "send application/json (parts) or multipart/form-data (archive)")
    try:
        body = JobBody.model_validate(await request.json())  # the guard's parse (ParsedJsonRoute), not a second one
    except ValidationError as exc:
        raise _validation(exc, "body") from None
    if len(body.parts) > max_parts:
        raise LimitExceededError("body.parts", f"at most {max_parts} parts per job")
    names = [str(p["name"]) if isinstance(p.get("name"), str) else f"part-{i}" for i, p in enumerate(body.parts)]
    return [(n, p, None) for n, p in zip(names, body.parts)], body.options, []


@router.post("", status_code=202, openapi_extra={"requestBody": _BODY},
             responses={202: {"model": JobCreatedOut, "description": "queued"}})
async def create_job(request: Request) -> JSONResponse:
    """Queue a batch: fixture design for every part document. Returns ``202`` and the job
    id. (A multipart archive is taken here too; ``/v1/jobs/archives`` declares it.)"""
    return await _create(request)


@router.post("/archives", status_code=202, openapi_extra={"requestBody": _ARCHIVE},
             responses={202: {"model": JobCreatedOut, "description": "queued"}})
async def create_archive_job(request: Request) -> JSONResponse:
    """Queue a batch over the part files of a zip or tar(.gz) archive (drawings, meshes,
    part documents), with ``options`` as a JSON string. Returns ``202`` and the job id."""
    if not request.headers.get("content-type", "").startswith("multipart/form-data"):
        raise ConfigError("content-type", "send multipart/form-data with a file field 'archive'")
    return await _create(request)


async def _create(request: Request) -> JSONResponse:
    svc = _svc(request)
    if not await asyncio.to_thread(svc.runner.executor.capacity):  # a Dask scheduler without workers
        raise UnavailableError("no_workers", "no worker can take batch parts now (the Dask scheduler has no "
                               "workers): try again once /readyz is ready", 10.0)
    entries, opts, skipped = await _entries(request, svc.settings.max_batch_parts, svc.settings.max_body_bytes)
    check_samples(svc.settings, opts.validate_, "options.validate.samples")
    if opts.gripper is not None:
        from optimisation.profile import profile_from_dict

        profile_from_dict(opts.gripper, "options.gripper")
    job_id = await asyncio.to_thread(svc.store.create_job, opts.design(svc.settings.cell_physics), entries, None,
                                     owner(who(request)))
    svc.runner.start(job_id)
    return JSONResponse({"id": job_id, "state": "queued", "total": len(entries), "ignored": skipped, "links": _links(job_id)},
                        status_code=202, headers={"Location": f"/v1/jobs/{job_id}"})


def _links(job_id: str) -> dict[str, str]:
    return {"self": f"/v1/jobs/{job_id}", "results": f"/v1/jobs/{job_id}/results"}


@router.get("", response_model=None, responses=ok(JobsOut))
async def list_jobs(request: Request, limit: int = LIMIT, offset: int = OFFSET) -> dict[str, Any]:
    return {"jobs": await asyncio.to_thread(_svc(request).store.jobs, limit, offset, sees(request))}


async def _progress(request: Request, job_id: str) -> dict[str, Any]:
    """The job's progress; 404 for an unknown job and for another key's (no leak of which)."""
    store, viewer = _svc(request).store, sees(request)
    p = await asyncio.to_thread(lambda: store.progress(job_id) if store.owns_job(job_id, viewer) else None)
    if p is None:
        raise HTTPException(404, f"no job {job_id!r}")
    return p  # type: ignore[no-any-return]


@router.get("/{job_id}", response_model=None, responses=ok(JobOut))
async def job(request: Request, job_id: str = Path(pattern=JOB_ID)) -> dict[str, Any]:
    """State, progress (done/total) and per-part status."""
    p = await _progress(request, job_id)
    return {**p, "progress": {"finished": p["total"] - p["pending"], "total": p["total"]}, "links": _links(job_id)}


@router.get("/{job_id}/results", response_class=Response, responses={200: {"description": "JSON lines or a zip", "content": {
    "application/x-ndjson": {"schema": {"type": "string"}}, "application/zip": {"schema": {"type": "string", "format": "binary"}}}}})
async def results(request: Request, job_id: str = Path(pattern=JOB_ID),
                  format: str = Query("jsonl", pattern="^(jsonl|zip)$"),  # noqa: A002
                  offset: int = Query(0, ge=0, le=1_000_000_000, description="jsonl: parts to skip"),
                  limit: int = Query(RESULTS_PAGE, ge=1, le=100_000, description="jsonl: most parts in this page")) -> Response:
    """JSON lines (one part per line; a page of ``limit`` parts from ``offset``, with a
    ``Link: rel="next"`` header while more follow) or a zip with results, summary, report
    and gripper specification. Partial while the job runs. A body past the response bound
    is a 422 naming what to lower."""
    svc = _svc(request)
    p = await _progress(request, job_id)
    rows = await asyncio.to_thread(svc.store.results, job_id)
    if format == "jsonl":
        body = results_jsonl(rows[offset:offset + limit]).encode()
        _bounded(svc, len(body), "limit")
        more = offset + limit < len(rows)
        headers = {"Link": f'</v1/jobs/{job_id}/results?offset={offset + limit}&limit={limit}>; rel="next"'} if more else {}
        return Response(body, media_type="application/x-ndjson", headers={**headers, "X-Total-Count": str(len(rows))})
    data = await asyncio.to_thread(report_zip, rows, p)
    _bounded(svc, len(data), "format")
    return Response(data, media_type="application/zip",
                    headers={"Content-Disposition": f'attachment; filename="job-{job_id}.zip"'})


def _bounded(svc: Any, size: int, option: str) -> None:
    if size > svc.settings.max_response_bytes:
        advice = "lower limit (page with offset)" if option == "limit" else "use format=jsonl, paged with offset and limit"
        raise LimitExceededError(option, f"the response would be {size} bytes (at most "
                                 f"{svc.settings.max_response_bytes}): {advice}")


@router.get("/{job_id}/gripper", response_model=None, responses=ok(GripperSpecOut))
async def gripper(request: Request, job_id: str = Path(pattern=JOB_ID)) -> dict[str, Any]:
    """The gripper specification covering every part oriented so far (``gripper_spec.json``
    of the results zip): jaw opening and length, push stroke, cycle times, and the parts
    not oriented with why. Partial while the job runs."""
    from service.fixture import catalogue_spec

    await _progress(request, job_id)
    rows = await asyncio.to_thread(_svc(request).store.results, job_id)
    return catalogue_spec(rows)


@router.delete("/{job_id}", response_model=None, responses=ok(CancelOut))
async def cancel(request: Request, job_id: str = Path(pattern=JOB_ID)) -> dict[str, Any]:
    """Cancel a queued or running job (parts already finished keep their results)."""
    p = await _progress(request, job_id)
    if not await asyncio.to_thread(_svc(request).runner.cancel, job_id):
        raise HTTPException(409, f"job {job_id} is already {p['state']}")
    return {"id": job_id, "state": "cancelled"}
