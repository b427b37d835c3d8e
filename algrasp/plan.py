"""Plans a cell controller executes: gripper angles in execution order, margins, and
verification through the transfer functions (conventions §4).

Action j (execution order) uses interval I_j = Θ_{N−j+1}. The last action is at α = 0,
so the final world orientations are the value of Θ₁'s step plus multiples of T. Going
backwards, α_j = α_{j+1} + δ_j where δ_j centres the image F(I_j) in I_{j+1}; the
slack on each side is the margin of action j + 1: how far its gripper angle may be off,
relative to the previous action's, with the plan still orienting the part.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from algrasp.analysis import Analysis
from algrasp.curves import FloatArray
from algrasp.errors import AlgraspError, NotOrientableError
from algrasp.functions import wrap
from algrasp.planner import algorithm_a_prime, images
from algrasp.transfer import TransferFunction

Action = Literal["squeeze", "push_grasp"]
SYMMETRY_TOL_RAD = 1e-7
FINAL_CLUSTER_RAD = 1e-6
"""Final orientations closer than this are one orientation in verification."""
VERIFY_SAMPLES = 3600


@dataclass(frozen=True)
class PlanStep:
    gripper_angle: float  # radians, world
    margin: float | None  # radians; None for the first action


@dataclass(frozen=True, eq=False)
class Plan:
    """A verified plan. Angles in radians; ``to_dict`` gives the JSON plan document."""

    action: Action
    transfer: TransferFunction
    symmetry_period: float
    intervals: tuple[tuple[float, float], ...]  # Θ₁ … Θ_N, lifted
    steps: tuple[PlanStep, ...]  # execution order
    final_orientations: tuple[float, ...]  # world, [0, 2π)
    verified: bool
    timings_s: dict[str, float] = field(default_factory=dict)

    def run(self, phi: FloatArray) -> FloatArray:
        """World orientations after executing the plan from ``phi`` (radians), per the
        transfer function: φ′ = F(φ − α) + α for each action."""
        phi = np.asarray(phi, dtype=float)
        for s in self.steps:
            phi = self.transfer.apply(phi - s.gripper_angle) + s.gripper_angle
        return phi

    def trace(self, phi0: float) -> list[float]:
        """World orientation before the plan and after each action (radians)."""
        out = [phi0]
        for s in self.steps:
            out.append(float(self.transfer(out[-1] - s.gripper_angle) + s.gripper_angle))
        return out

    def to_dict(self) -> dict[str, object]:
        T = self.symmetry_period
        return {
            "action": self.action,
            "symmetry_period_deg": float(np.degrees(T)),
            "intervals_deg": [[float(np.degrees(wrap(a, self.transfer.period, 1e-12))),
                               float(np.degrees(wrap(a, self.transfer.period, 1e-12) + b - a))] for a, b in self.intervals],
            "steps": [{"gripper_angle_deg": float(np.degrees(wrap(s.gripper_angle, 2 * np.pi, 1e-12))),
                       "margin_deg": None if s.margin is None else float(np.degrees(s.margin))} for s in self.steps],
            "final_orientations_deg": [float(np.degrees(f)) for f in self.final_orientations],
            "verified": self.verified,
            "timings_s": dict(self.timings_s),
        }


def transfer_for(analysis: Analysis, action: Action) -> TransferFunction:
    if action == "squeeze":
        if not analysis.squeeze.steps:
            raise NotOrientableError("constant_width", "the part has constant width: its squeeze function has no "
                                     "step, so no squeeze plan can orient it (try push_grasp)")
        return analysis.squeeze
    if not analysis.push_grasp.steps:
        raise NotOrientableError("no_step", "the push-grasp function has no step: no push-grasp plan can orient the part")
    return analysis.push_grasp


def gripper_steps(F: TransferFunction, intervals: list[tuple[float, float]]) -> list[PlanStep]:
    """Execution-order gripper angles (last at 0) and margins from Θ₁ … Θ_N."""
    order = intervals[::-1]  # I_1 … I_N
    alphas = [0.0] * len(order)
    margins: list[float | None] = [None] * len(order)
    imgs = images(F, order)
    for j in range(len(order) - 2, -1, -1):
        lo, hi = imgs[j]
        a, b = order[j + 1]
        delta = 0.5 * (a + b) - 0.5 * (lo + hi)  # centre F(I_j) in I_{j+1}
        alphas[j] = alphas[j + 1] + delta
        margins[j + 1] = max(0.0, 0.5 * ((b - a) - (hi - lo)))
    return [PlanStep(float(al), m) for al, m in zip(alphas, margins)]


def final_orientations(F: TransferFunction, intervals: list[tuple[float, float]], T: float) -> list[float]:
    value = F(intervals[0][0])
    k = int(round(2 * np.pi / T))
    return sorted(wrap(value + i * T, 2 * np.pi, 1e-12) for i in range(k))


def verify(plan: Plan, samples: int = VERIFY_SAMPLES) -> bool:
    """Run the plan from a dense set of orientations plus every breakpoint (and its
    neighbours) of every action; true when exactly 360/T final orientations remain,
    the reported ones."""
    phi = [np.linspace(0.0, 2 * np.pi, samples, endpoint=False)]
    starts = np.array([p.start for p in plan.transfer.pieces])
    for s in plan.steps:
        for eps in (-1e-7, 0.0, 1e-7):
            phi.append(starts + s.gripper_angle + eps)
            phi.append(starts + plan.transfer.period + s.gripper_angle + eps)
    final = np.sort(np.mod(plan.run(np.concatenate(phi)), 2 * np.pi))
    clusters = _clusters(final)
    want = np.array(plan.final_orientations)
    if len(clusters) != len(want):
        return False
    return bool(all(np.min(np.abs((c - want + np.pi) % (2 * np.pi) - np.pi)) <= FINAL_CLUSTER_RAD for c in clusters))


def _clusters(sorted_angles: FloatArray) -> list[float]:
    gaps = np.diff(sorted_angles) > FINAL_CLUSTER_RAD
    groups = np.split(sorted_angles, np.nonzero(gaps)[0] + 1)
    if len(groups) > 1 and (groups[0][0] + 2 * np.pi - groups[-1][-1]) <= FINAL_CLUSTER_RAD:
        groups[0] = np.concatenate([groups[-1] - 2 * np.pi, groups[0]])
        groups.pop()
    return [float(np.mean(g)) % (2 * np.pi) for g in groups]


def make_plan(analysis: Analysis, action: Action, min_margin_deg: float = 0.0) -> Plan:
    """The shortest verified plan of ``action`` for the analysed part.

    Raises NotOrientableError (constant width, no step, margin too large).
    """
    if not (np.isfinite(min_margin_deg) and 0.0 <= min_margin_deg < 180.0):
        raise AlgraspError(f"min_margin_deg must be in [0, 180), got {min_margin_deg}")
    F = transfer_for(analysis, action)
    t0 = time.perf_counter()
    T = F.symmetry_period(SYMMETRY_TOL_RAD)
    intervals = algorithm_a_prime(F, T, np.radians(min_margin_deg))
    steps = gripper_steps(F, intervals)
    finals = final_orientations(F, intervals, T)
    t1 = time.perf_counter()
    plan = Plan(action, F, T, tuple(intervals), tuple(steps), tuple(finals), False)
    ok = verify(plan)
    t2 = time.perf_counter()
    if not ok:
        raise NotOrientableError("verification_failed", "the plan did not verify: please report this part")
    return Plan(action, F, T, tuple(intervals), tuple(steps), tuple(finals), True,
                {"planning": t1 - t0, "verification": t2 - t1})
