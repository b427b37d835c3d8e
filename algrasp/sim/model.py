"""The Drake model of a part between a parallel-jaw gripper (see ``config`` for the model).

``PlanarGripperSim(part, cfg)`` builds the diagram once; ``run`` simulates a plan from one
initial pose and returns the final orientation and a sampled trajectory. Lengths are
converted from the part's unit to metres here and only here.
"""

from __future__ import annotations

import bisect
import logging
import math
from typing import Any

import numpy as np
from pydrake.geometry import (
    AddCompliantHydroelasticProperties,
    AddContactMaterial,
    AddRigidHydroelasticProperties,
    CollisionFilterDeclaration,
    Convex,
    GeometrySet,
    HalfSpace,
    ProximityProperties,
)
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.multibody.plant import AddMultibodyPlant, CoulombFriction, MultibodyPlantConfig
from pydrake.multibody.tree import (
    PdControllerGains,
    PlanarJoint,
    PrismaticJoint,
    RevoluteJoint,
    RotationalInertia,
    SpatialInertia,
    UnitInertia,
)
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import BasicVector, DiagramBuilder, EventStatus, LeafSystem

from algrasp.geometry.curves import FloatArray
from algrasp.geometry.part import Part
from algrasp.geometry.tolerances import PARAM_END, TIME_ROUNDING_S
from algrasp.sim.config import BODY_GYRATION_M2, DEFAULT_SIM, MIN_THICKNESS_M, Phase, SimConfig
from algrasp.sim.geometry import extent_midpoint, part_geometry

FRICTIONLESS = CoulombFriction(0.0, 0.0)
SOLVER_FALLBACKS: tuple[tuple[str, float], ...] = (("polygon", 1.0), ("triangle", 1.0), ("triangle", 0.5), ("polygon", 0.25))
"""Numerical variants of one model, tried in order when Drake's SAP solver fails on a run:
(contact surface representation, time-step factor). With jaw friction SAP's Newton
iteration sometimes fails to converge while every point of a patch sits on its friction
cone's edge (a part creeping at the edge of its sticky band just after the jaw force
reaches its cap): 6 of 64 lens squeezes at μ 0.4, 1 of 64 ellipse ones at μ 0.2. Any
perturbation of the problem escapes the failure; no single model knob removed it. The
triangle quadrature (several points per contact polygon) rescued 5 of those 6 at 1 ms,
and all 6 at 0.5 ms, ending within 0.01° of where the other steps and quadratures put
those parts. Polygons stay the default: triangles cost 1.4–1.9× the wall time on
frictionless squeezes.

The last variant (a quarter step) is where a *diverged* run goes directly (see
:data:`DIVERGED_SPEED_FACTOR`)."""
DIVERGED_SPEED_FACTOR = 100.0
"""A run has diverged when a point of the part or a jaw moves faster than this many times
the fastest jaw speed of the schedule (``open_speed_m_s``; 20 m/s for the bracket).
Seen on the bracket (20.5 mm reach) with frictionless jaws at its Froude-similar 2 ms
step: when a squeeze turns the part fast (8.5 rad/s at μ_s 0.2, 10 g, 1.6 N) onto the
flat edge at a minimum of d, the far end of the edge overlaps the rigid jaw by ω·Δt·L in
one step and the next steps' contact impulses fling part and jaw metres away (about
1000 m/s; every one of 16 push-grasp samples at the 8 frictionless corners of the
default ranges, misses up to 167°, and the centred squeeze's too). At 1 ms it still
happened; at 0.5 ms (a quarter of the similar step) none of 8 push-grasp and 6 squeeze
samples diverged and all ended within the claim, with impact spikes of at most 4.5 m/s
(hence the factor: 20 m/s is 4× above those, 50× below a divergence). Jaw friction damps
the impact: no friction corner diverged at its 1 ms step. The monitor stops the run
there (a RuntimeError) and it is repeated at a quarter of the step, the last of
:data:`SOLVER_FALLBACKS`."""


DIVERGED = "the contact step diverged"
"""What a diverged run's error says (the monitor's message, in Drake's RuntimeError)."""


class _RigidPlaneNote(logging.Filter):
    """Drops Drake's note, on registering a rigid half-space, that deformable bodies
    cannot touch it: this model has none, and the note would fill every worker's log."""

    def filter(self, record: logging.LogRecord) -> bool:
        return "half spaces are not currently supported for deformable contact" not in record.getMessage()


