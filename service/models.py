"""Request bodies of the HTTP API (pydantic): unknown fields are refused, every bound is
stated, so a malformed request gets a 422 naming the field before any work starts.
The part document itself is checked by the core parser (``algrasp.geometry.document``), whose
errors name the segment."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import Query
from pydantic import (
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    ValidationInfo,
    WithJsonSchema,
    field_validator,
    model_validator,
)

from algrasp.errors import ConfigError
from algrasp.planning.actions import ALIASES, Action
from algrasp.planning.cells import parse_cells
from algrasp.planning.physics import DEFAULT_PHYSICS, DEFAULT_RANGES, PARAMETERS, Physics
from service.contract import PART_REF

PartJson = Annotated[dict[str, Any], WithJsonSchema(PART_REF)]
"""A part document: validated by the core parser (errors name the segment), described in
the OpenAPI schema by :class:`service.contract.PartDocument` (a component)."""

LIMIT = Query(50, ge=1, le=1000, description="page size")
OFFSET = Query(0, ge=0, le=1_000_000_000, description="rows to skip")


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", populate_by_name=True)


class ValidateOptions(_Strict):
    """Drake validation of the plan (``samples`` also bounded by ``ALGRASP_MAX_SAMPLES``)."""

    samples: int = Field(36, ge=1, description="initial orientations simulated (per cell)")
    placement: Literal["centred", "random"] | None = Field(
        None, description="centred: both jaws touch together; random: offset between the jaws (default: as the "
                          "physics' placement says)")
    seed: int = Field(0, ge=0, le=2**32 - 1)
    tolerance_deg: float = Field(1.0, gt=0.0, le=180.0, description="agreement tolerance on the final orientation")
    sim_physics: str = Field("nominal", max_length=400,
                             description="cells of the physics ranges to simulate: nominal, corners, random, or "
                                         "KEY=VALUE,... (e.g. support_friction=0.05,jaw_friction=0.2,com_offset=0.5,0)")

    @field_validator("sim_physics")
    @classmethod
    def _cells(cls, v: str) -> str:
        try:
            parse_cells(v)
        except ConfigError as e:
            raise ValueError(e.message) from None
        return v


Range = float | Annotated[list[float], Field(min_length=1, max_length=2)]
BeltWidth = Annotated[float | None, Field(gt=0.0, le=1e9)]
"""A belt width between the rails (part units), where a fence design is asked for."""
FenceMarginDeg = Annotated[float, Field(ge=0.0, lt=45.0)]
"""How far every fence angle may be off (degrees; :func:`algrasp.planning.fences.check_min_margin`)."""
ExitSteepnessDeg = Annotated[float | None, Field(gt=0.0, le=10.0)]
"""The exit guide's angle to the belt (degrees; :func:`algrasp.planning.fence_exit.exit_steepness`)."""


def _range_field(key: str) -> Any:
    p = PARAMETERS[key]
    lo, hi = DEFAULT_RANGES[key]
    return Field(None, description=f"{p.help}{' (' + p.unit + ')' if p.unit else ''}: one value or [lo, hi] "
                                   f"(default [{lo:g}, {hi:g}]: {p.source})")


class PhysicsBody(_Strict):
    """The cell's physics as ranges (conventions §8), each key over the service's cell
    (``ALGRASP_CELL``, default the real-cell defaults); checked by the core's one options
    type (:class:`algrasp.planning.physics.Physics`)."""

    support_friction: Range | None = _range_field("support_friction")
    jaw_friction: Range | None = _range_field("jaw_friction")
    part_mass_kg: Range | None = _range_field("part_mass_kg")
    grip_force_n: Range | None = _range_field("grip_force_n")
    gravity_m_s2: Range | None = _range_field("gravity_m_s2")
    com_tolerance: float | None = Field(None, ge=0.0, le=1e6, description="radius of the centre-of-mass disk, part "
                                        "units (default 1 % of the part's size)")
    shape_tolerance: float | None = Field(None, ge=0.0, le=1e6,
                                          description="σ: slope error of the drawing, part units per radian "
                                                      "(default: derived from the drawing, never below the profile tolerance)")
    profile_tolerance: float | None = Field(None, ge=0.0, le=1e6, description="manufacturing profile tolerance, part "
                                            "units (default ISO 2768-1 class f for the part's size)")
    placement: Literal["centred", "any"] | None = Field(None, description="centred: both jaws touch together; any: "
                                                        "any offset between the jaws (default any)")

    @model_validator(mode="after")
    def _physics(self) -> PhysicsBody:
        try:
            Physics.from_mapping(self.given())
        except ConfigError as e:
            raise ValueError(e.message) from None
        return self

    def given(self) -> dict[str, Any]:
        return self.model_dump(exclude_none=True)


