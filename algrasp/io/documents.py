"""Every document algrasp reads or writes, typed once (docs/conventions.md §4–§8).

These pydantic models are the single source of the documents' shapes: the JSON schemas of
the run records' channels (:mod:`algrasp.io.record.schemas`), the HTTP contract
(:mod:`service.contract` derives its responses from them) and the published schemas
(``/v1/schemas/{name}``, ``algrasp/schemas/part.schema.json``) all come from here. The core
still parses and writes the documents with its own codecs (``algrasp.geometry.document``,
``algrasp.planning.documents``), whose errors name the field; a test holds each codec's
output to its model here.

Input documents (the part) forbid unknown fields; output documents name the fields they
guarantee and may carry more (a documented superset), so a newer writer stays readable.

>>> sorted(DOCUMENTS)[:4]
['analysis', 'error', 'fences', 'job']
>>> json_schema(PlanDocument)["properties"]["action"]["enum"]
['squeeze', 'push_grasp']
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field

from algrasp.geometry.limits import DEFAULT_LIMITS
from algrasp.planning.actions import Action

Point = Annotated[list[float], Field(min_length=2, max_length=2, description="[x, y] in the part's unit")]
Number = float
Interval = Annotated[list[float], Field(min_length=2, max_length=2, description="[start, end] in degrees")]


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")


class Open(BaseModel):
    """A written document: the fields named are guaranteed, others may be added."""

    model_config = ConfigDict(extra="allow")


# ------------------------------------------------------------------ the part (§5)
class LineSegment(_Strict):
    type: Literal["line"]
    start: Point
    end: Point


class ArcSegment(_Strict):
    """Circular arc from ``start_deg`` to ``end_deg`` (counter-clockwise when end > start;
    at most 360° of sweep)."""

    type: Literal["arc"]
    center: Point
    radius: float = Field(gt=0)
    start_deg: float
    end_deg: float


class EllipseArcSegment(_Strict):
    """``center + R(rotation_deg)·(rx cos t, ry sin t)`` for t from ``start_deg`` to ``end_deg``."""

    type: Literal["ellipse_arc"]
    center: Point
    rx: float = Field(gt=0)
    ry: float = Field(gt=0)
    rotation_deg: float = 0.0
    start_deg: float
    end_deg: float


class BezierSegment(_Strict):
    """Bezier curve of degree len(points) − 1 (at most ``Limits.max_bezier_degree``);
    ``weights`` make it rational."""

    type: Literal["bezier"]
    points: list[Point] = Field(min_length=2, max_length=DEFAULT_LIMITS.max_bezier_degree + 1)
    weights: list[Annotated[float, Field(gt=0)]] | None = None


Segment = Annotated[LineSegment | ArcSegment | EllipseArcSegment | BezierSegment, Field(discriminator="type")]
Loop = Annotated[list[Segment | Point], Field(min_length=1, description="segments in order, or polygon vertices "
                                                                       "(one kind per loop)")]


class PartDocument(_Strict):
    """A planar part: one closed ``boundary`` (or the ``polygon`` shorthand), optional
    holes and centre of mass."""

    name: str | None = None
    units: str = "mm"
    boundary: Loop | None = None
    polygon: list[Point] | None = Field(None, min_length=3)
    holes: list[Loop] = Field(default_factory=list)
    center_of_mass: Point | None = None
    approximate: bool | None = Field(None, description="set by mesh imports: the outline is a polygon approximation")
    source: dict[str, Any] | None = Field(None, description="where an imported part came from (file, layer, warnings)")


# ------------------------------------------------------------------ analysis (§3)
class Extremum(Open):
    theta_deg: float
    value: float
    kind: Literal["min", "max"]


class FunctionDoc(Open):
    """d(θ) or r(θ): extrema and constant intervals (degrees, part units)."""

    extrema: list[Extremum]
    constant_intervals_deg: list[Interval]


class TransferStep(Open):
    start_deg: float
    end_deg: float
    fixed_point_deg: float


class TransferDoc(Open):
    """A transfer function: steps ``[start, end)`` mapped to their fixed point, and ramps."""

    period_deg: float
    symmetry_period_deg: float
    steps: list[TransferStep]
    ramps: list[dict[str, float]]
    orientable: bool


class AnalysisDocument(Open):
    """``algrasp analyze --json``, ``POST /v1/analyses``, records' ``/analysis``."""

    part: dict[str, Any] = Field(description="summary: area, hull perimeter, centre of mass (part units)")
    diameter: FunctionDoc
    radius: FunctionDoc
    squeeze: TransferDoc
    push: TransferDoc
    push_grasp: TransferDoc
    model: str | None = Field(None, description="robust or exact")
    robust: dict[str, Any] | None = Field(None, description="the set-valued functions and the physics ranges (§7, §8)")


