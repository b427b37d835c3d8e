"""Optimised execution of a plan: push distances, jaw and gripper trajectories, cycle time.

``optimise_execution(analysis, plan, profile)`` → :class:`Execution`. Per action, in
execution order (positions along the closing axis n from the gripper centre, part
units; the lower jaw is negative):

- rotate the gripper to its angle (shortest turn, jaws open at ±W);
- squeeze: both jaws close fast to the contact zone ±Z (the part's largest half-width
  plus the placement tolerance), then at contact speed to g = d_lo/2 − δ, where d_lo is
  the narrowest grasp width the action can end in and δ = force/stiffness the servo's
  squeeze travel; hold; open at contact speed until clear of the widest outcome, then fast;
- push-grasp: the gripper moves along +n, fast until the lower jaw may touch, then at
  contact speed until it has pushed the optimised distance s beyond the last point where
  first contact can happen; the higher jaw closes (fast, then at contact speed) to
  d_lo − 2δ from the lower one; hold; the grasped part is carried back to the centre;
  the jaws open as for a squeeze.

Each move is a rest-to-rest chain solved time-optimally: in closed form (``chains``), or
with a jaw jerk limit by CasADi (``chains_nlp``). The naive reference executes the same moves at contact speed
throughout, each segment a rest-to-rest trapezoid under the same acceleration limit
(closed form).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from functools import partial

import numpy as np

from algrasp.geometry.angles import TWO_PI, shortest_turn, to_deg, to_rad
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.units import meters_per_unit
from algrasp.planning.analysis import Analysis
from algrasp.planning.deadband import mean_radius
from algrasp.planning.plans import Plan
from optimisation.chains import Chain, Profile1D, solve_chains, time_optimal, trapezoid_duration
from optimisation.profile import DEFAULT_PROFILE, GripperProfile
from optimisation.push import PushResult, push_distances, push_model

OUTCOME_SAMPLES = 721
"""Orientations sampled per input interval to find the grasp widths an action can end in."""


@dataclass(frozen=True)
class Move:
    """One phase of an action: a solved chain on one axis, or a dwell (profile None)."""

    axis: str  # "gripper" (rad), "jaws" (symmetric half-width), "lower", "higher", "both"
    profile: Profile1D | None
    duration_s: float


@dataclass(frozen=True, eq=False)
class StepExecution:
    """One action's trajectory: samples (t_s from the action's start; angle in radians;
    jaw positions in part units) and its push distance (None for squeezes)."""

    push: PushResult | None
    duration_s: float
    t_s: FloatArray
    gripper_angle_rad: FloatArray
    lower: FloatArray
    higher: FloatArray
    centre_at_s: float | None  # squeeze: when the jaws start closing (simulation centring)
    push_end_s: float | None  # push-grasp: when the push ends
    settle_at_s: float | None = None  # when the hold ends (the simulation waits for the part to settle)


@dataclass(frozen=True, eq=False)
class Execution:
    profile: GripperProfile
    units: str
    open_half_width: float  # W, part units
    steps: tuple[StepExecution, ...]
    cycle_time_s: float
    naive_cycle_time_s: float
    timings_s: dict[str, float] = field(default_factory=dict)

    def step_documents(self) -> list[dict[str, object]]:
        """Per-step fields the plan document gains (conventions §1: degrees, part units)."""
        out: list[dict[str, object]] = []
        for s in self.steps:
            out.append({
                "push_distance": None if s.push is None else s.push.distance,
                "push_distance_bound": None if s.push is None else s.push.bound,
                "duration_s": s.duration_s,
                "trajectory": {"t_s": s.t_s.tolist(), "gripper_angle_deg": to_deg(s.gripper_angle_rad).tolist(),
                               "lower_jaw": s.lower.tolist(), "higher_jaw": s.higher.tolist()},
            })
        return out

    def sampled_steps(self) -> tuple[list[SampledStep], float, tuple[float, ...]]:
        """Per step ``(t_s, gripper_angle_rad, lower_m, higher_m, centre_at_s, settle_at_s)``,
        the open half-width (m) and the push end times (s): the trajectories in metres, for
        a simulator (``algrasp.sim.config.execution_schedule``)."""
        s = meters_per_unit(self.units)
        steps: list[SampledStep] = []
        ends, t0 = [], 0.0
        for st in self.steps:
            steps.append((st.t_s.tolist(), st.gripper_angle_rad.tolist(), (st.lower * s).tolist(),
                          (st.higher * s).tolist(), st.centre_at_s, st.settle_at_s))
            if st.push_end_s is not None:
                ends.append(t0 + st.push_end_s)
            t0 += st.duration_s
        return steps, self.open_half_width * s, tuple(ends)

    def apply_to(self, plan_doc: dict[str, object]) -> dict[str, object]:
        """The plan document with the execution merged in (a new dict)."""
        doc = dict(plan_doc)
        steps = plan_doc["steps"]
        assert isinstance(steps, list)
        doc["steps"] = [{**s, **e} for s, e in zip(steps, self.step_documents())]
        doc["units"] = self.units
        doc["cycle_time_s"] = self.cycle_time_s
        doc["naive_cycle_time_s"] = self.naive_cycle_time_s
        doc["gripper_profile"] = self.profile.to_dict()
        doc["open_half_width"] = self.open_half_width
        return doc


SampledStep = tuple[list[float], list[float], list[float], list[float], float | None, float | None]
"""One step's samples: times (s), gripper angles (rad), lower and higher jaw (m), centring and settling times."""


