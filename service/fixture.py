"""Fixture design for one part and for a catalogue (pure: no I/O but the run record the
caller's Recording writes).

For a part: plan with both actions, choose the best (unique final orientation first,
then fewest steps, then the largest worst-case margin), optimise it, optionally validate
it in Drake, and state what the gripper must provide. For a catalogue: one gripper
specification that covers every orientable part, in millimetres.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from algrasp.errors import ConfigError, NotOrientableError
from algrasp.geometry.angles import to_deg
from algrasp.pipeline import PlanRequest, plan_part
from algrasp.planning.actions import ACTIONS
from algrasp.planning.analysis import Analysis, Model
from algrasp.planning.plans import LimitsWanted, Plan, make_plan
from algrasp.sim.config import meters_per_unit


@dataclass(frozen=True)
class DesignOptions:
    """Batch options (the same for every part of a job). ``samples`` 0: no validation."""

    min_margin_deg: float = 0.0
    samples: int = 0
    seed: int = 0
    placement: Literal["centred", "random"] | None = None
    gripper_profile: dict[str, Any] | None = None
    exact: bool = False
    physics: dict[str, Any] | None = None
    sim_physics: str = "nominal"
    fences: bool = False
    """Also design conveyor fences for the part (conventions §9)."""
    fence_friction: list[float] | None = None
    limits: LimitsWanted = "headline"
    """Physics limits per part (:data:`algrasp.planning.plans.LimitsWanted`): ``none``
    screens a catalogue fastest (a refusal says only why; the gripper's largest jaw
    friction is not given)."""
    belt_width: float | None = None
    """With fences: between the rails, in each part's unit (None: the least its design needs)."""
    fence_min_margin_deg: float | None = None
    """With fences: how far every fence angle may be off (None: ``min_margin_deg``, at least 1°)."""
    exit_steepness_deg: float | None = None
    """With fences: the exit guide's angle to the belt (None: the planner's 2°)."""
    exit_turns: bool = True
    """With fences: model the turn over each fence's tip (False: Berretty et al.'s model)."""
    same_rail: bool = False
    """With fences: consecutive fences may stand on one rail (False: they alternate)."""

    @property
    def model(self) -> Model:
        return Model.from_options({"exact": self.exact, "physics": self.physics})


def _min_margin(plan: Plan) -> float | None:
    """The plan's smallest transition margin (rad); None for a one-step plan."""
    return min((s.margin for s in plan.steps if s.margin is not None), default=None)


def _score(plan: Plan) -> tuple[bool, int, float]:
    m = _min_margin(plan)
    return (len(plan.final_orientations) != 1, len(plan.steps), -math.inf if m is None else -m)


def choose_plan(analysis: Analysis, min_margin_deg: float,
                limits: LimitsWanted = "headline") -> tuple[Plan | None, dict[str, Any]]:
    """The best plan over both actions (None if neither orients the part) and, per
    action, its step count or why it failed (with the ``limits`` searched)."""
    plans: dict[str, Plan] = {}
    compared: dict[str, Any] = {}
    for action in ACTIONS:
        try:
            plans[action] = make_plan(analysis, action, min_margin_deg, limits)
            p, m = plans[action], _min_margin(plans[action])
            compared[action] = {"steps": len(p.steps), "final_orientations": len(p.final_orientations),
                                "min_margin_deg": None if m is None else to_deg(m)}
        except NotOrientableError as exc:
            compared[action] = {"error": exc.to_dict()}
    best = min(plans.values(), key=_score) if plans else None
    return best, compared


def max_diameter(analysis: Analysis) -> float:
    """d_max in part units: the largest diameter-function maximum (constant width: d)."""
    values = [e.value for e in analysis.diameter.extrema]
    if values:
        return float(max(values))
    psi = np.array([0.0])
    return float(analysis.part.hull.support_many(psi)[0] + analysis.part.hull.support_many(psi + np.pi)[0])


