"""Simulation parameters and the jaw/gripper schedule of a plan (pure: no pydrake).

Model (stated for users and the README):
- The part is a rigid prism on a PlanarJoint (x, y, θ); its collision shape is the exact
  hull tessellated with a turn of ``tessellation_turn_rad`` per chord, so the chord error
  is ρ·Δψ²/8 for the largest radius of curvature ρ (reported per part); mass
  ``part_mass_kg``, rotational inertia from the exact region (``Part.polar_moment``).
- Support friction: the ellipsoidal limit surface of uniform-pressure Coulomb friction,
  f_max = μ m g and m_max = μ m g r̄ with r̄ the mean distance of the region's points from
  the centre of mass; below ``stiction_speed_m_s`` the force is regularised (viscous).
- Jaws: two rigid planes (half-spaces, solid away from the part) on prismatic joints of
  a gripper turned to α, with Coulomb friction ``jaw_friction`` against the part (0:
  frictionless, the paper's linear-bearing jaws); each jaw is PD-tracked along its
  schedule with its force capped at ``jaw_force_n``.
- Centre of mass: ``com_offset_m`` from the drawn one (the body's inertia and the support
  friction's limit surface are about the true one); mass ``part_mass_kg``.
- Grasp detection: at the end of each squeeze (the hold), the gripper keeps its targets
  until the part has settled — its speed below ``settle_speed_m_s`` / ``settle_rate_rad_s``
  for ``settle_quiet_s`` — at most ``settle_max_s``, as a gripper that reports "object
  gripped" when its jaws stop; once gripped, the schedule skips the rest of the hold. So a
  squeeze lasts as long as the part turns, neither cut short nor padded.
- Contact: hydroelastic (compliant part, rigid jaws), discrete SAP, ``time_step_s``, with
  the dissipation time scale ``relaxation_time_s`` (SAP ignores Hunt–Crossley dissipation).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from algrasp.geometry.angles import signed_diff
from algrasp.geometry.tolerances import TIME_ROUNDING_S
from algrasp.geometry.units import UNIT_TO_M, meters_per_unit  # noqa: F401 - re-exported for the adapter
from algrasp.planning.physics import DEFAULT_PHYSICS, Physics

MIN_THICKNESS_M = 1e-3
"""Jaws, gripper slab and extruded part are at least this thick: Drake needs volume."""
BODY_GYRATION_M2 = (1e-3, 1e-3, 1e-3)
"""Unit inertia of the gripper and jaws. They are driven kinematically, so their inertia
only conditions the contact solver; any value of this order gives the same trajectories."""
OPEN_CLEARANCE_M = 1e-3
"""Open jaws start this far beyond the part's reach, so no sample starts in contact."""