logging.getLogger("drake").addFilter(_RigidPlaneNote())


def jaw_contact_friction(mu: float) -> CoulombFriction:
    """One geometry's friction for a jaw–part pair of Coulomb μ (static = dynamic).

    Both geometries of the pair carry it, so Drake's combination 2μ₁μ₂/(μ₁ + μ₂) gives
    exactly μ; μ = 0 is returned as the exact frictionless pair (no 0/0 to rely on)."""
    if mu < 0.0 or not math.isfinite(mu):
        raise ValueError(f"jaw friction must be a finite μ ≥ 0, got {mu!r}")
    return FRICTIONLESS if mu == 0.0 else CoulombFriction(mu, mu)


def _contact_material(props: ProximityProperties, cfg: SimConfig) -> None:
    """Jaw friction ``cfg.jaw_friction``, with half the dissipation time scale: SAP adds
    the two geometries'."""
    AddContactMaterial(None, None, jaw_contact_friction(cfg.jaw_friction), props)
    props.AddProperty("material", "relaxation_time", cfg.relaxation_time_s / 2)


def part_inertia(cfg: SimConfig, polar_per_area_m2: float, thick_m: float) -> SpatialInertia:
    """The part's spatial inertia about its body origin Bo, the drawn centre of mass.

    The region's second moments about Bo (``polar_per_area_m2``, m², and the slab's
    ``thick_m``, m) are those of the drawing whatever the true centre of mass; the true
    one sits at ``cfg.com_offset_m`` (m) from Bo, so by the parallel-axis theorem the
    central inertia is the drawn one less m·(|δ|²·1 − δδᵀ). Mass ``cfg.part_mass_kg``."""
    m, (dx, dy) = cfg.part_mass_kg, cfg.com_offset_m
    izz = polar_per_area_m2
    if dx * dx + dy * dy >= izz:
        raise ValueError(f"centre-of-mass offset ({dx:g}, {dy:g}) m is too far for the part's polar moment "
                         f"({izz:.3g} m² per unit mass): no mass distribution has it")
    ixx = izz / 2 + thick_m * thick_m / 12
    I_Bo = RotationalInertia(m * ixx, m * ixx, m * izz)
    p_BoBcm = np.array([dx, dy, 0.0])
    return SpatialInertia.MakeFromCentralInertia(m, p_BoBcm, I_Bo.ShiftToCenterOfMass(m, p_BoBcm))