class ModelOptions(_Strict):
    """Which model: robust (default) or the paper's exact frictionless one."""

    exact: bool = Field(False, description="the paper's exact frictionless model (no dead band)")
    physics: PhysicsBody | None = Field(None, description="the cell's physics ranges (robust model)")
    limits: bool = Field(False, description="search every physics limit (the largest jaw friction is always given)")

    def model_options(self, cell: Physics = DEFAULT_PHYSICS) -> dict[str, Any]:
        """The exact flag and the whole physics: the request's keys over the service's cell."""
        return {"exact": self.exact, "physics": cell.merged(None if self.physics is None else self.physics.given()).to_dict()}


ActionName = Annotated[Action, BeforeValidator(lambda v: ALIASES.get(v, v) if isinstance(v, str) else v)]
"""An action in a request: the one spelling, the other accepted (:mod:`algrasp.planning.actions`)."""


class PlanBody(ModelOptions):
    """``POST /v1/plans``."""

    part: PartJson = Field(description="part document (conventions §5)")
    action: ActionName = Field("squeeze", description="squeeze or push_grasp (push-grasp is read as push_grasp)")
    min_margin_deg: float = Field(0.0, ge=0.0, lt=180.0, description="every transition tolerates this gripper error")
    optimise: bool = Field(False, description="optimise push distances and jaw timing (adds cycle_time_s)")
    gripper: dict[str, Any] | None = Field(None, description="gripper profile (SI keys of optimisation/profiles/default.yaml)")
    validate_: ValidateOptions | None = Field(None, alias="validate", description="simulate the plan in Drake")

    def request(self, cell: Physics = DEFAULT_PHYSICS) -> dict[str, Any]:
        """Keyword arguments of :class:`algrasp.pipeline.PlanRequest` (physics over ``cell``)."""
        out: dict[str, Any] = {"action": self.action, "min_margin_deg": self.min_margin_deg, "optimise": self.optimise,
                               "gripper_profile": self.gripper, **self.model_options(cell),
                               "limits": "all" if self.limits else "headline"}
        if self.validate_ is not None:
            out.update(self.validate_.model_dump())
        return out


def _fence_friction(v: Range | None) -> Range | None:
    """A fence friction range as the core's rules take it (``ValueError`` naming the problem)."""
    from algrasp.planning.fences import fence_rules

    if v is not None:
        try:
            fence_rules(v)
        except ConfigError as e:
            raise ValueError(e.problem) from None
    return v


class TailOptions(_Strict):
    """The last fence's curved tail (conventions §9)."""

    radius: float = Field(gt=0.0, le=1e9, description="of the arc, part units")
    sweep_deg: float | None = Field(None, gt=0.0, lt=90.0, description="its turn towards the belt (default the last "
                                    "fence's angle to the belt less the exit guide's: it ends tangent to the guide)")


class FenceValidateOptions(_Strict):
    """Drake validation of the fence design on a belt (``samples`` also bounded by ``ALGRASP_MAX_SAMPLES``)."""

    samples: int = Field(3, ge=1, description="seeded random starts (orientation and lateral position)")
    seed: int = Field(0, ge=0, le=2**32 - 1)