@dataclass(frozen=True)
class SimConfig:
    """Physical and numerical parameters (SI units)."""

    # Shared with the planner's dead band (algrasp.planning.deadband): plan and simulation model one gripper.
    # One cell of the planner's physics ranges (algrasp.planning.physics): the nominal one
    # by default; validation draws others from the plan's ranges (``cell_config``).
    part_mass_kg: float = 0.02
    support_friction: float = 0.3
    gravity_m_s2: float = DEFAULT_PHYSICS.gravity_m_s2[0]
    jaw_friction: float = 0.0
    """Coulomb μ of the jaw–part contact pair (both jaws). The part's and the jaws'
    collision geometries both carry it, so Drake's combined μ = 2μμ/(μ + μ) is exactly it."""
    com_offset_m: tuple[float, float] = (0.0, 0.0)
    """Where the true centre of mass sits relative to the drawn one, in the part frame (m)."""
    stiction_speed_m_s: float = 5e-3
    jaw_speed_m_s: float = 0.01
    open_speed_m_s: float = 0.1
    """Jaw speed away from contact (the fast approach and the release), within what
    electric parallel grippers reach (0.1–0.15 m/s). 0.05 m/s gave the same agreement on
    every part of ``bench_validate.py`` (the pie's random placement: 63 % of 100 samples
    both ways) and 15 % more simulated time (pie, 36 samples: 70.4 s against 60.2 s)."""
    rotate_speed_rad_s: float = 6.0
    jaw_force_n: float = 2.0
    jaw_stiffness_n_m: float = 2000.0
    jaw_damping_n_s_m: float = 40.0
    hold_s: float = 0.1
    push_distance_factor: float = 2.0
    """Default push distance as a multiple of the largest centre-of-mass-to-hull distance."""
    open_margin_factor: float = 1.6
    time_step_s: float = 1e-3
    hydroelastic_modulus_pa: float = 5e8
    relaxation_time_s: float = 2e-3
    """SAP's linear (Kelvin–Voigt) contact dissipation time scale τ, part + jaw together:
    each contact point's force is k(−φ − τ·v_n). Drake's default (0.1 s per geometry) makes
    a squeezed part's patch resist turning like a viscous hinge: over the cam's flat stretch
    of d(θ) it crept at 5°/s and was released mid-turn. 2 ms (two steps) still damps the
    contact's vibration; 0.5–10 ms gave the same agreement, 2 ms settles fastest."""
    tessellation_turn_rad: float = 0.03
    """Chord turn of the collision hull. Its bound is on angle, not length: a part resting
    on a chord of an arc sits up to half the chord's turn away from resting on the arc, so
    0.03 rad keeps that (0.86°) inside the 1° agreement tolerance. 0.09 rad (3× fewer
    faces) cut the pie's wall time by 15 % but moved the optimised push-grasp's pushes
    outside it (push agreement 75 %)."""
    record_hz: float = 50.0
    settle_speed_m_s: float = 1e-3
    settle_rate_rad_s: float = 0.01
    settle_quiet_s: float = 0.05
    settle_max_s: float = 1.0
    similarity_reach_m: float = 0.005
    """The part reach at which the speeds and times above apply as written; a larger part
    is simulated at Froude-similar settings (``similar_config``). 0: never scaled."""
    max_time_step_s: float = 0.003
    """Similarity never makes the step longer than this: at 4.7 ms the 160 mm frame plate's
    contact solve diverged (NaN); at 3 ms it agreed as at 1 ms."""


DEFAULT_SIM = SimConfig()
FRICTION_TIME_STEP_S = 5e-4
"""The time step with jaw friction: a squeeze that ends inside a friction band reaches
the band's edge still turning, and at 1 ms how far it coasts in was up to 0.9° off the
converged outcome (lens, μ_j 0.1); at 0.5 ms within 0.09° of 0.25 ms on every part and μ
of ``benchmarks/bench_sim_convergence.py`` (about twice the cost)."""


def similar_config(cfg: SimConfig, reach_m: float) -> SimConfig:
    """``cfg`` for a part of reach ``reach_m`` (m) by Froude similarity.

    With gravity-driven Coulomb support friction the only acceleration scale is μg, so
    lengths × L, times × √L and speeds × √L map one motion onto another exactly: the part
    turns and slides the same way relative to its size, with the same coasting fraction
    v²/(2μg·reach) — the quasi-static margin of the plan's model. Scaling the time step
    and the friction regularisation with it keeps the number of steps per motion fixed,
    so a 160 mm part costs what a 5 mm one does instead of 32 times more. Parts smaller
    than ``similarity_reach_m`` keep the settings as written (never slower). With jaw
    friction the step stays at most :data:`FRICTION_TIME_STEP_S` (issue 30: the bracket's
    similar 1 ms step let the fast release kick the gripped part by up to 1.1°, 0.88° off
    its claim where the 0.5 ms step ends 0.32° off)."""
    if cfg.similarity_reach_m <= 0.0 or reach_m <= cfg.similarity_reach_m:
        return cfg
    from dataclasses import replace

    k = math.sqrt(reach_m / cfg.similarity_reach_m)
    step = min(k * cfg.time_step_s, cfg.max_time_step_s)
    if cfg.jaw_friction > 0.0:  # the friction step's convergence is in absolute time: never longer
        step = min(step, FRICTION_TIME_STEP_S)
    return replace(cfg, jaw_speed_m_s=k * cfg.jaw_speed_m_s, open_speed_m_s=k * cfg.open_speed_m_s,
                   stiction_speed_m_s=k * cfg.stiction_speed_m_s, time_step_s=step,
                   relaxation_time_s=step * cfg.relaxation_time_s / cfg.time_step_s,  # the same number of steps
                   hold_s=k * cfg.hold_s,
                   settle_speed_m_s=k * cfg.settle_speed_m_s, settle_rate_rad_s=cfg.settle_rate_rad_s / k,
                   settle_quiet_s=k * cfg.settle_quiet_s, settle_max_s=k * cfg.settle_max_s,
                   record_hz=cfg.record_hz / k, similarity_reach_m=0.0)