def design_part(doc: dict[str, Any], opts: DesignOptions, rec: Any, analysis: Analysis, sim_workers: int = 1) -> dict[str, Any]:
    """The fixture design of one analysed part (see module docs); ``rec`` records the
    chosen plan's run. Lengths in the part's unit and in mm."""
    best, compared = choose_plan(analysis, opts.min_margin_deg, opts.limits)
    units = analysis.part.units
    out: dict[str, Any] = {"name": analysis.part.name, "units": units, "compared": compared, "orientable": best is not None}
    if opts.fences:
        out["fences"] = fence_design(analysis, opts)
    if best is None:
        out["reasons"] = {a: c["error"]["message"] for a, c in compared.items()}
        return out
    req = PlanRequest(best.action, opts.min_margin_deg, True, opts.gripper_profile, samples=opts.samples, seed=opts.seed,
                      placement=opts.placement, exact=opts.exact, physics=opts.physics, sim_physics=opts.sim_physics,
                      limits=opts.limits)  # the chosen plan already carries these limits: not searched again
    res = plan_part(doc, req, rec, sim_workers=sim_workers, analysis=analysis, plan=best)  # analysed and planned once
    out["action"] = best.action
    # The sampled trajectories (100 Hz: most of a plan's bytes) stay in the run record;
    # a catalogue's results carry the plan without them (``GET /v1/runs/{run_id}`` has them).
    out["plan"] = {**res.plan_doc, "steps": [{k: v for k, v in s.items() if k != "trajectory"} for s in res.plan_doc["steps"]]}
    v = res.validation
    out["validation"] = None if v is None else {"samples": len(v.samples), "agreement": v.agreement,
                                                "agreement_clear": v.agreement_clear, "push_agreement": v.push_agreement}
    out["gripper"] = _requirements(analysis, res.plan_doc)
    limits = res.plan_doc.get("limits") or {}
    jaw = limits.get("jaw_friction_max") or {}
    out["gripper"]["jaw_friction_max"] = jaw.get("value") if jaw.get("bounded", True) else None
    out["limits"] = limits
    return out


FENCE_OPTIONS = ("fence_friction", "belt_width", "fence_min_margin_deg", "exit_steepness_deg", "exit_turns",
                 "same_rail")
"""The options of :class:`DesignOptions` that describe the belt and its fences (need ``fences``)."""


def check_fence_options(opts: DesignOptions, fences: str = "fences") -> None:
    """ConfigError naming the first fence option that is out of range, or given without
    ``fences`` (named as ``fences`` says: the option or its flag); the checks of
    ``algrasp.api.fences``, made once for the whole job."""
    from algrasp.planning.fence_exit import exit_steepness
    from algrasp.planning.fences import check_min_margin, fence_rules

    if not opts.fences:
        for name in FENCE_OPTIONS:
            if getattr(opts, name) != getattr(DesignOptions, name):
                raise ConfigError(name, f"needs {fences} (it describes the belt and its fences)")
        return
    fence_rules(opts.fence_friction)
    exit_steepness(opts.exit_steepness_deg)
    if opts.belt_width is not None and not (math.isfinite(opts.belt_width) and opts.belt_width > 0.0):
        raise ConfigError("belt_width", f"expected a width > 0 (each part's unit), got {opts.belt_width!r}")
    if opts.fence_min_margin_deg is not None:
        check_min_margin(opts.fence_min_margin_deg, "fence_min_margin_deg")
    for name in ("exit_turns", "same_rail"):
        if not isinstance(getattr(opts, name), bool):
            raise ConfigError(name, f"expected true or false, got {getattr(opts, name)!r}")


def fence_keywords(opts: DesignOptions) -> dict[str, Any]:
    """The keywords of ``algrasp.api.fences`` the job's options give (but the model), with
    the defaults filled in: what a part's fence design used (its ``options``)."""
    from algrasp.planning.fence_exit import DEFAULT_EXIT_STEEPNESS_DEG
    from algrasp.planning.fences import fence_rules

    margin = max(opts.min_margin_deg, 1.0) if opts.fence_min_margin_deg is None else opts.fence_min_margin_deg
    steep = DEFAULT_EXIT_STEEPNESS_DEG if opts.exit_steepness_deg is None else opts.exit_steepness_deg
    return {"fence_friction": list(fence_rules(opts.fence_friction).friction), "belt_width": opts.belt_width,
            "min_margin_deg": margin, "exit_steepness_deg": steep, "exit_turns": opts.exit_turns,
            "same_rail": opts.same_rail}


