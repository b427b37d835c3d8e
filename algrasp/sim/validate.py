"""Validate a plan in Drake from many initial orientations, in parallel worker processes.

Workers are spawned once per process lifetime (``ValidationPool``) and keep their
pydrake import and built diagrams (keyed by part document and parameters), since
importing pydrake costs about a second. Orientations are world orientations φ of the
part (conventions §2) before and after the whole plan.
"""

from __future__ import annotations

import hashlib
import json
import math
import multiprocessing
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, dataclass
from typing import Any, Literal

import numpy as np

from algrasp.analysis import Analysis
from algrasp.plan import Plan
from algrasp.sim.config import DEFAULT_SIM, SimConfig, schedule
from algrasp.sim.geometry import part_geometry

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


@dataclass(frozen=True)
class Validation:
    samples: tuple[Sample, ...]
    agreement: float
    agreement_clear: float
    tolerance_deg: float
    placement: Placement
    sim_seconds: float
    wall_seconds: float
    model: dict[str, float]

    def to_dict(self, plan_doc: dict[str, Any]) -> dict[str, Any]:
        return {"plan": plan_doc,
                "samples": [{"initial_deg": s.initial_deg, "predicted_deg": s.predicted_deg,
                             "simulated_deg": s.simulated_deg, "agrees": s.agrees,
                             "near_unstable": s.near_unstable, "offset_mm": s.offset_mm} for s in self.samples],
                "agreement": self.agreement, "agreement_clear": self.agreement_clear,
                "tolerance_deg": self.tolerance_deg, "placement": self.placement,
                "sim_seconds": self.sim_seconds, "wall_seconds": self.wall_seconds, "model": self.model}


# ----------------------------------------------------------------- worker side

_SIMS: dict[str, Any] = {}


def _warm() -> None:
    import pydrake.all  # noqa: F401  (the expensive import, once per worker)


def _key(doc: dict[str, Any], cfg: SimConfig) -> str:
    return hashlib.sha256(json.dumps([doc, asdict(cfg)], sort_keys=True).encode()).hexdigest()


def simulate_one(doc: dict[str, Any], cfg: SimConfig, angles: list[float], action: str, phi0: float,
                 offset_m: float, centring: bool, record: bool = False) -> tuple[float, float, list[tuple[float, ...]]]:
    """Run one sample (in a worker or in-process): final φ (rad), sim seconds, samples."""
    from algrasp.part import load_part
    from algrasp.sim.model import PlanarGripperSim

    key = _key(doc, cfg)
    if key not in _SIMS:
        _SIMS[key] = PlanarGripperSim(load_part(doc), cfg)
    sim = _SIMS[key]
    W = cfg.open_margin_factor * sim.geom.reach_m + 1e-3
    phases = schedule(angles, action, W, cfg.push_distance_factor * sim.geom.reach_m, cfg, reach_m=sim.geom.reach_m,
                      min_half_width_m=sim.geom.min_half_width_m)
    phi, traj = sim.run(phases, phi0, offset_m, angles[0], W, record=record, centring=centring)
    return phi, phases[-1].t1, traj


def _task(args: tuple[Any, ...]) -> tuple[float, float]:
    phi, sim_s, _ = simulate_one(*args)
    return phi, sim_s


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

    def map(self, tasks: list[tuple[Any, ...]]) -> list[tuple[float, float]]:
        return list(self._pool.map(_task, tasks))


# ----------------------------------------------------------------- orchestration


def _wrap_deg(x: float) -> float:
    return float(math.degrees(x) % 360.0)


def _near_unstable(plan: Plan, phi0: float) -> bool:
    """Whether the first action sees the part within NEAR_UNSTABLE_DEG of a piece boundary
    of its transfer function: an unstable or semiunstable equilibrium (Appendix A)."""
    theta = phi0 - plan.steps[0].gripper_angle
    P = plan.transfer.period
    tol = math.radians(NEAR_UNSTABLE_DEG)
    for p in plan.transfer.pieces:
        d = (theta - p.start) % P
        if min(d, P - d) < tol:
            return True
    return False


def validate_plan(analysis: Analysis, plan: Plan, samples: int = 36, seed: int = 0,
                  placement: Placement = "centred", tolerance_deg: float = 1.0,
                  cfg: SimConfig = DEFAULT_SIM, workers: int = 2) -> Validation:
    """Simulate the plan from ``samples`` seeded uniform initial orientations."""
    doc = dict(analysis.part.source_document)
    rng = np.random.default_rng(seed)
    phi0 = rng.uniform(0.0, 2 * math.pi, samples)
    geom = part_geometry(analysis.part, cfg)
    W = cfg.open_margin_factor * geom.reach_m + 1e-3
    offsets = rng.uniform(-0.5, 0.5, samples) * (W - geom.reach_m) if placement == "random" else np.zeros(samples)
    angles = [s.gripper_angle for s in plan.steps]
    tasks = [(doc, cfg, angles, plan.action, float(p), float(o), placement == "centred") for p, o in zip(phi0, offsets)]
    t0 = time.perf_counter()
    results = ValidationPool.shared(workers).map(tasks) if workers > 1 else [_task(t) for t in tasks]
    wall = time.perf_counter() - t0
    predicted = plan.run(phi0)
    out = []
    for p, o, pred, (sim_phi, _) in zip(phi0, offsets, predicted, results):
        err = (math.degrees(sim_phi - pred) + 180.0) % 360.0 - 180.0
        out.append(Sample(_wrap_deg(p), _wrap_deg(pred), _wrap_deg(sim_phi), abs(err) <= tolerance_deg,
                          _near_unstable(plan, float(p)), float(o * 1e3)))
    clear = [s for s in out if not s.near_unstable]
    model = {"chord_error_m": geom.chord_error_m, "reach_m": geom.reach_m, "mean_radius_m": geom.mean_radius_m,
             **{k: float(v) for k, v in asdict(cfg).items()}}
    return Validation(tuple(out), sum(s.agrees for s in out) / len(out),
                      sum(s.agrees for s in clear) / len(clear) if clear else float("nan"),
                      tolerance_deg, placement, float(sum(r[1] for r in results)), wall, model)