# ------------------------------------------------------------------ plans (§4, §6)
class PlanStep(Open):
    gripper_angle_deg: float = Field(description="gripper angle in the world frame, [0, 360)")
    margin_deg: float | None = Field(description="gripper error this transition tolerates (None: the first action)")
    push_distance: float | None = Field(None, description="push-grasp with optimise: push length (part units)")
    push_distance_bound: float | None = Field(None, description="push-grasp with optimise: the closed-form bound")
    duration_s: float | None = Field(None, description="with optimise: the action's duration")
    trajectory: dict[str, Any] | None = Field(None, description="with optimise: the jaws' planned motion")
    image_deg: list[Interval] | None = Field(None, description="world arcs [lo, hi] the part can be in after this "
                                             "action, from any start (the plan's own images)")


class PlanDocument(Open):
    """The plan, with its execution when optimised (``cycle_time_s``, ``units``,
    ``gripper_profile``, per-step durations)."""

    action: Action
    symmetry_period_deg: float
    intervals_deg: list[Interval] = Field(description="Θ intervals of Algorithm A′, last to first")
    steps: list[PlanStep] = Field(min_length=1)
    final_orientations_deg: list[float]
    final_uncertainty_deg: float = 0.0
    model: str = Field("exact", description="robust or exact")
    verified: bool
    dead_band: dict[str, Any] | None = None
    limits: dict[str, Any] | None = Field(None, description="how far each physics range may go (§8)")
    images: dict[str, Any] | None = Field(None, description="the action's map: period_deg and pieces [start, end, "
                                          "lower, upper] (gripper frame, deg; null: θ itself), robust bounds when robust")
    timings_s: dict[str, float] = Field(default_factory=dict)
    cycle_time_s: float | None = Field(None, description="with optimise")


# ------------------------------------------------------------------ conveyor fences (§9)
class Fence(Open):
    """One fence of a layout, in the order the part meets it."""

    side: Literal["left", "right"] = Field(description="the rail it stands on, looking downstream (+x): right is y = 0")
    angle_deg: float = Field(description="world angle α of the wall, (0, 180): the lower jaw's angle (§2)")
    position: float = Field(description="its root on the rail, along the belt from the first fence's root (part units)")
    length: float = Field(gt=0, description="along the wall (part units)")
    steepness_deg: float | None = Field(None, description="β: its angle to the belt direction")
    margin_deg: float | None = Field(None, description="how far the angle may be off, the others as designed")
    push_distance_bound: float | None = Field(None, description="Peshkin's push distance along its normal (part units)")
    reach: float | None = Field(None, description="its extent across the belt from its rail (part units)")


class ExitGuideDoc(Open):
    """The exit guide: a straight wall from the last fence's tip (or its tail's end) at a
    small steepness, on the same rail (conventions §9)."""

    side: Literal["left", "right"]
    angle_deg: float
    steepness_deg: float = Field(gt=0, description="β_e: its angle to the belt; the claim is ±β_e/2 wider")
    length: float = Field(gt=0, description="along the wall (part units): push_distance_bound · cot β_e")
    start: list[float] = Field(min_length=2, max_length=2, description="(x, y) where it leaves the fence (part units)")
    end: list[float] = Field(min_length=2, max_length=2, description="(x, y) of its downstream end")
    push_distance_bound: float
    image_deg: list[list[float]] | None = Field(None, description="world arcs [lo, hi] the part can be in past it, "
                                                "from any start (what a page animates)")


class FenceDocument(Open):
    """``algrasp fences --json`` and ``POST /v1/fences``: a fence design laid out on a belt
    moving along world +x (lengths in ``units``)."""

    units: str
    model: Literal["exact", "robust"]
    belt_width: float = Field(gt=0, description="between the side rails (part units)")
    fence_friction: list[float] = Field(min_length=2, max_length=2, description="μ_f range the angles hold for")
    exit_turns: bool | None = Field(None, description="whether the design models the turn a part takes over each "
                                    "fence's tip (false: Berretty et al.'s model)")
    same_rail: bool | None = Field(None, description="whether consecutive fences may stand on one rail (false: they "
                                   "alternate)")
    fences: list[Fence] = Field(min_length=1)
    total_length: float
    symmetry_period_deg: float
    final_orientations_deg: list[float] = Field(description="world orientations the part leaves the layout in (past "
                                                "the exit guide), [0, 360)")
    final_uncertainty_deg: float
    last_fence_orientations_deg: list[float] | None = Field(None, description="its orientations on the last fence")
    last_fence_uncertainty_deg: float | None = None
    exit: ExitGuideDoc | None = Field(None, description="the exit guide on the last fence's rail (null: none holds)")
    follow_deg: list[list[list[float]]] | None = Field(None, description="per whole-degree start 0…359: the world arc "
                                                       "[lo, hi] it is in after each fence and past the exit guide "
                                                       "(what a page animates one start with; not in batch results)")


class FenceValidationSample(Open):
    initial_deg: float
    lateral: float = Field(description="the start's distance from the first fence's rail (part units)")
    simulated_deg: float
    error_deg: float = Field(description="from the nearest claimed final orientation, modulo the symmetry period")
    agrees: bool
    on_last_fence_deg: float | None = None


