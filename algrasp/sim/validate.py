"""Validate a plan in Drake from many initial orientations, in parallel worker processes.

Workers are spawned once per process lifetime (``ValidationPool``) and keep their
pydrake import and built diagrams (keyed by the part and the parameters), since
importing pydrake costs about a second. Orientations are world orientations φ of the
part (conventions §2) before and after the whole plan.
"""

from __future__ import annotations

import hashlib
import json
import math
import multiprocessing
import pickle
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, dataclass, field, replace
from typing import Any, Literal

import numpy as np

from algrasp.errors import SimulationError, UnavailableError
from algrasp.geometry.angles import to_deg, to_rad, wrap_deg
from algrasp.geometry.part import Part
from algrasp.geometry.tolerances import SYMMETRY_TOL_RAD
from algrasp.planning.analysis import Analysis
from algrasp.planning.plans import Plan
from algrasp.sim.config import DEFAULT_SIM, OPEN_CLEARANCE_M, SimConfig, SimSchedule, schedule, similar_config
from algrasp.sim.geometry import Geometry, part_geometry

Placement = Literal["centred", "random"]
NEAR_UNSTABLE_DEG = 2.0
"""Samples whose first relative orientation is this close to a step boundary (an
unstable equilibrium) are reported but not counted in ``agreement_clear``."""


@dataclass(frozen=True)
class Sample:
    initial_deg: float
    predicted_deg: float
    simulated_deg: float
    agrees: bool
    near_unstable: bool
    offset_mm: float
    pushed_deg: float | None = None  # simulated φ after the first push (push-grasp)
    push_predicted_deg: float | None = None  # p(φ0 − α1) + α1
    push_agrees: bool | None = None


