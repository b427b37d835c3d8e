"""Drake validation of a fence design on a conveyor belt (conventions §9).

The part (the gripper validation's geometry, inertia and hydroelastic contact, from
``model`` and ``geometry``) lies on a belt moving at ``belt_speed`` along world +x. The
belt is a kinematically driven plate: its only effect on the part is the support
friction (the ellipsoidal limit surface of ``config``) with the part's velocity taken
relative to the belt's surface, ``v − (v_belt, 0)``; the fences and the two rails are
fixed walls (rigid hydroelastic boxes welded to the world) at the layout's positions,
angles and lengths, with the part–fence friction at the middle of its range. So the
layout's frame is the simulation's frame: the recorded part moves down the belt past
fences that stand still, as a camera over a real feeder would see it.

Each sample starts at a seeded random orientation, its centre of mass 2a upstream of the
first fence's root (a the covering radius) and a seeded random distance from the first
fence's rail between the part's own extent and 2a (where the layout lets parts enter); it
ends when the part's centre is 2a past the layout's end (the exit guide's, a wall like the
fences). It agrees when its final orientation is within the document's claimed
uncertainty plus ``tolerance_deg`` of a claimed final orientation (past the exit guide,
:meth:`FenceLayout.claim`), modulo the design's symmetry period T.
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, field, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from algrasp.errors import SimulationError
from algrasp.geometry.angles import to_deg, wrap_deg
from algrasp.geometry.part import Part
from algrasp.geometry.units import meters_per_unit
from algrasp.planning.physics import Physics
from algrasp.sim.config import DEFAULT_SIM, MIN_THICKNESS_M, SimConfig, sim_config, similar_config
from algrasp.sim.geometry import Geometry, part_geometry

if TYPE_CHECKING:
    from optimisation.fence_layout import FenceLayout

BELT_SPEED_M_S = 0.05
"""Belt speed at the similarity reach (5 mm); a larger part runs on a Froude-similar belt
(× √(reach / 5 mm), as the jaws' speeds are scaled): 0.106 m/s for a 22 mm reach. Real
feeder belts run 0.05–0.5 m/s; the fence model is quasi-static, so the slow end."""
TOLERANCE_DEG = 0.25
"""A sample agrees within the design's uncertainty plus this."""
END_MARGIN = 2.0
"""A run ends when the part's centre is this many covering radii past the last tip."""
TIME_FACTOR = 2.0
"""A run is given this many times the quasi-static time of the layout: the belt's over its
length plus, per fence, its length at the speed a part slides along it, v (cos β − μ sin β)
(Coulomb sliding on the wall, the belt's drag along −x relative to the part; at least 0.05 v)."""


@dataclass(frozen=True)
class Wall:
    """A straight wall in metres: from ``start`` along (cos α, sin α) for ``length``;
    the part is on the side of n = (−sin α, cos α), the wall's solid behind it."""

    start: tuple[float, float]
    alpha: float
    length: float
    name: str


def walls_m(layout: FenceLayout, scale: float, pad: float) -> list[Wall]:
    """The rails (``pad`` metres beyond the layout at both ends) and the fences, in metres."""
    W = layout.belt_width * scale
    last = layout_end(layout) * scale
    x0, x1 = -pad, last + pad
    out = [Wall((x0, 0.0), 0.0, x1 - x0, "rail_right"), Wall((x1, W), math.pi, x1 - x0, "rail_left")]
    for i, (a, n) in enumerate(zip(layout.design.angles, layout.lengths)):
        # The wall runs along (cos α, sin α) from root to tip on the right rail, from tip
        # to root on the left (α = π − β points upstream and towards the left rail).
        x, y = layout.root(i) if layout.design.sides[i] == 0 else layout.tip(i)
        out.append(Wall((x * scale, y * scale), float(a), n * scale, f"fence_{i + 1}"))
    if layout.tail is not None:  # chords of at most 2°, part side as the fence's (their left)
        pts = layout.tail_points(max(4, math.ceil(to_deg(layout.tail.sweep) / 2.0)))
        if layout.design.sides[-1] == 1:
            pts = pts[::-1]
        for k, (p, q) in enumerate(zip(pts[:-1], pts[1:])):
            d = (q[0] - p[0], q[1] - p[1])
            out.append(Wall((p[0] * scale, p[1] * scale), math.atan2(d[1], d[0]), math.hypot(*d) * scale, f"tail_{k}"))
    if layout.exit is not None:  # from its start on the right rail, from its end on the left (part on its left)
        (x0, y0), (x1, y1) = layout.exit_points()
        x, y = (x0, y0) if layout.exit.side == 0 else (x1, y1)
        out.append(Wall((x * scale, y * scale), layout.exit.angle, layout.exit_length * scale, "exit_guide"))
    return out


def layout_end(layout: FenceLayout) -> float:
    """The largest x of the fences, the tail and the exit guide (part units)."""
    xs = [layout.tip(i)[0] for i in range(len(layout.lengths))] + [x for x, _ in layout.tail_points()]
    xs += [x for x, _ in layout.exit_points()]
    return max(xs)


@dataclass(frozen=True)
class BeltSample:
    """One start: world orientations in degrees, the start's distance from the first
    fence's rail in the part's unit."""

    initial_deg: float
    lateral: float
    simulated_deg: float
    error_deg: float
    agrees: bool
    sim_seconds: float
    on_last_fence_deg: float | None = None
    """φ when the part's centre is a (its covering radius) short of the last fence's tip,
    along the fence: the push's outcome before the part comes off (None: never got there)."""
    on_last_fence_error_deg: float | None = None
    """Its distance from the design's own finals (without the tail's turn), modulo T."""
    finished: bool = True
    """The part got 2a past the layout in the time given (else it does not agree)."""


@dataclass(frozen=True)
class BeltValidation:
    """A fence design simulated on a belt from ``samples`` seeded starts."""

    samples: tuple[BeltSample, ...]
    agreement: float
    agreement_on_last_fence: float
    tolerance_deg: float
    final_orientations_deg: tuple[float, ...]
    final_uncertainty_deg: float
    symmetry_period_deg: float
    belt_speed_m_s: float
    support_friction: float
    fence_friction: float
    seed: int
    wall_seconds: float
    model: dict[str, Any]
    trajectories: tuple[list[tuple[float, float, float, float]], ...] = field(default=(), repr=False)
    """Per sample (t, x, y, φ) in SI units, if recorded."""
    run_id: str | None = None
    tail: bool = False
    walls: tuple[Wall, ...] = field(default=(), repr=False)
    """The simulated walls (metres), for records."""
    outline_m: Any = field(default=None, repr=False)
    """The part's collision outline about its centre of mass (metres), for records."""

    def to_dict(self) -> dict[str, Any]:
        """The fence validation document (degrees; lateral starts in the part's unit)."""
        return {"samples": [asdict(s) for s in self.samples], "agreement": self.agreement,
                "agreement_on_last_fence": self.agreement_on_last_fence, "tail": self.tail,
                "tolerance_deg": self.tolerance_deg, "final_orientations_deg": list(self.final_orientations_deg),
                "final_uncertainty_deg": self.final_uncertainty_deg, "symmetry_period_deg": self.symmetry_period_deg,
                "belt_speed_m_s": self.belt_speed_m_s, "support_friction": self.support_friction,
                "fence_friction": self.fence_friction, "seed": self.seed, "wall_seconds": self.wall_seconds,
                "model": self.model, "run_id": self.run_id}


def angle_error_deg(phi_deg: float, finals_deg: list[float] | tuple[float, ...], period_deg: float) -> float:
    """Distance (degrees) of φ from the nearest claimed final orientation, modulo T."""
    return min(abs((phi_deg - f + 0.5 * period_deg) % period_deg - 0.5 * period_deg) for f in finals_deg)


class BeltSim:
    """Part + belt + fixed fences; reusable for many starts of one layout."""

    def __init__(self, part: Part, layout: FenceLayout, cfg: SimConfig, belt_speed_m_s: float) -> None:
        from pydrake.geometry import (
            AddCompliantHydroelasticProperties,
            AddContactMaterial,
            AddRigidHydroelasticProperties,
            Box,
            Convex,
            ProximityProperties,
        )
        from pydrake.math import RigidTransform, RotationMatrix
        from pydrake.multibody.plant import AddMultibodyPlant
        from pydrake.multibody.tree import PlanarJoint
        from pydrake.systems.analysis import Simulator
        from pydrake.systems.framework import DiagramBuilder

        from algrasp.sim.model import jaw_contact_friction, part_inertia, plant_config

        self.part, self.layout, self.cfg, self.v = part, layout, cfg, belt_speed_m_s
        self.geom: Geometry = part_geometry(part, cfg)
        self.scale = meters_per_unit(part.units)
        a = self.geom.reach_m
        self.walls = walls_m(layout, self.scale, (END_MARGIN + 2.0) * a)
        builder = DiagramBuilder()
        plant, _ = AddMultibodyPlant(plant_config(cfg), builder)
        plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, 0.0])  # support friction is modelled
        thick = max(0.2 * a, MIN_THICKNESS_M)
        body = plant.AddRigidBody("part", part_inertia(cfg, self.geom.polar_per_area_m2, thick))
        outline = self.geom.outline_m
        pts = np.vstack([np.column_stack([outline, np.full(len(outline), z)]) for z in (-thick / 2, thick / 2)])
        props = ProximityProperties()
        AddCompliantHydroelasticProperties(a, cfg.hydroelastic_modulus_pa, props)
        AddContactMaterial(None, None, jaw_contact_friction(cfg.jaw_friction), props)
        props.AddProperty("material", "relaxation_time", cfg.relaxation_time_s / 2)
        plant.RegisterCollisionGeometry(body, RigidTransform(), Convex(np.asarray(pts.T, dtype=np.float64), "part_hull"),
                                        "part", props)
        self.wall_thickness_m = max(0.3 * a, MIN_THICKNESS_M)
        for w in self.walls:
            wp = ProximityProperties()
            AddRigidHydroelasticProperties(wp)
            AddContactMaterial(None, None, jaw_contact_friction(cfg.jaw_friction), wp)
            wp.AddProperty("material", "relaxation_time", cfg.relaxation_time_s / 2)
            c, s = math.cos(w.alpha), math.sin(w.alpha)
            t = self.wall_thickness_m
            centre = np.array([w.start[0] + 0.5 * w.length * c + 0.5 * t * s,
                               w.start[1] + 0.5 * w.length * s - 0.5 * t * c, 0.0])
            X = RigidTransform(RotationMatrix.MakeZRotation(w.alpha), centre)
            plant.RegisterCollisionGeometry(plant.world_body(), X, Box(w.length, t, 4.0 * thick), w.name, wp)
        self.joint = plant.AddJoint(PlanarJoint("part_xy_theta", plant.world_frame(), body.body_frame()))
        plant.Finalize()
        self.plant = plant
        f_max = cfg.support_friction * cfg.part_mass_kg * cfg.gravity_m_s2
        self.support = builder.AddSystem(_BeltFriction(plant.num_positions(), cfg, f_max, f_max * self.geom.mean_radius_m,
                                                       belt_speed_m_s))
        builder.Connect(plant.get_state_output_port(), self.support.get_input_port(0))
        builder.Connect(self.support.get_output_port(0), plant.get_applied_generalized_force_input_port())
        self.diagram = builder.Build()
        self.simulator = Simulator(self.diagram)
        last = layout_end(layout) * self.scale
        k = len(layout.lengths) - 1
        self._root = np.array(layout.root(k)) * self.scale
        tip = np.array(layout.tip(k)) * self.scale
        self._along = (tip - self._root) / float(np.hypot(*(tip - self._root)))
        self._check_at = float(np.hypot(*(tip - self._root))) - a
        self.x_start, self.x_end = -2.0 * a, last + END_MARGIN * a
        mu = cfg.jaw_friction
        slide = sum(n * self.scale / max(math.cos(b) - mu * math.sin(b), 0.05) for n, b in zip(layout.lengths, layout.steepness))
        self.t_max = TIME_FACTOR * (self.x_end - self.x_start + slide) / belt_speed_m_s

    def start_y(self, phi0: float, u: float) -> float:
        """The start's centre y (m): a fraction u of the way from touching the first
        fence's rail (the part's own extent across the belt at φ0) to 2a from it."""
        c, s = math.cos(phi0), math.sin(phi0)
        ys = self.geom.outline_m @ np.array([s, c])  # y of the rotated outline about the centre of mass
        first_right = self.layout.design.sides[0] == 0
        near = float(-ys.min()) if first_right else float(ys.max())
        near += 1e-4 * self.geom.reach_m
        d = near + u * max(2.0 * self.geom.reach_m - near, 0.0)
        return d if first_right else self.layout.belt_width * self.scale - d

    def run(self, phi0: float, y0: float,
            record: bool = False) -> tuple[float, float, float | None, list[tuple[float, float, float, float]]]:
        """Simulate one start (φ0 rad, centre y0 m): the final φ (rad, unwrapped), the
        simulated time (s), φ on the last fence (see :class:`BeltSample`) and, if asked,
        samples (t, x, y, φ) at ``record_hz``."""
        ctx = self.simulator.get_mutable_context()
        ctx.SetTime(0.0)
        pc = self.plant.GetMyMutableContextFromRoot(ctx)
        self.plant.SetDefaultState(pc, pc.get_mutable_state())
        self.joint.set_translation(pc, [self.x_start, y0])
        self.joint.set_rotation(pc, phi0)
        self.joint.set_translational_velocity(pc, [self.v, 0.0])  # riding on the belt
        self.simulator.Initialize()
        step = 1.0 / self.cfg.record_hz
        samples: list[tuple[float, float, float, float]] = []
        t = 0.0
        i = self.joint.position_start()
        on_fence: float | None = None
        while True:
            q = self.plant.GetPositions(pc)
            if on_fence is None and float((q[i:i + 2] - self._root) @ self._along) >= self._check_at:
                on_fence = float(q[i + 2])
            if record:
                samples.append((t, float(q[i]), float(q[i + 1]), float(q[i + 2])))
            if q[i] >= self.x_end or t >= self.t_max:
                break
            t += step
            self.simulator.AdvanceTo(t)
        self.finished = bool(self.plant.GetPositions(pc)[i] >= self.x_end)
        return float(self.plant.GetPositions(pc)[i + 2]), t, on_fence, samples