class FenceValidationDocument(Open):
    """``algrasp fences --validate`` and ``POST /v1/fences`` with ``validate``: the design
    simulated on a belt in Drake (conventions §9)."""

    samples: list[FenceValidationSample]
    agreement: float
    agreement_on_last_fence: float
    tolerance_deg: float
    final_orientations_deg: list[float]
    belt_speed_m_s: float
    support_friction: float
    fence_friction: float


# ------------------------------------------------------------------ validation (Drake)
class ValidationSample(Open):
    initial_deg: float
    predicted_deg: float
    simulated_deg: float
    agrees: bool
    near_unstable: bool | None = None
    offset_mm: float | None = None
    pushed_deg: float | None = None
    push_predicted_deg: float | None = None
    push_agrees: bool | None = None


class ValidationDocument(Open):
    """Simulated outcomes of a plan; the HTTP and CLI forms embed the plan under ``plan``,
    the record keeps it on ``/plan`` only."""

    samples: list[ValidationSample]
    agreement: float
    agreement_clear: float
    push_agreement: float | None = None
    tolerance_deg: float
    placement: Literal["centred", "random"]
    sim_seconds: float
    wall_seconds: float
    model: dict[str, Any] | None = None
    cells: list[dict[str, Any]] | None = Field(None, description="per simulated cell of the physics ranges")


# ------------------------------------------------------------------ runs, jobs, errors
Command = Literal["analyze", "plan", "validate", "service", "batch", "design", "fences"]


class ErrorDetail(Open):
    """What went wrong: ``type`` (``part_document_error``, ``config_error``,
    ``limit_exceeded``, ``not_orientable``, ``time_limit_exceeded``, ``unavailable``,
    ``storage_error``, ``too_many_requests``, ``unauthorized``, ``not_found``, …) and the
    typed fields of that error."""

    type: str
    message: str
    field: str | None = None
    segment_index: int | None = None
    reason: str | None = None
    retry_after_s: float | None = None
    stage: str | None = None
    limit_s: float | None = None
    errors: list[dict[str, Any]] | None = None


class ErrorBody(BaseModel):
    """Every error response and CLI error: ``{"error": {...}}``."""

    error: ErrorDetail


class RequestDocument(Open):
    """A record's ``/request``: the part as given (also a malformed one: failed runs are
    recorded) and the options."""

    run_id: str
    command: Command
    part: dict[str, Any]
    options: dict[str, Any]


class RunSummary(Open):
    """A record's ``/run``, written last: how the run ended."""

    run_id: str
    command: str
    status: Literal["ok", "error"]
    error: ErrorDetail | None = None
    started_unix_s: float
    part_name: str | None = None
    action: str | None = None
    steps: int | None = None
    agreement: float | None = None
    cycle_time_s: float | None = None
    timings_s: dict[str, float]
    versions: dict[str, str]


class SimState(Open):
    """A record's ``/sim/state``: one simulated instant (SI lengths)."""

    sample: int
    t_s: float
    x_m: float
    y_m: float
    phi_deg: float
    gripper_angle_deg: float
    lower_jaw_m: float
    higher_jaw_m: float


class JobProgress(Open):
    finished: int = Field(description="parts done, failed or cancelled")
    total: int


class JobDocument(Open):
    """A batch job's state (``GET /v1/jobs/{id}``)."""

    id: str
    state: str
    total: int
    done: int
    failed: int
    cancelled: int
    pending: int
    parts: list[dict[str, Any]]
    progress: JobProgress


DOCUMENTS: dict[str, type[BaseModel]] = {
    "part": PartDocument, "analysis": AnalysisDocument, "plan": PlanDocument, "validation": ValidationDocument,
    "request": RequestDocument, "run": RunSummary, "job": JobDocument, "error": ErrorBody, "sim-state": SimState,
    "fences": FenceDocument,
}
"""The published documents by name (``/v1/schemas/{name}``)."""


def inline(schema: dict[str, Any]) -> dict[str, Any]:
    """A JSON Schema with its ``$defs`` references replaced by the definitions (for
    readers, like MCAP viewers, that resolve no references)."""
    defs = schema.pop("$defs", {})

    def walk(x: Any) -> Any:
        if isinstance(x, dict):
            if "$ref" in x and x["$ref"].startswith("#/$defs/"):
                return walk(defs[x["$ref"].rsplit("/", 1)[-1]])
            return {k: walk(v) for k, v in x.items()}
        return [walk(v) for v in x] if isinstance(x, list) else x

    return walk(schema)  # type: ignore[no-any-return]


def json_schema(model: type[BaseModel]) -> dict[str, Any]:
    """The model's JSON Schema, draft 2020-12, references inlined."""
    return {"$schema": "https://json-schema.org/draft/2020-12/schema", **inline(model.model_json_schema())}