@dataclass(frozen=True)
class _Geometry:
    """Widths in metres that set the waypoints."""

    d_max: float
    d_min: float
    outcomes: tuple[tuple[float, float], ...]  # per action: narrowest, widest final width


def _widths(analysis: Analysis, plan: Plan, scale: float) -> _Geometry:
    d = analysis.diameter
    grid = d.values(np.linspace(0.0, math.pi, 1441))
    ext = [e.value for e in d.extrema]
    d_max, d_min = max([float(grid.max())] + ext), min([float(grid.min())] + ext)
    outcomes = []
    for a, b in plan.intervals[::-1]:
        theta = np.linspace(a, b, OUTCOME_SAMPLES, endpoint=False)
        # d at each distinct outcome once: a step sends many samples to one orientation
        # (on a catalogue, ~1 in 8 samples is distinct); the same values, so the same extremes.
        w = d.values(np.unique(plan.transfer.apply(theta)))
        outcomes.append((float(w.min()) * scale, float(w.max()) * scale))
    return _Geometry(d_max * scale, d_min * scale, tuple(outcomes))


def _action_chains(pf: GripperProfile, g: _Geometry, k: int, action: str, turn: float, push_m: float,
                   contact: float, fast: float) -> list[tuple[str, Chain | float]]:
    """The moves of action k: (axis, chain) or ("dwell", seconds); metres and radians."""
    tol, delta = pf.placement_tolerance_m, pf.squeeze_overtravel_m
    W, Z = g.d_max / 2 + pf.open_clearance_m + tol, g.d_max / 2 + tol
    lo, hi = g.outcomes[k]
    rot = Chain((0.0, turn), (pf.rotate_max_speed_rad_s,), pf.rotate_max_accel_rad_s2)
    a = pf.jaw_max_accel_m_s2
    release = Chain((lo / 2 - delta, hi / 2 + delta, W), (contact, fast), a)
    if action == "squeeze":
        close = Chain((W, Z, lo / 2 - delta), (fast, contact), a)
        return [("gripper", rot), ("jaws", close), ("dwell", pf.hold_s), ("jaws", release)]
    end = -g.d_min / 2 + tol + push_m
    push = Chain((-W, -Z, end), (fast, contact), a)
    close_h = Chain((end + 2 * W, end + g.d_max + tol, end + lo - 2 * delta), (fast, contact), a)
    back = Chain((0.0, -(end + lo / 2 - delta)), (fast,), a)
    return [("gripper", rot), ("push", push), ("higher", close_h), ("dwell", pf.hold_s), ("both", back), ("jaws", release)]


def optimise_execution(analysis: Analysis, plan: Plan, profile: GripperProfile = DEFAULT_PROFILE,
                       push_scale: float = 1.0) -> Execution:
    """Push distances, time-optimal trajectories and cycle time of ``plan``.

    ``push_scale`` multiplies the optimised push distances (1: the optimum; the
    validation uses 0.5 to show the optimum is tight). Cost: tens of milliseconds (push
    law quadrature, closed-form moves, sampling); with a jaw jerk limit add one IPOPT
    solve per distinct jaw move (tens to hundreds of ms each)."""
    t0 = time.perf_counter()
    scale = meters_per_unit(analysis.part.units)
    pushes: list[PushResult | None] = [None] * len(plan.steps)
    if plan.action == "push_grasp":
        jaw = 0.0 if analysis.robust is None else analysis.robust.physics.jaw_friction[1]
        model = push_model(analysis, mean_radius(analysis.part), jaw)
        pushes = list(push_distances(model, analysis, list(plan.intervals[::-1]), to_rad(profile.push_tolerance_deg),
                                     to_rad(profile.unstable_band_deg)))
    t1 = time.perf_counter()
    g = _widths(analysis, plan, scale)
    starts, turns = _turns([s.gripper_angle for s in plan.steps], plan.transfer.period)
    push_m = [0.0 if p is None else p.distance * scale * push_scale for p in pushes]
    fast, slow = profile.jaw_max_speed_m_s, profile.contact_speed_m_s
    best = _solve(profile, g, plan.action, turns, push_m, slow, fast)
    naive_cycle = sum(c if isinstance(c, float) else trapezoid_duration(c)
                      for k in range(len(turns)) for _, c in _action_chains(profile, g, k, plan.action, turns[k], push_m[k],
                                                                             slow, slow))
    t2 = time.perf_counter()
    steps = tuple(_sample(profile, moves, starts[k], pushes[k], scale, g)
                  for k, moves in enumerate(best))
    cycle = sum(s.duration_s for s in steps)
    W = (g.d_max / 2 + profile.open_clearance_m + profile.placement_tolerance_m) / scale
    return Execution(profile, analysis.part.units, W, steps, cycle, naive_cycle,
                     {"push_distances": t1 - t0, "trajectories": t2 - t1})