def _belt_friction_class() -> Any:
    from pydrake.systems.framework import BasicVector, LeafSystem

    class BeltFriction(LeafSystem):  # type: ignore[misc]
        """Support friction of the belt on the part: the limit surface of ``config`` about
        the true centre of mass, at the part's velocity relative to the belt's surface."""

        def __init__(self, nq: int, cfg: SimConfig, f_max: float, m_max: float, belt_speed: float) -> None:
            super().__init__()
            self._nq, self._cfg, self._f, self._m, self._v = nq, cfg, f_max, m_max, belt_speed
            self.DeclareVectorInputPort("state", 2 * nq)
            self.DeclareVectorOutputPort("forces", BasicVector(nq), self._forces)

        def _forces(self, context: Any, out: Any) -> None:
            x = np.asarray(self.get_input_port(0).Eval(context))
            theta, vx0, vy0, w = float(x[2]), float(x[self._nq]), float(x[self._nq + 1]), float(x[self._nq + 2])
            c, s = math.cos(theta), math.sin(theta)
            dx, dy = self._cfg.com_offset_m
            rx, ry = c * dx - s * dy, s * dx + c * dy
            vx, vy = vx0 - w * ry - self._v, vy0 + w * rx  # relative to the belt's surface
            lam = math.sqrt(self._f**2 * (vx * vx + vy * vy) + self._m**2 * w * w
                            + (self._f * self._cfg.stiction_speed_m_s) ** 2)
            if lam == 0.0:
                out.SetFromVector([0.0, 0.0, 0.0])
                return
            fx, fy, m = -self._f**2 * vx / lam, -self._f**2 * vy / lam, -self._m**2 * w / lam
            out.SetFromVector([fx, fy, m + rx * fy - ry * fx])

    return BeltFriction


