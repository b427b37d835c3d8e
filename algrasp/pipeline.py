"""One plan request end to end — analyse, plan, optimise, validate, record — shared by the
CLI, the HTTP service and batch jobs so the three compute and record the same thing.

A shell module: it calls the pure core, the CasADi optimiser and (only when a
validation is asked for) the Drake simulation, each imported lazily.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Any, Literal

from algrasp.errors import ConfigError
from algrasp.planning.actions import Action
from algrasp.planning.analysis import Analysis, Model, analyse_document
from algrasp.planning.plans import LIMITS_WANTED, LimitsWanted, Plan, make_plan


@dataclass(frozen=True)
class PlanRequest:
    """What to compute for one part. ``samples`` 0: no validation; ``gripper_profile``
    None: the default profile (only used with ``optimise``)."""

    action: Action = "squeeze"
    min_margin_deg: float = 0.0
    optimise: bool = False
    gripper_profile: dict[str, Any] | None = None
    push_scale: float = 1.0
    samples: int = 0
    seed: int = 0
    placement: Literal["centred", "random"] | None = None
    """Simulated placement; None follows the physics (``any`` → random offsets)."""
    tolerance_deg: float = 1.0
    exact: bool = False
    physics: dict[str, Any] | None = None
    limits: LimitsWanted = "headline"
    sim_physics: str = "nominal"
    """Which cells of the ranges validation simulates (:func:`algrasp.sim.cells.sim_cells`)."""

    def __post_init__(self) -> None:
        """The one place a request's options are checked (CLI, HTTP, batch and API build
        a PlanRequest before any work)."""
        if self.gripper_profile is not None:
            if not self.optimise:
                raise ConfigError("gripper", "a gripper profile needs optimise")
            from optimisation.profile import profile_from_dict

            profile_from_dict(self.gripper_profile, "gripper")
        if not 0.0 < self.push_scale <= 10.0:
            raise ConfigError("push_scale", f"must be in (0, 10], got {self.push_scale}")
        if self.samples < 0:
            raise ConfigError("samples", f"must be ≥ 0, got {self.samples}")
        if self.placement not in (None, "centred", "random"):
            raise ConfigError("placement", f"expected centred, random or None, got {self.placement!r}")
        if not 0.0 < self.tolerance_deg < 180.0:
            raise ConfigError("tolerance_deg", f"must be in (0, 180) degrees, got {self.tolerance_deg}")
        if self.limits not in LIMITS_WANTED:
            raise ConfigError("limits", f"expected one of {', '.join(LIMITS_WANTED)}, got {self.limits!r}")
        _ = self.model  # the physics are checked here, before any work
        from algrasp.planning.cells import parse_cells

        parse_cells(self.sim_physics)

    @property
    def sim_placement(self) -> Literal["centred", "random"]:
        if self.placement is not None:
            return self.placement
        return "random" if not self.exact and self.model.physics.placement == "any" else "centred"

    @cached_property
    def model(self) -> Model:
        """The model of these options, built once (a request passes through the shell as
        this object: the service's worker gets it pickled with its model)."""
        return Model.from_options({"exact": self.exact, "physics": self.physics})

    def record_options(self) -> dict[str, Any]:
        """The options a run record keeps (what replay needs to recompute the run)."""
        out: dict[str, Any] = {"action": self.action, "min_margin_deg": self.min_margin_deg, "optimise": self.optimise,
                               **self.model.to_options(), "limits": "none" if self.exact else self.limits}
        if self.gripper_profile is not None:
            out["gripper_profile"] = self.gripper_profile
        if self.samples:
            out.update(samples=self.samples, seed=self.seed, placement=self.sim_placement, tolerance_deg=self.tolerance_deg,
                       push_scale=self.push_scale, sim_physics=self.sim_physics)
        return out


@dataclass
class PlanOutcome:
    """Everything one request computed; ``plan_doc`` is the plan document (optimised
    fields included), ``validation`` the Drake validation or None."""

    analysis: Analysis
    plan: Plan
    execution: Any = None
    validation: Any = None
    plan_doc: dict[str, Any] = field(default_factory=dict)

    def validation_doc(self, with_plan: bool = True) -> dict[str, Any] | None:
        """The validation document; ``with_plan`` False leaves the plan out (the record
        and the HTTP response carry it beside, not inside)."""
        if self.validation is None:
            return None
        doc: dict[str, Any] = self.validation.to_dict(self.plan_doc) if with_plan else self.validation.to_dict(with_plan=False)
        return doc


WARM_UP_PART: dict[str, Any] = {"name": "warm-up", "boundary": [
    {"type": "line", "start": [0.0, 0.0], "end": [3.0, 0.0]}, {"type": "line", "start": [3.0, 0.0], "end": [1.0, 2.0]},
    {"type": "line", "start": [1.0, 2.0], "end": [0.0, 0.0]}]}
"""A 3 × 2 triangle: its robust analysis and push-grasp plan take the paths of every
plan request."""


def warm_up() -> None:
    """Analyse and plan :data:`WARM_UP_PART` once, so that a new worker's first request
    pays no first-use costs (lazy imports, numpy's first calls). ~20–50 ms."""
    import algrasp.planning.limits  # noqa: F401  (a refusal's searches)

    make_plan(analyse_document(WARM_UP_PART), "push_grasp")


def plan_part(doc: dict[str, Any], req: PlanRequest, rec: Any, sim_workers: int = 2, record_sim: bool = True,
              analysis: Analysis | None = None, plan: Plan | None = None) -> PlanOutcome:
    """Analyse, plan, optionally optimise and validate one part document; feed ``rec``
    (a :class:`~algrasp.io.record.session.Recording`) with every result as it comes.
    ``analysis``/``plan``: work the caller has already done for this document and
    request (a batch part compares both actions first), so nothing is computed twice."""
    t0 = time.perf_counter()
    analysis = analysis if analysis is not None else analyse_document(doc, req.model)
    rec.analysis(analysis.to_dict())
    t1 = time.perf_counter()
    plan = plan if plan is not None else make_plan(analysis, req.action, req.min_margin_deg,
                                                   "none" if req.model.exact else req.limits)
    plan = replace(plan, timings_s={"analysis": t1 - t0, **plan.timings_s})
    if req.optimise and plan.execution is None:
        plan = optimise_plan(plan, req.gripper_profile, req.push_scale)
    out = PlanOutcome(analysis, plan, plan.execution)
    out.plan_doc = plan.to_dict()
    rec.plan(out.plan_doc)
    if req.samples:
        out.validation = _validate(out, req, sim_workers, record_sim)
        _record_validation(rec, out)
    else:
        _record_plan_scene(rec, out)
    return out


def optimise_plan(plan: Plan, gripper_profile: dict[str, Any] | None = None, push_scale: float = 1.0) -> Plan:
    """``plan`` with its execution optimised (CasADi: push distances, jaw timing, cycle
    time) for the gripper profile (None: the default profile); the plan's own analysis."""
    from optimisation.execution import optimise_execution
    from optimisation.profile import DEFAULT_PROFILE, profile_from_dict

    if plan.analysis is None:
        raise ConfigError("plan", "this plan has no analysis to optimise against: make it with algrasp.plan()")
    profile = DEFAULT_PROFILE if gripper_profile is None else profile_from_dict(gripper_profile, "gripper")
    execution = optimise_execution(plan.analysis, plan, profile, push_scale)
    return replace(plan, execution=execution,
                   timings_s={**plan.timings_s, **{f"optimisation_{k}": v for k, v in execution.timings_s.items()}})


def _validate(out: PlanOutcome, req: PlanRequest, sim_workers: int, record_sim: bool) -> Any:
    try:
        from algrasp.sim.config import execution_config, execution_schedule, sim_config
    except ImportError:  # pragma: no cover - drake is an optional extra
        raise ConfigError("validate", "validation needs Drake: pip install 'algrasp[sim]'") from None
    from algrasp.planning.cells import parse_cells, sim_cells
    from algrasp.sim.validate import validate_cells

    ex = out.execution
    base = sim_config(req.model.physics)
    sim = {"cfg": base} if ex is None else {"sim_schedule": execution_schedule(ex), "cfg": execution_config(ex, base)}
    band = out.analysis.robust.band if out.analysis.robust is not None else None
    cells = sim_cells(parse_cells(req.sim_physics), req.model.physics, 0.0 if band is None else band.com_tolerance,
                      req.samples, req.seed)
    if req.sim_physics == "random":  # one sample in each of ``samples`` random cells
        return validate_cells(out.analysis, out.plan, cells, 1, req.seed, req.sim_placement, req.tolerance_deg,
                              workers=sim_workers, record=record_sim, **sim)
    return validate_cells(out.analysis, out.plan, cells, req.samples, req.seed, req.sim_placement, req.tolerance_deg,
                          workers=sim_workers, record=record_sim, **sim)


def _record_plan_scene(rec: Any, out: PlanOutcome) -> None:
    """A plan-only record's Foxglove scene: the part at each action's outcome between the jaws."""
    if not getattr(rec, "record_path", None):
        return  # recording off: nothing to compute
    from algrasp.io.record.scene import plan_frames
    from algrasp.sim.config import DEFAULT_SIM
    from algrasp.sim.geometry import jaw_size_m, part_geometry

    geom = part_geometry(out.analysis.part, DEFAULT_SIM)
    rec.plan_scene(plan_frames(out.plan, geom.outline_m), geom.outline_m, jaw_size_m(geom))


def _record_validation(rec: Any, out: PlanOutcome) -> None:
    from algrasp.sim.config import DEFAULT_SIM
    from algrasp.sim.geometry import jaw_size_m, part_geometry

    geom = part_geometry(out.analysis.part, DEFAULT_SIM)
    doc = out.validation_doc(with_plan=False)
    assert doc is not None
    rec.validation(doc, out.validation.trajectories, geom.outline_m, jaw_size_m(geom))