@dataclass(frozen=True)
class Validation:
    """A plan simulated in Drake from many starts, as :func:`algrasp.validate` makes it
    (angles in degrees, as in the validation document ``to_dict()`` gives).

    Attributes
    ----------
    samples : tuple of Sample
        Per start: ``initial_deg``, ``predicted_deg`` and ``simulated_deg`` (world φ),
        ``agrees``, ``near_unstable``, ``offset_mm`` (jaw placement) and, for push-grasps,
        the first push (``pushed_deg``, ``push_predicted_deg``, ``push_agrees``).
    agreement : float
        Fraction of samples that end within ``tolerance_deg`` plus the plan's final
        uncertainty of a claimed orientation.
    agreement_clear : float
        The same over samples not within 2° of an unstable equilibrium.
    tolerance_deg : float
        The agreement tolerance (degrees).
    placement : {"centred", "random"}
        Where the jaws met the part.
    sim_seconds, wall_seconds : float
        Simulated time (summed over samples) and wall time taken (seconds).
    model : dict
        The simulation's configuration (SI) and the part's geometry in it.
    push_agreement : float or None
        Fraction of clear samples whose first push ends within tolerance (push-grasps).
    optimised : bool
        Whether the plan's optimised execution was simulated.
    trajectories : tuple of list
        Per sample (t, x, y, φ, α, q_L, q_H), SI; if recorded.
    cells : tuple of dict
        Per simulated cell of the physics ranges: its values, samples and agreement.
    plan_document : dict or None
        The document of the plan validated (what :meth:`to_dict` embeds by default).

    Examples
    --------
    >>> doc = {"samples": [{"initial_deg": 10.0, "predicted_deg": 0.0, "simulated_deg": 0.02, "agrees": True,
    ...                     "near_unstable": False, "offset_mm": 0.0}], "agreement": 1.0, "agreement_clear": 1.0,
    ...        "tolerance_deg": 1.0, "placement": "centred", "sim_seconds": 1.5, "wall_seconds": 0.9, "model": {}}
    >>> v, plan_doc = Validation.from_dict(doc)
    >>> v.agreement, v.samples[0].simulated_deg, plan_doc, v.to_dict(with_plan=False)["sim_seconds"]
    (1.0, 0.02, {}, 1.5)
    """

    samples: tuple[Sample, ...]
    agreement: float
    agreement_clear: float
    tolerance_deg: float
    placement: Placement
    sim_seconds: float
    wall_seconds: float
    model: dict[str, Any]
    push_agreement: float | None = None  # first push within tolerance, clear samples only
    optimised: bool = False
    trajectories: tuple[list[tuple[float, ...]], ...] = ()  # per sample (t, x, y, φ, α, q_L, q_H), SI; if recorded
    cells: tuple[dict[str, Any], ...] = ()
    plan_document: dict[str, Any] | None = field(default=None, repr=False, compare=False)

    def to_dict(self, plan_doc: dict[str, Any] | None = None, with_plan: bool = True) -> dict[str, Any]:
        """The validation document (degrees): per-sample outcomes, agreement, per-cell
        agreement, and (``with_plan``) the plan validated (``plan_doc``, else
        :attr:`plan_document`)."""
        plan = {"plan": plan_doc if plan_doc is not None else dict(self.plan_document or {})} if with_plan else {}
        return {**plan, "samples": [asdict(s) for s in self.samples],
                "agreement": self.agreement, "agreement_clear": self.agreement_clear,
                "push_agreement": self.push_agreement, "optimised": self.optimised,
                "tolerance_deg": self.tolerance_deg, "placement": self.placement,
                "sim_seconds": self.sim_seconds, "wall_seconds": self.wall_seconds, "model": self.model,
                "cells": [dict(c) for c in self.cells]}

    @staticmethod
    def from_dict(doc: dict[str, Any]) -> tuple[Validation, dict[str, Any]]:
        """A validation document read back (records' ``/validation``, HTTP responses):
        the Validation (without trajectories) and its plan document (``{}`` if absent).
        PartDocumentError names the first malformed field."""
        from algrasp.errors import PartDocumentError

        try:
            samples = tuple(Sample(**s) for s in doc["samples"])
            v = Validation(samples, float(doc["agreement"]), float(doc["agreement_clear"]), float(doc["tolerance_deg"]),
                           doc["placement"], float(doc["sim_seconds"]), float(doc["wall_seconds"]), dict(doc["model"]),
                           doc.get("push_agreement"), bool(doc.get("optimised", False)),
                           cells=tuple(dict(c) for c in doc.get("cells") or () if isinstance(c, dict)),
                           plan_document=dict(doc.get("plan") or {}))
        except KeyError as exc:
            raise PartDocumentError(f"validation.{exc.args[0]}", "missing") from None
        except (TypeError, ValueError) as exc:
            raise PartDocumentError("validation", f"malformed: {exc}") from None
        return v, dict(doc.get("plan") or {})


@dataclass(frozen=True)
class SimTask:
    """One simulation run; picklable for the worker processes. ``part`` is the part as
    planned (not its document: a worker re-parsing it would redo the parent's work, and
    with other load options might simulate another part); ``key`` names the (part,
    config) pair a worker keeps one simulator for."""

    part: Part
    key: str
    cfg: SimConfig
    schedule: SimSchedule
    alpha0: float
    phi0: float
    offset_m: float
    centring: bool
    record: bool = False


# ----------------------------------------------------------------- worker side

_SIMS: dict[str, Any] = {}


def _warm() -> None:
    import pydrake.all  # noqa: F401  (the expensive import, once per worker)

    from algrasp.lifecycle import exit_with_parent

    exit_with_parent()


def sim_key(part: Part, cfg: SimConfig) -> str:
    """The name of a (part, config) pair: its pickled bytes' digest (computed once per
    validation, in the parent)."""
    return hashlib.sha256(pickle.dumps(part) + json.dumps(asdict(cfg), sort_keys=True).encode()).hexdigest()