class _Controller(LeafSystem):
    """Support friction on the part (ellipsoidal limit surface about its true centre of
    mass, ``cfg.com_offset_m`` from the drawn one) and the desired state of the gripper and
    jaw actuators along the schedule (their PD loops run implicitly in the plant's SAP
    solver, with the jaw force capped by the actuators' effort limit)."""

    def __init__(self, nq: int, nv: int, idx: dict[str, tuple[int, int]], cfg: SimConfig,
                 f_max: float, m_max: float, outline: FloatArray) -> None:
        super().__init__()
        self._idx, self._cfg, self._f, self._m, self._nq = idx, cfg, f_max, m_max, nq
        self._outline = outline
        self.centring = True
        self.set_phases([Phase(0.0, 0.0, (0.0, 0.0), (0.0, 0.0), (0.0, 0.0), 0)])
        self.DeclareVectorInputPort("state", nq + nv)
        self.DeclareVectorOutputPort("forces", BasicVector(nv), self._forces)
        self.DeclareVectorOutputPort("desired_state", BasicVector(6), self._desired)

    def set_phases(self, phases: list[Phase]) -> None:
        self._phases = phases
        self._starts = [p.t0 for p in phases]
        self._shift: dict[int, float] = {}
        self.delay = 0.0  # simulated time spent waiting for the part to settle so far
        self.hold_at: float | None = None  # schedule time whose targets are held, while waiting

    def schedule_time(self, t: float) -> float:
        return self.hold_at if self.hold_at is not None else t - self.delay

    def phase(self, t: float) -> Phase:
        """The phase at simulated time ``t``."""
        return self._phases[max(bisect.bisect_right(self._starts, self.schedule_time(t)) - 1, 0)]

    def targets(self, t: float, x: FloatArray | None = None) -> tuple[float, float, float]:
        """Gripper angle and jaw targets at simulated time ``t``."""
        ph = self.phase(t)
        g, lo, hi = ph.at(self.schedule_time(t))
        if self.centring and ph.centre and ph.action not in self._shift and x is not None:
            self._shift[ph.action] = self._centre_offset(x, g)
        d = self._shift.get(ph.action, 0.0)
        return g, lo + d, hi + d

    def _centre_offset(self, x: FloatArray, g: float) -> float:
        """Midpoint of the part's extent along the closing axis n of gripper angle g."""
        pq, _ = self._idx["part"]
        n = np.array([-math.sin(g), math.cos(g)])
        return extent_midpoint(self._outline, x[pq], x[pq + 1], x[pq + 2], n)

    def _forces(self, context: Any, out: BasicVector) -> None:
        x = np.asarray(self.get_input_port(0).Eval(context))
        q, v = x[:self._nq], x[self._nq:]
        tau = np.zeros(len(v))
        pq, pv = self._idx["part"]
        tau[pv:pv + 3] = self.support_wrench(float(q[pq + 2]), v[pv:pv + 3])
        out.SetFromVector(tau)

    def support_wrench(self, theta: float, v_Bo: FloatArray) -> tuple[float, float, float]:
        """Support friction as generalized forces of the part's planar joint (N, N, N·m),
        at orientation θ (rad) and joint velocities (vx, vy of Bo in m/s, ω in rad/s).

        The limit surface is about the true centre of mass (``com_offset_m`` from Bo, the
        drawn one): its velocity v = v_Bo + ω × r, and the wrench (f, m) there moves to
        Bo as (f, m + r × f)."""
        c, s = math.cos(theta), math.sin(theta)
        dx, dy = self._cfg.com_offset_m
        rx, ry = c * dx - s * dy, s * dx + c * dy  # Bo → true centre of mass, world frame
        w = float(v_Bo[2])
        vx, vy = float(v_Bo[0]) - w * ry, float(v_Bo[1]) + w * rx
        # (f, m) = −(f_max² v, m_max² ω)/λ: the twist is normal to the ellipsoid; λ is
        # regularised below the stiction speed (explicit force: keeps the step stable).
        lam = math.sqrt(self._f**2 * (vx * vx + vy * vy) + self._m**2 * w * w
                        + (self._f * self._cfg.stiction_speed_m_s) ** 2)
        if lam == 0.0:  # no support friction (μ, m or g zero): nothing to divide
            return 0.0, 0.0, 0.0
        fx, fy, m = -self._f**2 * vx / lam, -self._f**2 * vy / lam, -self._m**2 * w / lam
        return fx, fy, m + rx * fy - ry * fx

    def _desired(self, context: Any, out: BasicVector) -> None:
        x = np.asarray(self.get_input_port(0).Eval(context))
        g, lo, hi = self.targets(context.get_time(), x)
        out.SetFromVector([g, lo, hi, 0.0, 0.0, 0.0])


def plant_config(cfg: SimConfig, variant: int = 0) -> MultibodyPlantConfig:
    """Discrete SAP, hydroelastic contact, at ``cfg.time_step_s`` (s) times the step
    factor of :data:`SOLVER_FALLBACKS` ``[variant]``, with its surface representation."""
    surface, step_factor = SOLVER_FALLBACKS[variant]
    return MultibodyPlantConfig(time_step=cfg.time_step_s * step_factor, discrete_contact_approximation="sap",
                                contact_model="hydroelastic_with_fallback", contact_surface_representation=surface)