def fence_design(analysis: Analysis, opts: DesignOptions) -> dict[str, Any]:
    """The part's conveyor fence document (conventions §9), or why none exists
    (``{"orientable": false, "reason", "message", "limits"}``; a belt too narrow for this
    part's design: reason ``belt_width``), each with the ``options`` it was designed with."""
    from algrasp.planning.fences import fence_rules
    from optimisation.fence_layout import plan_fences

    kw = fence_keywords(opts)
    try:
        doc = plan_fences(analysis, fence_rules(kw["fence_friction"]), kw["min_margin_deg"], kw["belt_width"],
                          kw["exit_steepness_deg"], kw["exit_turns"], kw["same_rail"]).to_dict(follow=False)
        return {"orientable": True, "options": kw, **doc}
    except NotOrientableError as e:
        return {"orientable": False, "options": kw, "reason": e.reason, "message": e.message, "limits": e.limits}
    except ConfigError as e:  # an option this part's design cannot take: a belt_width too narrow for it
        return {"orientable": False, "options": kw, "reason": e.field, "message": e.message, "limits": None}


def _requirements(analysis: Analysis, plan_doc: dict[str, Any]) -> dict[str, Any]:
    """Jaw opening 2W (largest diameter + clearance + placement tolerance, from the
    optimiser), jaw length = extent along the jaws at the worst orientation (d_max) plus
    the placement tolerance on each side, longest push, cycle time."""
    mm = 1000.0 * meters_per_unit(analysis.part.units)
    profile = plan_doc["gripper_profile"]
    d_max = max_diameter(analysis)
    opening = 2.0 * plan_doc["open_half_width"]
    length = d_max + 2.0 * profile["placement_tolerance_m"] * 1000.0 / mm
    pushes = [s["push_distance"] for s in plan_doc["steps"] if s.get("push_distance") is not None]
    push = max(pushes, default=None)
    return {"max_diameter": d_max, "jaw_opening": opening, "jaw_length": length, "push_distance": push,
            "jaw_opening_mm": opening * mm, "jaw_length_mm": length * mm,
            "push_distance_mm": None if push is None else push * mm, "cycle_time_s": plan_doc["cycle_time_s"]}


def catalogue_spec(results: list[dict[str, Any]]) -> dict[str, Any]:
    """The gripper specification covering every oriented part (mm, s), and the parts
    that cannot be oriented (or failed) with why. ``results`` are job-part records
    ``{"index", "name", "status", "result"|"error"}``."""
    ok = [r for r in results if r["status"] == "done" and r["result"]["orientable"]]
    grips = [r["result"]["gripper"] for r in ok]
    pushes = [g["push_distance_mm"] for g in grips if g["push_distance_mm"] is not None]
    cycles = [g["cycle_time_s"] for g in grips]
    failed = [{"index": r["index"], "name": r["name"], "why": _why(r)} for r in results if r not in ok]
    return {
        "parts": len(results), "oriented": len(ok),
        "jaw_opening_mm": max((g["jaw_opening_mm"] for g in grips), default=None),
        "jaw_length_mm": max((g["jaw_length_mm"] for g in grips), default=None),
        "push_stroke_mm": max(pushes, default=None),
        "max_cycle_time_s": max(cycles, default=None),
        "mean_cycle_time_s": sum(cycles) / len(cycles) if cycles else None,
        "actions": {a: sum(r["result"]["action"] == a for r in ok) for a in ACTIONS},
        **_jaw_friction(ok),
        "not_oriented": failed,
    }


def _jaw_friction(ok: list[dict[str, Any]]) -> dict[str, Any]:
    """The largest jaw friction every oriented part's plan tolerates, and what it means
    for the jaws (``jaw_friction_max`` None: no part is limited by jaw friction up to 1)."""
    unsearched = sum("jaw_friction_max" not in (r["result"].get("limits") or {}) for r in ok)
    if unsearched:
        return {"jaw_friction_max": None,
                "jaw_advice": f"not searched for {unsearched} oriented part(s) (limits 'none'): run with limits headline"}
    values = [g["jaw_friction_max"] for r in ok if (g := r["result"]["gripper"]).get("jaw_friction_max") is not None]
    if not values:
        return {"jaw_friction_max": None, "jaw_advice": "no oriented part is limited by jaw friction up to μ 1"}
    worst = min(values)
    return {"jaw_friction_max": worst,
            "jaw_advice": f"every oriented part holds with jaw μ ≤ {worst:.3g}; mount PTFE pads or a linear bearing above that"}


def _why(r: dict[str, Any]) -> str:
    if r["status"] == "done":
        return "; ".join(f"{a}: {m}" for a, m in r["result"]["reasons"].items())
    if r.get("error"):
        return f"{r['error'].get('type')}: {r['error'].get('message')}"
    return str(r["status"])