def _turns(angles: list[float], period: float) -> tuple[list[float], list[float]]:
    """Start angle and shortest signed turn of each action, continuous over the cycle:
    the cycle starts at the last action's angle (where the previous cycle left the
    gripper), wrapped into [0, 2π). An action maps to itself under a turn by its period
    (π for a squeeze: the jaws trade places), so the gripper turns the shortest way to an
    angle equivalent to the plan's (the trajectory's angles may differ from the plan's by
    multiples of the period)."""
    at = angles[-1] % TWO_PI
    starts, turns = [], []
    for a in angles:
        turn = shortest_turn(a - at, period)
        starts.append(at)
        turns.append(turn)
        at += turn
    return starts, turns


def _solve(pf: GripperProfile, g: _Geometry, action: str, turns: list[float], push_m: list[float],
           contact: float, fast: float) -> list[list[Move]]:
    """All actions' moves, every chain solved time-optimally."""
    plans = [_action_chains(pf, g, k, action, turns[k], push_m[k], contact, fast) for k in range(len(turns))]
    chains = [c for moves in plans for _, c in moves if isinstance(c, Chain)]
    solved = iter(_solve_chains(pf, chains, [axis for moves in plans for axis, c in moves if isinstance(c, Chain)]))
    out = []
    for moves in plans:
        row = []
        for axis, c in moves:
            if isinstance(c, float):
                row.append(Move(axis, None, c))  # a dwell
            else:
                p = next(solved)
                row.append(Move(axis, p, p.duration_s))
        out.append(row)
    return out


def _solve_chains(pf: GripperProfile, chains: list[Chain], axes: list[str]) -> list[Profile1D]:
    """Closed-form time-optimal moves; with a jaw jerk limit the jaw moves are CasADi's
    jerk-limited S-curves (the gripper's rotation keeps its own acceleration limit)."""
    if pf.jaw_max_jerk_m_s3 <= 0.0:
        return solve_chains(chains)
    from optimisation.chains_nlp import jerk_limited

    jerk = partial(jerk_limited, jerk_limit=pf.jaw_max_jerk_m_s3)
    jaws = iter(solve_chains([c for c, a in zip(chains, axes) if a != "gripper"], jerk))
    return [time_optimal(c) if a == "gripper" else next(jaws) for c, a in zip(chains, axes)]


def _sample(pf: GripperProfile, moves: list[Move], alpha0: float, push: PushResult | None, scale: float,
            g: _Geometry) -> StepExecution:
    """Samples at ``sample_hz`` plus every move boundary; state carried across moves."""
    W = g.d_max / 2 + pf.open_clearance_m + pf.placement_tolerance_m
    state = np.array([alpha0, -W, W])
    ts: list[FloatArray] = [np.zeros(1)]
    rows: list[FloatArray] = [state[None, :].copy()]
    t, centre, push_end, settle = 0.0, None, None, None
    for m in moves:
        if m.axis == "dwell":
            settle = t + max(m.duration_s, 0.0)
        if m.duration_s <= 0.0:
            continue
        if m.axis == "jaws" and m.profile is not None and m.profile.q[0] > m.profile.q[-1] and centre is None:
            centre = t
        if m.axis == "push":
            push_end = t + m.duration_s
        local = np.union1d(np.arange(0.0, m.duration_s, 1.0 / pf.sample_hz)[1:], [m.duration_s])
        rows.append(_states_at(m, state, local))
        ts.append(t + local)
        state = rows[-1][-1].copy()
        t += m.duration_s
    arr = np.concatenate(rows)
    return StepExecution(push, t, np.concatenate(ts), arr[:, 0], arr[:, 1] / scale, arr[:, 2] / scale,
                         centre if push is None else None, push_end, settle)


def _states_at(m: Move, base: FloatArray, tau: FloatArray) -> FloatArray:
    """(angle, lower, higher) rows after each τ (s) of move m, from state ``base``; (len(τ), 3)."""
    out = np.repeat(base[None, :], len(tau), axis=0)
    if m.profile is None:
        return out
    q = m.profile.sample(tau)
    q0 = float(m.profile.q[0])
    if m.axis == "gripper":
        out[:, 0] = base[0] + q
    elif m.axis == "jaws":
        out[:, 1], out[:, 2] = -q, q
    elif m.axis == "higher":
        out[:, 2] = q
    elif m.axis == "push":
        out[:, 1], out[:, 2] = q, base[2] + (q - q0)
    else:  # "both": carry the grasped part
        out[:, 1], out[:, 2] = base[1] + q, base[2] + q
    return out
