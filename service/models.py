"""Request bodies of the HTTP API (pydantic): unknown fields are refused, every bound is
stated, so a malformed request gets a 422 naming the field before any work starts.
The part document itself is checked by the core parser (``algrasp.geometry.document``), whose
errors name the segment."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import Query
from pydantic import BaseModel, ConfigDict, Field, WithJsonSchema

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

    samples: int = Field(36, ge=1, description="initial orientations simulated")
    placement: Literal["centred", "random"] = Field("centred", description="centred: both jaws touch together")
    seed: int = Field(0, ge=0, le=2**32 - 1)
    tolerance_deg: float = Field(1.0, gt=0.0, le=180.0, description="agreement tolerance on the final orientation")


class PhysicsBody(_Strict):
    """The gripper and part physics of the dead band (conventions §7; defaults shared with
    the Drake simulation)."""

    support_friction: float = Field(0.3, ge=0.0, le=10.0, description="μ between part and support")
    part_mass_kg: float = Field(0.02, ge=0.0, le=1000.0)
    grip_force_n: float = Field(2.0, gt=0.0, le=1e5)
    gravity_m_s2: float = Field(9.81, ge=0.0, le=100.0)
    shape_tolerance: float | None = Field(None, ge=0.0, le=1e6,
                                          description="σ: slope error of the drawing, part units per radian "
                                                      "(default: derived from the drawing)")


class ModelOptions(_Strict):
    """Which model: robust (default) or the paper's exact frictionless one."""

    exact: bool = Field(False, description="the paper's exact frictionless model (no dead band)")
    physics: PhysicsBody | None = Field(None, description="dead-band physics (robust model)")

    def model_options(self) -> dict[str, Any]:
        return {"exact": self.exact, "physics": None if self.physics is None else self.physics.model_dump()}


class PlanBody(ModelOptions):
    """``POST /v1/plans``."""

    part: PartJson = Field(description="part document (conventions §5)")
    action: Literal["squeeze", "push_grasp"] = "squeeze"
    min_margin_deg: float = Field(0.0, ge=0.0, lt=180.0, description="every transition tolerates this gripper error")
    optimise: bool = Field(False, description="optimise push distances and jaw timing (adds cycle_time_s)")
    gripper: dict[str, Any] | None = Field(None, description="gripper profile (SI keys of optimisation/profiles/default.yaml)")
    validate_: ValidateOptions | None = Field(None, alias="validate", description="simulate the plan in Drake")

    def request(self) -> dict[str, Any]:
        """Keyword arguments of :class:`algrasp.pipeline.PlanRequest`."""
        out: dict[str, Any] = {"action": self.action, "min_margin_deg": self.min_margin_deg, "optimise": self.optimise,
                               "gripper_profile": self.gripper, **self.model_options()}
        if self.validate_ is not None:
            out.update(self.validate_.model_dump())
        return out


class JobOptions(ModelOptions):
    """Options applied to every part of a job."""

    min_margin_deg: float = Field(0.0, ge=0.0, lt=180.0)
    validate_: ValidateOptions | None = Field(None, alias="validate")
    gripper: dict[str, Any] | None = None

    def design(self) -> dict[str, Any]:
        """Keyword arguments of :class:`service.fixture.DesignOptions`."""
        out: dict[str, Any] = {"min_margin_deg": self.min_margin_deg, "gripper_profile": self.gripper,
                               **self.model_options()}
        if self.validate_ is not None:
            v = self.validate_
            out.update(samples=v.samples, seed=v.seed, placement=v.placement)
        return out


class JobBody(_Strict):
    """``POST /v1/jobs`` as JSON: the part documents and the options."""

    parts: list[PartJson] = Field(min_length=1, description="part documents")
    options: JobOptions = Field(default_factory=JobOptions)  # type: ignore[arg-type]