class FencesBody(ModelOptions):
    """``POST /v1/fences``: the part and the fence rules (conventions §9)."""

    part: PartJson = Field(description="part document (conventions §5)")
    fence_friction: Range | None = Field(None, description="part–fence friction μ_f: one value or [lo, hi] "
                                         "(default [0.1, 0.3]: UHMW-PE guide rails on dry parts)")
    belt_width: BeltWidth = Field(None, description="between the rails, part units "
                                     "(default: the least the design needs)")
    min_margin_deg: FenceMarginDeg = Field(1.0, description="every fence angle may be off by this much")
    drawing: Literal["svg", "dxf"] | None = Field(None, description="answer the drawing of the belt and fences "
                                                   "(image/svg+xml or application/dxf, part units) instead of the document")
    tail: TailOptions | None = Field(None, description="a curved tail on the last fence")
    exit_steepness_deg: ExitSteepnessDeg = Field(None, description="the exit guide's angle to the belt "
                                             "(default 2°): the claim past it is ±β_e/2 wider")
    exit_turns: bool = Field(True, description="model the turn a part takes over each fence's tip (false: Berretty "
                             "et al.'s model, the part keeps its orientation between fences)")
    same_rail: bool = Field(False, description="let consecutive fences stand on one rail (the later reaching further "
                            "across the belt); false: they alternate rails")
    validate_: FenceValidateOptions | None = Field(None, alias="validate", description="simulate the design on a belt "
                                                   "in Drake (the document's validation)")

    @field_validator("fence_friction")
    @classmethod
    def _friction(cls, v: Range | None) -> Range | None:
        return _fence_friction(v)

    def options(self, cell: Physics = DEFAULT_PHYSICS) -> dict[str, Any]:
        """Keyword arguments of ``algrasp.api.fences`` but the part (physics over ``cell``)."""
        model = self.model_options(cell)
        return {"fence_friction": self.fence_friction, "belt_width": self.belt_width,
                "min_margin_deg": self.min_margin_deg, "exact": model["exact"], "physics": model["physics"],
                "tail": None if self.tail is None else self.tail.model_dump(),
                "exit_steepness_deg": self.exit_steepness_deg, "exit_turns": self.exit_turns,
                "same_rail": self.same_rail}


class JobOptions(ModelOptions):
    """Options applied to every part of a job."""

    min_margin_deg: float = Field(0.0, ge=0.0, lt=180.0)
    validate_: ValidateOptions | None = Field(None, alias="validate")
    gripper: dict[str, Any] | None = None
    fences: bool = Field(False, description="also design conveyor fences for every part (conventions §9)")
    fence_friction: Range | None = Field(None, description="with fences: part–fence friction μ_f, one value or [lo, hi]")
    belt_width: BeltWidth = Field(None, description="with fences: between the rails, in each "
                                     "part's unit (default: the least each design needs)")
    fence_min_margin_deg: FenceMarginDeg | None = Field(None, description="with fences: every fence angle "
                                               "may be off by this much (default min_margin_deg, at least 1°)")
    exit_steepness_deg: ExitSteepnessDeg = Field(None, description="with fences: the exit guide's "
                                             "angle to the belt (default 2°)")
    exit_turns: bool = Field(True, description="with fences: model the turn a part takes over each fence's tip "
                             "(false: Berretty et al.'s model)")
    same_rail: bool = Field(False, description="with fences: let consecutive fences stand on one rail (false: they "
                            "alternate rails)")

    @field_validator("fence_friction")
    @classmethod
    def _friction(cls, v: Range | None) -> Range | None:
        return _fence_friction(v)

    @field_validator("fence_friction", "belt_width", "fence_min_margin_deg", "exit_steepness_deg", "exit_turns",
                     "same_rail")
    @classmethod
    def _needs_fences(cls, v: Any, info: ValidationInfo) -> Any:
        """A fence option given (not its default) without ``fences``: refused, named."""
        if not info.data.get("fences") and v != cls.model_fields[str(info.field_name)].default:
            raise ValueError("needs fences true (it describes the belt and its fences)")
        return v

    def design(self, cell: Physics = DEFAULT_PHYSICS) -> dict[str, Any]:
        """Keyword arguments of :class:`service.fixture.DesignOptions` (physics over ``cell``)."""
        friction = [self.fence_friction] if isinstance(self.fence_friction, (int, float)) else self.fence_friction
        out: dict[str, Any] = {"min_margin_deg": self.min_margin_deg, "gripper_profile": self.gripper,
                               **self.model_options(cell), "fences": self.fences, "fence_friction": friction,
                               "belt_width": self.belt_width, "fence_min_margin_deg": self.fence_min_margin_deg,
                               "exit_steepness_deg": self.exit_steepness_deg, "exit_turns": self.exit_turns,
                               "same_rail": self.same_rail, "limits": "all" if self.limits else "headline"}
        if self.validate_ is not None:
            v = self.validate_
            out.update(samples=v.samples, seed=v.seed, placement=v.placement, sim_physics=v.sim_physics)
        return out


class JobBody(_Strict):
    """``POST /v1/jobs`` as JSON: the part documents and the options."""

    parts: list[PartJson] = Field(min_length=1, description="part documents")
    options: JobOptions = Field(default_factory=JobOptions)  # type: ignore[arg-type]