class PlanarGripperSim:
    """Diagram of part + gripper; reusable for many runs of plans with the same action."""

    def __init__(self, part: Part, cfg: SimConfig = DEFAULT_SIM, variant: int = 0) -> None:
        """``variant`` indexes :data:`SOLVER_FALLBACKS` (0: the model as configured; the
        plant steps at ``cfg.time_step_s`` times the variant's factor)."""
        self.part, self.cfg, self.variant = part, cfg, variant
        self.geom = part_geometry(part, cfg)
        self._jaw_geometry: list[Any] = []
        self._fallbacks: dict[int, PlanarGripperSim] = {}  # by variant, built on first need
        self.fallback_runs = 0  # runs whose result came from a fallback variant
        self.sim_seconds = 0.0  # simulated time of the last run (s)
        builder = DiagramBuilder()
        plant, scene_graph = AddMultibodyPlant(plant_config(cfg, variant), builder)
        plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, 0.0])  # support friction is modelled
        self._add_bodies(plant)
        plant.Finalize()
        # The two jaws' half-spaces overlap beyond the part: only the part may touch them.
        scene_graph.collision_filter_manager().Apply(
            CollisionFilterDeclaration().ExcludeWithin(GeometrySet(self._jaw_geometry)))
        self.plant = plant
        idx = {name: (j.position_start(), j.velocity_start()) for name, j in self.joints.items()}
        f_max = cfg.support_friction * cfg.part_mass_kg * cfg.gravity_m_s2
        self.controller: Any = builder.AddSystem(_Controller(plant.num_positions(), plant.num_velocities(), idx,
                                                        cfg, f_max, f_max * self.geom.mean_radius_m,
                                                        self.geom.outline_m))
        builder.Connect(plant.get_state_output_port(), self.controller.get_input_port(0))
        builder.Connect(self.controller.get_output_port(0), plant.get_applied_generalized_force_input_port())
        builder.Connect(self.controller.get_output_port(1),
                        plant.get_desired_state_input_port(self._instance))
        self.diagram = builder.Build()
        self.simulator = Simulator(self.diagram)
        self._speed_limit = DIVERGED_SPEED_FACTOR * max(cfg.open_speed_m_s, cfg.jaw_speed_m_s)
        self.simulator.set_monitor(self._monitor)
        del scene_graph

    def _monitor(self, root: Any) -> EventStatus:
        """Fails the step (SAP diverged) when the part or a jaw moves faster than
        :data:`DIVERGED_SPEED_FACTOR` times the schedule's fastest jaw speed."""
        v = self.plant.GetVelocities(self.plant.GetMyContextFromRoot(root))
        pv = self.joints["part"].velocity_start()
        part = math.hypot(v[pv], v[pv + 1]) + abs(v[pv + 2]) * self.geom.reach_m
        jaws = max(abs(v[self.joints[name].velocity_start()]) for name in ("lower", "higher"))
        if max(part, jaws) > self._speed_limit:
            return EventStatus.Failed(self.diagram, f"{DIVERGED} at part speed {part:.3g} m/s, jaw speed {jaws:.3g} m/s "
                                      f"(limit {self._speed_limit:.3g} m/s)")
        return EventStatus.Succeeded()

    def _add_bodies(self, plant: Any) -> None:
        cfg, g = self.cfg, self.geom
        thick = max(0.2 * g.reach_m, MIN_THICKNESS_M)
        part = plant.AddRigidBody("part", part_inertia(cfg, g.polar_per_area_m2, thick))
        pts = np.vstack([np.column_stack([g.outline_m, np.full(len(g.outline_m), z)]) for z in (-thick / 2, thick / 2)])
        props = ProximityProperties()
        AddCompliantHydroelasticProperties(g.reach_m, cfg.hydroelastic_modulus_pa, props)
        _contact_material(props, cfg)
        plant.RegisterCollisionGeometry(part, RigidTransform(), Convex(pts.T, "part_hull"), "part", props)
        gripper = plant.AddRigidBody("gripper", SpatialInertia(0.1, np.zeros(3), UnitInertia(*BODY_GYRATION_M2)))
        jaws = {}
        for name, side in (("lower", -1.0), ("higher", 1.0)):
            body = plant.AddRigidBody(f"jaw_{name}", SpatialInertia(0.05, np.zeros(3), UnitInertia(*BODY_GYRATION_M2)))
            jp = ProximityProperties()
            AddRigidHydroelasticProperties(jp)
            _contact_material(jp, cfg)
            # A jaw face is a plane at the joint coordinate, solid away from the part (a
            # half-space occupies z ≤ 0 of its frame: turn +z onto the face's normal).
            # It touches the part exactly where a jaw longer than the part would, and
            # its contact surface is one plane clip of the part's mesh: 27–35 % less
            # wall time than a box of the same face, with the same agreement.
            X = RigidTransform(RotationMatrix.MakeXRotation(side * math.pi / 2), [0.0, 0.0, 0.0])
            self._jaw_geometry.append(plant.RegisterCollisionGeometry(body, X, HalfSpace(), f"jaw_{name}", jp))
            jaws[name] = body
        world = plant.world_frame()
        self.joints = {
            "part": plant.AddJoint(PlanarJoint("part_xy_theta", world, part.body_frame())),
            "gripper": plant.AddJoint(RevoluteJoint("gripper_angle", world, gripper.body_frame(), [0, 0, 1])),
            "lower": plant.AddJoint(PrismaticJoint("jaw_lower", gripper.body_frame(), jaws["lower"].body_frame(), [0, 1, 0])),
            "higher": plant.AddJoint(PrismaticJoint("jaw_higher", gripper.body_frame(), jaws["higher"].body_frame(), [0, 1, 0])),
        }
        self._instance = part.model_instance()
        # Implicit PD actuators (SAP): stiff gripper rotation; jaws capped at the grip force.
        for name, kp, kd, cap in (("gripper", 20.0, 0.05, 10.0),
                                  ("lower", cfg.jaw_stiffness_n_m, cfg.jaw_damping_n_s_m, cfg.jaw_force_n),
                                  ("higher", cfg.jaw_stiffness_n_m, cfg.jaw_damping_n_s_m, cfg.jaw_force_n)):
            act = plant.AddJointActuator(f"act_{name}", self.joints[name], cap)
            act.set_controller_gains(PdControllerGains(p=kp, d=kd))

    def run(self, phases: list[Phase], phi0: float, offset_m: float, alpha0: float, half_open_m: float,
            record: bool = False, centring: bool = True,
            checkpoints: tuple[float, ...] = ()) -> tuple[float, list[float], list[tuple[float, ...]]]:
        """Simulate from part orientation φ0 (rad), centred between the jaws of the first
        action up to ``offset_m`` along its closing axis. Returns the final φ (rad,
        unwrapped), φ at each checkpoint (schedule time), and, if asked, samples
        (t, x, y, φ, α, q_lower, q_higher). Simulated time runs ahead of schedule time
        by the waits for the part to settle (:attr:`sim_seconds` after the run).

        If Drake's solver fails, the run is repeated from the start on the next of
        :data:`SOLVER_FALLBACKS` (built once, on first need); if the run diverged
        (:data:`DIVERGED_SPEED_FACTOR`), on the last, finest-step one. The fallback's
        simulator then holds the final state. The last variant's failure is raised."""
        try:
            return self._run(phases, phi0, offset_m, alpha0, half_open_m, record, centring, checkpoints)
        except RuntimeError as exc:
            last = len(SOLVER_FALLBACKS) - 1
            nxt = last if DIVERGED in str(exc) else self.variant + 1  # a divergence needs the finest step
            if self.variant >= last:
                raise
        if nxt not in self._fallbacks:
            self._fallbacks[nxt] = PlanarGripperSim(self.part, self.cfg, nxt)
        fallback = self._fallbacks[nxt]
        result = fallback.run(phases, phi0, offset_m, alpha0, half_open_m, record, centring, checkpoints)
        self.sim_seconds, self.fallback_runs = fallback.sim_seconds, self.fallback_runs + 1
        return result

    def _run(self, phases: list[Phase], phi0: float, offset_m: float, alpha0: float, half_open_m: float,
             record: bool, centring: bool, checkpoints: tuple[float, ...]) -> tuple[float, list[float], list[tuple[float, ...]]]:
        """One run on this variant's diagram (see :meth:`run`)."""
        self.controller.set_phases(phases)
        self.controller.centring = centring
        ctx = self.simulator.get_mutable_context()
        ctx.SetTime(0.0)
        pc = self.plant.GetMyMutableContextFromRoot(ctx)
        self._place(pc, phi0, offset_m, alpha0, half_open_m)
        # The gripper starts where the schedule starts (an optimised cycle first turns
        # from the previous cycle's last angle); the part is placed for the first action.
        self.joints["gripper"].set_angle(pc, phases[0].gripper[0])
        self.simulator.Initialize()
        self._record = record
        samples: list[tuple[float, ...]] = []
        at: dict[float, float] = {}
        settles = {p.t1: p.action for p in phases if p.settle}
        for s in sorted(set(checkpoints) | set(settles) | {phases[-1].t1}):
            if s in settles:
                self._grip(pc, s, settles[s], samples)
            else:
                self._advance(pc, s + self.controller.delay, samples)
            at[s] = self._phi(pc)
        self.sim_seconds = self.simulator.get_context().get_time()
        return at[phases[-1].t1], [at[c] for c in checkpoints], samples

    def _advance(self, pc: Any, t: float, samples: list[tuple[float, ...]]) -> None:
        """Simulate up to time t, sampling at ``record_hz`` on the way if recording."""
        ctx = self.simulator.get_context()
        if self._record:
            step = 1.0 / self.cfg.record_hz
            k = math.floor(ctx.get_time() / step + PARAM_END) + 1
            while k * step < t - TIME_ROUNDING_S:
                self.simulator.AdvanceTo(k * step)
                samples.append(self._sample(k * step, self.plant.GetPositions(pc)))
                k += 1
        if t > ctx.get_time():
            self.simulator.AdvanceTo(t)
            if self._record:
                samples.append(self._sample(t, self.plant.GetPositions(pc)))

    def _grip(self, pc: Any, s: float, action: int, samples: list[tuple[float, ...]]) -> None:
        """Squeeze up to the hold ending at schedule time s, the way a gripper with grasp
        detection does: once, in this action, both jaws press with at least half the grip force and jaws
        and part have been still for ``settle_quiet_s``, the part is gripped and the
        schedule jumps to s; if s comes first, its targets are held until that happens
        (at most ``settle_max_s`` longer).

        Still means moved less than the settle speeds allow over each half of the quiet
        window: displacement, not instantaneous velocity, since a squeezed compliant
        contact chatters with a tiny amplitude but a real speed."""
        cfg, ctl = self.cfg, self.controller
        chunk, quiet, held = cfg.settle_quiet_s / 2, 0.0, 0.0
        before = self._pose(pc)
        while quiet < cfg.settle_quiet_s:
            t = self.simulator.get_context().get_time()
            if ctl.hold_at is None and t >= s + ctl.delay - TIME_ROUNDING_S:
                ctl.hold_at = s
            if ctl.hold_at is not None and held >= cfg.settle_max_s:
                break
            end = t + chunk if ctl.hold_at is not None else min(t + chunk, s + ctl.delay)
            self._advance(pc, end, samples)
            held += end - t if ctl.hold_at is not None else 0.0
            now = self._pose(pc)
            gripping = self.controller.phase(end).action == action
            quiet = quiet + (end - t) if gripping and self._still(before, now, end - t, end) else 0.0
            before = now
        ctl.delay, ctl.hold_at = self.simulator.get_context().get_time() - s, None

    def _pose(self, pc: Any) -> FloatArray:
        """(x, y, φ) of the part and the two jaw positions."""
        q = self.plant.GetPositions(pc)
        i = self.joints["part"].position_start()
        return np.array([q[i], q[i + 1], q[i + 2], q[self.joints["lower"].position_start()],
                         q[self.joints["higher"].position_start()]])

    def _still(self, before: FloatArray, now: FloatArray, dt: float, t: float) -> bool:
        """Part and jaws still over dt, with both jaws pressing (targets ≥ half the
        grip force's servo travel inside them)."""
        cfg = self.cfg
        _, lo, hi = self.controller.targets(t)
        press = 0.5 * cfg.jaw_force_n / cfg.jaw_stiffness_n_m
        return bool(math.hypot(*(now[:2] - before[:2])) < cfg.settle_speed_m_s * dt
                    and abs(now[2] - before[2]) < cfg.settle_rate_rad_s * dt
                    and np.all(np.abs(now[3:] - before[3:]) < cfg.settle_speed_m_s * dt)
                    and lo - now[3] >= press and now[4] - hi >= press)

    def _phi(self, pc: Any) -> float:
        return float(self.plant.GetPositions(pc)[self.joints["part"].position_start() + 2])

    def _place(self, pc: Any, phi0: float, offset_m: float, alpha0: float, half_open_m: float) -> None:
        self.plant.SetDefaultState(pc, pc.get_mutable_state())
        n = np.array([-math.sin(alpha0), math.cos(alpha0)])
        centre = -extent_midpoint(self.geom.outline_m, 0.0, 0.0, phi0, n) + offset_m
        self.joints["part"].set_translation(pc, centre * n)
        self.joints["part"].set_rotation(pc, phi0)
        self.joints["gripper"].set_angle(pc, alpha0)
        self.joints["lower"].set_translation(pc, -half_open_m)
        self.joints["higher"].set_translation(pc, half_open_m)

    def _sample(self, t: float, q: FloatArray) -> tuple[float, ...]:
        i = self.joints["part"].position_start()
        return (t, float(q[i]), float(q[i + 1]), float(q[i + 2]),
                float(q[self.joints["gripper"].position_start()]),
                float(q[self.joints["lower"].position_start()]), float(q[self.joints["higher"].position_start()]))