def simulate_one(task: SimTask) -> tuple[float, list[float], float, list[tuple[float, ...]]]:
    """Run one sample (in a worker or in-process): final φ (rad), φ at each push end,
    simulated seconds and (if recorded) trajectory samples."""
    from algrasp.sim.model import PlanarGripperSim

    key = task.key
    if key not in _SIMS:
        _SIMS[key] = PlanarGripperSim(task.part, task.cfg)
    sch = task.schedule
    try:
        phi, pushed, traj = _SIMS[key].run(list(sch.phases), task.phi0, task.offset_m, task.alpha0, sch.half_open_m,
                                           record=task.record, centring=task.centring, checkpoints=sch.push_ends_s)
    except RuntimeError as exc:  # Drake's own errors (e.g. degenerate contact faces on a millimetre-sized part)
        raise SimulationError(str(exc).splitlines()[0][:300],
                              f"part reach {1e3 * _SIMS[key].geom.reach_m:.3g} mm; parts of a few mm and below are under the "
                              "contact model's resolution") from None
    return phi, pushed, _SIMS[key].sim_seconds, traj


def _task(task: SimTask) -> tuple[float, list[float], float, list[tuple[float, ...]]]:
    return simulate_one(task)


def default_schedule(plan: Plan, geom: Geometry, cfg: SimConfig, push_m: float = 0.0) -> SimSchedule:
    """The constant-speed profile used when no optimised execution is given: jaws open
    to ``open_margin_factor``·reach, push ``push_distance_factor``·reach past the centre,
    or ``push_m`` (m) if longer (the push law's worst case for the plan's slowest cell)."""
    W = cfg.open_margin_factor * geom.reach_m + OPEN_CLEARANCE_M
    angles = [s.gripper_angle for s in plan.steps]
    push = max(cfg.push_distance_factor * geom.reach_m, push_m)
    phases = schedule(angles, plan.action, W, push, cfg, reach_m=geom.reach_m)
    return SimSchedule(tuple(phases), W)


class ValidationPool:
    """A warm pool of simulation workers (spawned, so the parent never forks pydrake)."""

    _shared: ValidationPool | None = None

    def __init__(self, workers: int) -> None:
        self.workers = max(1, workers)
        ctx = multiprocessing.get_context("spawn")
        self._pool = ProcessPoolExecutor(max_workers=self.workers, mp_context=ctx, initializer=_warm)

    @classmethod
    def shared(cls, workers: int) -> ValidationPool:
        if cls._shared is None or cls._shared.workers != max(1, workers):
            cls._shared = cls(workers)
        return cls._shared

    def map(self, tasks: list[SimTask]) -> list[tuple[float, list[float], float, list[tuple[float, ...]]]]:
        """Every task's outcome, in order. A simulation worker that dies (killed, out of
        memory) breaks the whole executor: it is thrown away — the next validation gets a
        fresh pool — and this one is a 503 to retry, not a broken pool kept for ever."""
        from concurrent.futures.process import BrokenProcessPool

        try:
            return list(self._pool.map(_task, tasks))
        except BrokenProcessPool:
            self.close()
            raise UnavailableError("worker_lost", "a simulation worker died during the validation; the pool is "
                                   "replaced: send the request again", 1.0) from None

    def close(self) -> None:
        """Shut the pool down (without waiting for the dead) and forget it as the shared one."""
        self._pool.shutdown(wait=False, cancel_futures=True)
        if ValidationPool._shared is self:
            ValidationPool._shared = None


# ----------------------------------------------------------------- orchestration


def _wrap_deg(x: float) -> float:
    return wrap_deg(to_deg(x))


def _near_unstable(plan: Plan, phi0: float) -> bool:
    """Whether the first action sees the part within NEAR_UNSTABLE_DEG of a piece boundary
    of its transfer function: an unstable or semiunstable equilibrium (Appendix A)."""
    theta = phi0 - plan.steps[0].gripper_angle
    P = plan.transfer.period
    tol = to_rad(NEAR_UNSTABLE_DEG)
    for p in plan.transfer.pieces:
        d = (theta - p.start) % P
        if min(d, P - d) < tol:
            return True
    return False