def _BeltFriction(nq: int, cfg: SimConfig, f_max: float, m_max: float, belt_speed: float) -> Any:  # noqa: N802
    return _belt_friction_class()(nq, cfg, f_max, m_max, belt_speed)


def belt_config(physics: Physics, fence_friction: tuple[float, float], reach_m: float,
                base: SimConfig = DEFAULT_SIM) -> tuple[SimConfig, float]:
    """The simulation's settings for one cell (the middle of every range, the fence
    friction's too, as the part–wall μ) and the belt speed (m/s), Froude-similar."""
    cfg = sim_config(physics, base)
    mu = 0.5 * (fence_friction[0] + fence_friction[1])
    from algrasp.sim.config import FRICTION_TIME_STEP_S

    cfg = replace(cfg, jaw_friction=mu, time_step_s=min(cfg.time_step_s, FRICTION_TIME_STEP_S) if mu > 0 else cfg.time_step_s)
    k = math.sqrt(reach_m / cfg.similarity_reach_m) if cfg.similarity_reach_m > 0 and reach_m > cfg.similarity_reach_m else 1.0
    return similar_config(cfg, reach_m), BELT_SPEED_M_S * k


def validate_fences(part: Part, layout: FenceLayout, physics: Physics, samples: int = 3, seed: int = 0,
                    tolerance_deg: float = TOLERANCE_DEG, record: bool = False,
                    base: SimConfig = DEFAULT_SIM, wall_friction: float | None = None) -> BeltValidation:
    """Simulate ``layout`` (designed for ``part``) from ``samples`` seeded starts, in
    process, with the part–wall μ ``wall_friction`` (None: the middle of the design's
    fence friction range). Raises SimulationError when Drake cannot simulate the part."""
    reach_m = part_geometry(part, base).reach_m
    walls = layout.design.rules.friction if wall_friction is None else (wall_friction, wall_friction)
    cfg, v = belt_config(physics, walls, reach_m, base)
    sim = BeltSim(part, layout, cfg, v)
    rng = np.random.default_rng(seed)
    phi0 = rng.uniform(0.0, 2 * math.pi, samples)
    u = rng.uniform(0.0, 1.0, samples)
    d = layout.design
    design_finals = [round(float(to_deg(f)), 9) for f in d.final_orientations]
    claimed, claimed_unc = layout.claim()
    finals = [round(float(to_deg(f)) % 360.0, 9) for f in claimed]
    T = float(to_deg(d.symmetry))
    allowed = float(to_deg(claimed_unc)) + tolerance_deg
    allowed_on_fence = float(to_deg(d.final_uncertainty)) + tolerance_deg
    out: list[BeltSample] = []
    trajs: list[list[tuple[float, float, float, float]]] = []
    t0 = time.perf_counter()
    for p, uu in zip(phi0, u):
        y0 = sim.start_y(float(p), float(uu))
        try:
            phi, secs, on_fence, traj = sim.run(float(p), y0, record)
        except RuntimeError as exc:
            raise SimulationError(str(exc).splitlines()[0][:300], f"part reach {1e3 * reach_m:.3g} mm") from None
        err = angle_error_deg(float(to_deg(phi)), finals, T)
        lateral = (y0 if d.sides[0] == 0 else layout.belt_width * sim.scale - y0) / sim.scale
        fe = None if on_fence is None else angle_error_deg(float(to_deg(on_fence)), design_finals, T)
        out.append(BeltSample(wrap_deg(float(to_deg(p))), lateral, wrap_deg(float(to_deg(phi))), err,
                              sim.finished and err <= allowed, secs,
                              None if on_fence is None else wrap_deg(float(to_deg(on_fence))), fe, sim.finished))
        trajs.append(traj)
    wall = time.perf_counter() - t0
    model = {"reach_m": sim.geom.reach_m, "chord_error_m": sim.geom.chord_error_m, "wall_thickness_m": sim.wall_thickness_m,
             **{k: [float(x) for x in val] if isinstance(val, tuple) else float(val) for k, val in asdict(cfg).items()}}
    on = sum(s.on_last_fence_error_deg is not None and s.on_last_fence_error_deg <= allowed_on_fence
             for s in out) / len(out)
    return BeltValidation(tuple(out), sum(s.agrees for s in out) / len(out), on, tolerance_deg, tuple(finals),
                          float(to_deg(claimed_unc)), T, v, cfg.support_friction, cfg.jaw_friction, seed, wall,
                          model, tuple(trajs), tail=layout.tail is not None, walls=tuple(sim.walls),
                          outline_m=sim.geom.outline_m)


def record_validation(v: BeltValidation, layout: FenceLayout, part_doc: dict[str, Any], options: dict[str, Any],
                      directory: Any = None) -> BeltValidation:
    """Write ``v`` as one MCAP run record (``/request``, ``/fences``, ``/fence_validation``,
    ``/scene`` and ``/tf`` of every sample, ``/run``); ``v`` with its ``run_id``."""
    from algrasp.io.record.recorder import RunRecorder

    with RunRecorder(directory) as rec:
        rec.summary.update({"command": "fences", "part_name": part_doc.get("name"), "agreement": v.agreement,
                            "steps": len(layout.lengths)})
        rec.write("/request", {"run_id": rec.run_id, "command": "fences", "part": part_doc, "options": options})
        rec.write("/fences", dict(layout.to_dict()))
        rec.write("/fence_validation", v.to_dict())
        if v.outline_m is not None:
            runs: list[list[tuple[float, ...]]] = [list(t) for t in v.trajectories]
            rec.belt_trajectories(v.outline_m, list(v.walls), float(v.model["wall_thickness_m"]), runs)
    return replace(v, run_id=rec.run_id)