def sim_config(physics: Physics, base: SimConfig = DEFAULT_SIM, com_offset_m: tuple[float, float] = (0.0, 0.0)) -> SimConfig:
    """``base`` with one cell of the physics: ``physics`` must hold one value per range
    (:meth:`~algrasp.planning.physics.Physics.corners`, ``nominal``); a range is taken at
    its middle."""
    from dataclasses import replace

    def mid(span: tuple[float, float]) -> float:
        return 0.5 * (span[0] + span[1])

    jaw = mid(physics.jaw_friction)
    step = min(base.time_step_s, FRICTION_TIME_STEP_S) if jaw > 0.0 else base.time_step_s
    return replace(base, part_mass_kg=mid(physics.part_mass_kg), support_friction=mid(physics.support_friction),
                   gravity_m_s2=mid(physics.gravity_m_s2), jaw_force_n=mid(physics.grip_force_n),
                   jaw_friction=jaw, com_offset_m=com_offset_m, time_step_s=step)


@dataclass(frozen=True)
class Phase:
    """Linear motion of the targets over [t0, t1]: gripper angle (rad), jaws L and H (m,
    along the gripper's closing axis n, from the gripper centre)."""

    t0: float
    t1: float
    gripper: tuple[float, float]
    lower: tuple[float, float]
    higher: tuple[float, float]
    action: int
    centre: bool = False
    """At the start of this phase (ideal placement only) the jaws' paths are shifted so
    both touch the part together (Assumption 7): the shift is the midpoint of the part's
    extent along the closing axis, kept until the action ends."""
    settle: bool = False
    """At the end of this phase (a squeeze's hold) the targets stay until the part settles."""

    def at(self, t: float) -> tuple[float, float, float]:
        s = 0.0 if self.t1 <= self.t0 else min(max((t - self.t0) / (self.t1 - self.t0), 0.0), 1.0)
        return (self.gripper[0] + s * (self.gripper[1] - self.gripper[0]),
                self.lower[0] + s * (self.lower[1] - self.lower[0]),
                self.higher[0] + s * (self.higher[1] - self.higher[0]))


@dataclass(frozen=True)
class SimSchedule:
    """Everything the simulation needs from a plan's execution: target phases, the open
    half-width of the jaws (m) and the times (s) at which each push ends."""

    phases: tuple[Phase, ...]
    half_open_m: float
    push_ends_s: tuple[float, ...] = ()


SampledStep = tuple[list[float], list[float], list[float], list[float], float | None, float | None]