def validate_plan(analysis: Analysis, plan: Plan, samples: int = 36, seed: int = 0,
                  placement: Placement = "centred", tolerance_deg: float = 1.0,
                  cfg: SimConfig = DEFAULT_SIM, workers: int = 2, sim_schedule: SimSchedule | None = None,
                  record: bool = False, push_m: float = 0.0) -> Validation:
    """Simulate the plan from ``samples`` seeded uniform initial orientations, with the
    given (optimised) schedule or the default constant-speed one; ``record`` keeps every
    simulated trajectory (at ``cfg.record_hz``)."""
    rng = np.random.default_rng(seed)
    phi0 = rng.uniform(0.0, 2 * math.pi, samples)
    geom = part_geometry(analysis.part, cfg)
    if sim_schedule is None:  # the default schedule's speeds are ours to scale; an execution's are not
        cfg = similar_config(cfg, geom.reach_m)
    sch = sim_schedule or default_schedule(plan, geom, cfg, push_m)
    offsets = rng.uniform(-0.5, 0.5, samples) * (sch.half_open_m - geom.reach_m) if placement == "random" \
        else np.zeros(samples)
    key = sim_key(analysis.part, cfg)
    tasks = [SimTask(analysis.part, key, cfg, sch, plan.steps[0].gripper_angle, float(p), float(o),
                     placement == "centred", record) for p, o in zip(phi0, offsets)]
    t0 = time.perf_counter()
    results = ValidationPool.shared(workers).map(tasks) if workers > 1 else [_task(t) for t in tasks]
    wall = time.perf_counter() - t0
    out = [_sample(analysis, plan, float(p), float(o), pred, r, tolerance_deg)
           for p, o, pred, r in zip(phi0, offsets, plan.run(phi0), results)]
    clear = [s for s in out if not s.near_unstable]
    pushes = [s.push_agrees for s in clear if s.push_agrees is not None]
    model = {"chord_error_m": geom.chord_error_m, "reach_m": geom.reach_m, "mean_radius_m": geom.mean_radius_m,
             **{k: [float(x) for x in v] if isinstance(v, tuple) else float(v) for k, v in asdict(cfg).items()}}
    return Validation(tuple(out), sum(s.agrees for s in out) / len(out),
                      sum(s.agrees for s in clear) / len(clear) if clear else float("nan"),
                      tolerance_deg, placement, float(sum(r[2] for r in results)), wall, model,
                      sum(pushes) / len(pushes) if pushes else None, sim_schedule is not None,
                      tuple(r[3] for r in results))


def _sample(analysis: Analysis, plan: Plan, phi0: float, offset_m: float, predicted: float,
            result: tuple[float, list[float], float, Any], tolerance_deg: float) -> Sample:
    sim_phi, pushed, _, _ = result
    # A robust plan guarantees one of its final orientations within its uncertainty
    # (conventions §7); which one a start near an unstable equilibrium reaches is not
    # predicted, so it agrees with any. An exact plan is held to its per-sample prediction,
    # up to rotations that map the part onto itself (the same pose).
    allowed = tolerance_deg + to_deg(plan.final_uncertainty)
    sym = _part_symmetry(analysis)
    targets = list(plan.final_orientations) if plan.bounds is not None else [predicted]
    err = min(_angle_err_deg(sim_phi, t + k * sym) for t in targets for k in range(int(round(2 * math.pi / sym))))
    sample = Sample(_wrap_deg(phi0), _wrap_deg(predicted), _wrap_deg(sim_phi),
                    err <= allowed, _near_unstable(plan, phi0), offset_m * 1e3)
    if not pushed:
        return sample
    a1 = plan.steps[0].gripper_angle
    want = analysis.push(phi0 - a1) + a1
    return replace(sample, pushed_deg=_wrap_deg(pushed[0]), push_predicted_deg=_wrap_deg(want),
                   push_agrees=_angle_err_deg(pushed[0], want) <= tolerance_deg)


