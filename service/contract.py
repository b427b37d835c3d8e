"""The typed HTTP contract, so ``/openapi.json`` describes what the service takes and sends.

The documents themselves (part, analysis, plan, validation, job, error) are typed once in
:mod:`algrasp.io.documents` — the same models give the run records' schemas; here they are
extended by what only HTTP adds (``run_id``, drawing samples) and the service's own
responses (runs, health, jobs) are typed. The part document is still parsed by the core
(``algrasp.geometry.document``), whose errors name the segment.
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field

from algrasp.io.documents import (
    AnalysisDocument,
    ErrorBody,
    FenceDocument,
    JobDocument,
    JobProgress,
    PartDocument,
    PlanDocument,
    Point,
    ValidationDocument,
    json_schema,
)


class _Open(BaseModel):
    """A response document: the fields named here are guaranteed, others may be added
    (a documented superset)."""

    model_config = ConfigDict(extra="allow")


class PlanOut(PlanDocument):
    """``POST /v1/plans``: the plan document, its run and (with validate) its validation."""

    model: str = Field(description="robust or exact")
    run_id: str
    validation: ValidationDocument | None = Field(None, description="with validate: agreement and per-sample outcomes")


class FencesOut(FenceDocument):
    """``POST /v1/fences``: the fence document (conventions §9)."""


class GeometryOut(_Open):
    """The part drawn (part frame, part unit): closed polylines, first point not repeated."""

    outline: list[Point]
    holes: list[list[Point]]
    hull: list[Point]
    center_of_mass: Point


class CurvesOut(_Open):
    """d, r and the exact transfer functions (lifted, deg) on a regular θ grid in [0, 360)."""

    theta_deg: list[float]
    diameter: list[float]
    radius: list[float]
    squeeze_deg: list[float]
    push_deg: list[float]
    push_grasp_deg: list[float]


class AnalysisOut(AnalysisDocument):
    """``POST /v1/analyses``: the analysis document (and with ``samples`` the drawing
    samples ``geometry`` and ``curves``)."""

    geometry: GeometryOut | None = None
    curves: CurvesOut | None = None
    run_id: str


class SheetOut(_Open):
    """``POST /v1/imports`` with ``list=true``: the parts of a drawing sheet."""

    parts: list[dict[str, Any]]
    ignored: list[str]
    warnings: list[str]


class ImportedFence(_Open):
    """A fence read back from a layout drawing (the file's unit)."""

    side: Literal["left", "right"]
    angle_deg: float = Field(description="the wall's world direction, [0, 180)")
    steepness_deg: float = Field(description="its angle to the belt direction")
    position: float = Field(description="its root's position along the belt")
    length: float


class FenceLayoutOut(_Open):
    """``POST /v1/imports`` of a fence layout DXF (``algrasp fences --dxf``): the layout
    read back, not a part (:mod:`algrasp.io.fence_import`)."""

    kind: Literal["fence_layout"]
    units: str
    belt_width: float
    fences: list[ImportedFence]
    total_length: float


class RunOut(_Open):
    run_id: str
    created_at: float
    command: str
    part_name: str | None
    action: str | None
    steps: int | None
    agreement: float | None
    cycle_time_s: float | None
    status: str
    error: dict[str, Any] | None
    job_id: str | None


class RunDetailOut(RunOut):
    record: dict[str, Any] | None = Field(description="the record's /run summary; null when damaged")
    record_error: str | None = None


class TrajectoryOut(_Open):
    """One simulated sample, thinned: lists of equal length; lengths in the part's unit."""

    sample: int
    t_s: list[float]
    phi_deg: list[float]
    gripper_angle_deg: list[float]
    x: list[float]
    y: list[float]
    lower_jaw: list[float]
    higher_jaw: list[float]


class PlaybackOut(_Open):
    """``GET /v1/runs/{id}/playback``: what a run recorded, for playing it back."""

    run_id: str
    part: dict[str, Any] = Field(description="the part document as the request gave it")
    options: dict[str, Any]
    plan: dict[str, Any] | None
    validation: dict[str, Any] | None
    trajectories: list[TrajectoryOut]


class ExampleOut(_Open):
    name: str
    kind: Literal["paper", "real"] = "paper"
    part: dict[str, Any]


class ExamplesOut(_Open):
    examples: list[ExampleOut]


class LayoutOut(_Open):
    """A Foxglove layout (its own format: panels by id and their arrangement)."""

    configById: dict[str, Any]  # noqa: N815 - Foxglove's field name
    layout: dict[str, Any] | str


class RunsOut(_Open):
    total: int
    limit: int
    offset: int
    runs: list[RunOut]


class HealthOut(_Open):
    status: Literal["ok"]
    version: str
    executor: str
    auth_required: bool = Field(description="the other endpoints need `Authorization: Bearer KEY`")


class ReadyOut(_Open):
    status: Literal["ready"]
    checks: dict[str, str]
    load: dict[str, int]


class JobCreatedOut(_Open):
    id: str
    state: str
    total: int
    ignored: list[str] = Field(default_factory=list, description="archive files that are not parts, and why")
    links: dict[str, str]


class JobsOut(_Open):
    jobs: list[dict[str, Any]]


ProgressOut = JobProgress
JobOut = JobDocument


class GripperSpecOut(_Open):
    """``GET /v1/jobs/{id}/gripper``: the catalogue's gripper specification (mm, s)."""

    parts: int
    oriented: int
    jaw_opening_mm: float | None
    jaw_length_mm: float | None
    push_stroke_mm: float | None
    max_cycle_time_s: float | None
    mean_cycle_time_s: float | None
    actions: dict[str, int]
    jaw_friction_max: float | None = None
    """The largest jaw–part friction every oriented part's plan holds with (None: none is
    limited up to μ 1)."""
    jaw_advice: str = ""
    not_oriented: list[dict[str, Any]]


class CancelOut(_Open):
    id: str
    state: Literal["cancelled"]


def ok(model: type[BaseModel], description: str = "success") -> dict[int | str, dict[str, Any]]:
    """The documented 200 response of an operation that builds its own Response."""
    return {200: {"model": model, "description": description}}


def _error(description: str) -> dict[str, Any]:
    return {"model": ErrorBody, "description": description}


ERRORS: dict[int | str, dict[str, Any]] = {
    401: _error("missing or wrong API key (only when keys are configured)"),
    413: _error("request body or archive too large"),
    422: _error("malformed request or part, not orientable, or past a time limit; `field` names the place"),
    429: _error("this client has too many requests in flight; see Retry-After"),
    500: _error("a bug: please report it with the request"),
    503: _error("queue full, worker lost or storage fault; see Retry-After"),
}
"""The error responses every operation may give (documented on each)."""

NOT_FOUND: dict[int | str, dict[str, Any]] = {404: _error("no such run or job"), 409: _error("the job already finished")}


def part_schema() -> dict[str, Any]:
    """The part document's JSON Schema (draft 2020-12, no references)."""
    return json_schema(PartDocument)


def typed(spec: dict[str, Any]) -> dict[str, Any]:
    """The OpenAPI document completed: the part document's components, and error
    responses as JSON on every operation (:func:`json_errors`)."""
    spec.setdefault("components", {}).setdefault("schemas", {}).update(components())

    def walk(x: Any) -> Any:
        if isinstance(x, dict):
            if x.get("x-algrasp") == "part-document":
                return {"$ref": "#/components/schemas/PartDocument", **{k: v for k, v in x.items()
                                                                        if k in ("description", "title")}}
            return {k: walk(v) for k, v in x.items()}
        return [walk(v) for v in x] if isinstance(x, list) else x

    return files(json_errors(walk(spec)))  # type: ignore[no-any-return]


BINARY = {"type": "string", "format": "binary"}
FILE_TYPES = ("image/svg+xml", "application/zip", "application/x-ndjson")
"""Success media types that clients generated from the contract read as files."""


def files(spec: dict[str, Any]) -> dict[str, Any]:
    """Uploads and downloads as files: an upload field (``contentMediaType``
    application/octet-stream) is ``format: binary``, and a success whose media type a
    generator cannot type (SVG, NDJSON, zip) is also offered as ``application/octet-stream``
    — the same bytes, which the server sends whatever the ``Accept``."""
    for schema in spec.get("components", {}).get("schemas", {}).values():
        for prop in schema.get("properties", {}).values():
            if prop.get("contentMediaType") == "application/octet-stream":
                prop["format"] = "binary"
    for ops in spec.get("paths", {}).values():
        for op in ops.values():
            for code, response in op.get("responses", {}).items():
                content = response.get("content", {})
                if code.startswith("2") and any(t in content for t in FILE_TYPES):
                    content.setdefault("application/octet-stream", {"schema": dict(BINARY)})
    return spec


def json_errors(spec: dict[str, Any]) -> dict[str, Any]:
    """Error responses are JSON on every operation, also where the success is SVG, text
    or a file (FastAPI files them under the success's media type)."""
    for ops in spec.get("paths", {}).values():
        for op in ops.values():
            for code, response in op.get("responses", {}).items():
                content = response.get("content", {})
                if code[0] in "45" and content and "application/json" not in content:
                    response["content"] = {"application/json": next(iter(content.values()))}
    return spec


IMPORTED: dict[int | str, dict[str, Any]] = {200: {"description": "the part document, or with list=true the sheet's parts "
                                                                  "(a fence layout DXF: its layout)",
                                                   "content": {"application/json": {"schema": {"anyOf": [
                                                       {"$ref": "#/components/schemas/PartDocument"},
                                                       {"$ref": "#/components/schemas/SheetOut"},
                                                       {"$ref": "#/components/schemas/FenceLayoutOut"}]}}}}}

PART_REF = {"type": "object", "x-algrasp": "part-document"}
"""Placeholder schema of a part-document field; :func:`typed` replaces it by a reference
to the ``PartDocument`` component (pydantic cannot emit a reference it does not own)."""


def components() -> dict[str, Any]:
    """Schemas the OpenAPI document needs beyond those FastAPI collects: the part document
    (with its segment types) and the sheet listing, as components."""
    out: dict[str, Any] = {}
    for model in (PartDocument, SheetOut, FenceLayoutOut):
        schema = model.model_json_schema(ref_template="#/components/schemas/{model}")
        out.update(schema.pop("$defs", {}))
        out[model.__name__] = schema
    return out


def media(description: str, types: dict[str, dict[str, Any]]) -> dict[int | str, dict[str, Any]]:
    """A documented 200 response in other media types (``{media type: schema}``)."""
    return {200: {"description": description, "content": {k: {"schema": v} for k, v in types.items()}}}