def sampled_schedule(steps: list[SampledStep], half_open_m: float, push_ends_s: tuple[float, ...]) -> SimSchedule:
    """Phases that interpolate sampled trajectories linearly. ``steps`` holds per action
    (t_s, gripper angle rad, lower m, higher m, centring time or None, settle time or
    None), times from the action's start; actions follow each other."""
    phases: list[Phase] = []
    t0 = 0.0
    for k, (t, g, lo, hi, centre, settle) in enumerate(steps):
        for i in range(len(t) - 1):
            phases.append(Phase(t0 + t[i], t0 + t[i + 1], (g[i], g[i + 1]), (lo[i], lo[i + 1]), (hi[i], hi[i + 1]), k,
                                centre=centre is not None and abs(t[i] - centre) < TIME_ROUNDING_S,
                                settle=settle is not None and abs(t[i + 1] - settle) < TIME_ROUNDING_S))
        t0 += t[-1]
    return SimSchedule(tuple(phases), half_open_m, push_ends_s)


def schedule(angles: list[float], action: str, half_open_m: float, push_m: float, cfg: SimConfig,
             start_angle: float | None = None, reach_m: float = 0.0) -> list[Phase]:
    """Phases for a plan: per action rotate (jaws open), then squeeze (fast approach to
    ``reach_m``, slow contact), or push, close, move back; then open (slow out to
    ``reach_m``, then fast). ``angles`` are
    gripper angles (rad) in execution order."""
    W, v, fast = half_open_m, cfg.jaw_speed_m_s, cfg.open_speed_m_s
    R = min(reach_m, W)
    t, g = 0.0, angles[0] if start_angle is None else start_angle
    phases: list[Phase] = []

    def add(duration: float, gripper: tuple[float, float], lower: tuple[float, float],
            higher: tuple[float, float], k: int, settle: bool = False) -> None:
        nonlocal t
        phases.append(Phase(t, t + duration, gripper, lower, higher, k, settle=settle))
        t += duration

    for k, alpha in enumerate(angles):
        target = g + signed_diff(alpha, g)  # the shortest turn
        add(max(abs(target - g) / cfg.rotate_speed_rad_s, 0.05), (g, target), (-W, -W), (W, W), k)
        g = target
        if action == "squeeze":
            phases.append(Phase(t, t + (W - R) / fast, (g, g), (-W, -R), (W, R), k, centre=True))
            t += (W - R) / fast
            add(R / v, (g, g), (-R, 0.0), (R, 0.0), k)
            add(cfg.hold_s, (g, g), (0.0, 0.0), (0.0, 0.0), k, settle=True)
        else:
            add((W + push_m) / v, (g, g), (-W, push_m), (W, W + push_m), k)
            add(W / v, (g, g), (push_m, push_m), (W + push_m, push_m), k)
            add(cfg.hold_s, (g, g), (push_m, push_m), (push_m, push_m), k, settle=True)
            add(push_m / v, (g, g), (push_m, 0.0), (push_m, 0.0), k)
        # Release at contact speed out to the reach, then fast: a fast release kicks a
        # gripped part as the compressed contacts let go (issue 30: the bracket, 50 g at
        # μ_s 0.45 and 1.6 N, turned 2.2° on the last release and ended 2.16° off its
        # claim; 0.11° released this way; on the pie the fast release cost 0.04°).
        add(R / v, (g, g), (0.0, -R), (0.0, R), k)
        add((W - R) / fast, (g, g), (-R, -W), (R, W), k)
    return phases


def execution_schedule(ex: Any) -> SimSchedule:
    """The optimised execution's trajectories (``optimisation.execution.Execution``) as
    simulation targets in metres, push ends as checkpoints."""
    steps, half_open_m, push_ends_s = ex.sampled_steps()
    return sampled_schedule(steps, half_open_m, push_ends_s)


def execution_config(ex: Any, cfg: SimConfig) -> SimConfig:
    """``cfg`` with the jaw servo of the execution's gripper profile: the force cap and
    stiffness the squeeze targets were computed for."""
    from dataclasses import replace

    return replace(cfg, jaw_force_n=ex.profile.grip_force_n, jaw_stiffness_n_m=ex.profile.jaw_stiffness_n_m)