def _part_symmetry(analysis: Analysis) -> float:
    """The part's rotational symmetry (radians): the period of its radius function, which
    sees the whole outline and the centre of mass (to the drawing's tolerance when robust)."""
    if analysis.robust is not None and analysis.robust.push is not None:
        return analysis.robust.push.symmetry
    return analysis.push.symmetry_period(SYMMETRY_TOL_RAD)


def _angle_err_deg(a: float, b: float) -> float:
    return abs((to_deg(a - b) + 180.0) % 360.0 - 180.0)


def validate_cells(analysis: Analysis, plan: Plan, cells: list[Any], samples: int, seed: int, placement: Placement,
                   tolerance_deg: float, cfg: SimConfig, workers: int = 2, sim_schedule: SimSchedule | None = None,
                   record: bool = False) -> Validation:
    """:func:`validate_plan` in each cell (:class:`algrasp.planning.cells.Cell`), ``samples``
    per cell (seeds differ per cell), merged: agreement over all samples, and per cell.
    Without an optimised schedule, push-grasps push as far as the push law needs for the
    slowest cell of the plan's ranges (:func:`needed_push_m`)."""
    from algrasp.geometry.units import meters_per_unit
    from algrasp.sim.config import sim_config

    m = meters_per_unit(analysis.part.units)
    push_m = needed_push_m(analysis, plan) if sim_schedule is None else 0.0
    runs = [validate_plan(analysis, plan, samples, seed + i, placement, tolerance_deg,
                          sim_config(c.physics, cfg, (m * c.com_offset[0], m * c.com_offset[1])), workers, sim_schedule, record,
                          push_m) for i, c in enumerate(cells)]
    out = [s for v in runs for s in v.samples]
    clear = [s for s in out if not s.near_unstable]
    pushes = [s.push_agrees for s in clear if s.push_agrees is not None]
    per_cell = tuple({**c.to_dict(), "samples": len(v.samples), "agreement": v.agreement,
                      "worst_error_deg": _worst(v, plan)} for c, v in zip(cells, runs))
    return Validation(tuple(out), sum(s.agrees for s in out) / len(out),
                      sum(s.agrees for s in clear) / len(clear) if clear else float("nan"), tolerance_deg, placement,
                      sum(v.sim_seconds for v in runs), sum(v.wall_seconds for v in runs), runs[0].model,
                      sum(pushes) / len(pushes) if pushes else None, sim_schedule is not None,
                      tuple(t for v in runs for t in v.trajectories), per_cell)


def _worst(v: Validation, plan: Plan) -> float:
    """Largest distance (degrees) of a simulated end from the nearest claimed orientation."""
    return max(min(_angle_err_deg(to_rad(s.simulated_deg), f) for f in plan.final_orientations) if plan.bounds is not None
               else _angle_err_deg(to_rad(s.simulated_deg), to_rad(s.predicted_deg)) for s in v.samples)


PUSH_MARGIN = 1.2
"""Default-schedule pushes are this much longer than the push law's worst case (the law
is quasi-static; the simulated part also has inertia and a compliant contact)."""


def needed_push_m(analysis: Analysis, plan: Plan) -> float:
    """The longest push (m) the push law needs over the plan's steps, with the plan's
    largest jaw friction (``optimisation.push``); 0 for squeezes or without the extra."""
    if plan.action != "push_grasp":
        return 0.0
    try:
        from optimisation.profile import DEFAULT_PROFILE
        from optimisation.push import push_distances, push_model
    except ImportError:  # pragma: no cover - the optimisation extra is optional
        return 0.0
    from algrasp.geometry.units import meters_per_unit
    from algrasp.planning.deadband import mean_radius

    jaw = 0.0 if analysis.robust is None else analysis.robust.physics.jaw_friction[1]
    model = push_model(analysis, mean_radius(analysis.part), jaw)
    found = push_distances(model, analysis, list(plan.intervals[::-1]), to_rad(DEFAULT_PROFILE.push_tolerance_deg),
                           to_rad(DEFAULT_PROFILE.unstable_band_deg))
    return PUSH_MARGIN * meters_per_unit(analysis.part.units) * max((r.distance for r in found), default=0.0)
