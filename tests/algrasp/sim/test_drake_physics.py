"""Jaw friction and a displaced centre of mass in the Drake model, against statics
worked out by hand (marked ``sim``)."""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np
import pytest

pytest.importorskip("pydrake")

from pydrake.geometry import SceneGraph  # noqa: E402
from pydrake.multibody.plant import CalcContactFrictionFromSurfaceProperties, CoulombFriction  # noqa: E402

from algrasp.geometry.part import load_part  # noqa: E402
from algrasp.sim.config import OPEN_CLEARANCE_M, SimConfig, schedule  # noqa: E402
from algrasp.sim.model import PlanarGripperSim  # noqa: E402
from algrasp.testing import shapes  # noqa: E402

pytestmark = pytest.mark.sim


def _final_deg(sim: PlanarGripperSim, action: str, phi0_deg: float) -> float:
    """Final φ (degrees) of one action at gripper angle 0 from φ0, centred, with the
    validation's default jaw opening and push distance."""
    cfg, reach = sim.cfg, sim.geom.reach_m
    W = cfg.open_margin_factor * reach + OPEN_CLEARANCE_M
    phases = schedule([0.0], action, W, cfg.push_distance_factor * reach, cfg, reach_m=reach)
    phi, _, _ = sim.run(phases, math.radians(phi0_deg), 0.0, 0.0, W)
    return math.degrees(phi)


def _pair_friction(sim: PlanarGripperSim) -> list[float]:
    """Drake's combined μ of each jaw–part pair, read back from the scene graph."""
    scene_graph = sim.diagram.GetSubsystemByName("scene_graph")
    assert isinstance(scene_graph, SceneGraph)
    inspector, plant = scene_graph.model_inspector(), sim.plant

    def mu(body: str) -> CoulombFriction:
        (gid,) = plant.GetCollisionGeometriesForBody(plant.GetBodyByName(body))
        friction = inspector.GetProximityProperties(gid).GetProperty("material", "coulomb_friction")
        assert isinstance(friction, CoulombFriction)
        return friction

    return [CalcContactFrictionFromSurfaceProperties(mu("part"), mu(jaw)).dynamic_friction()
            for jaw in ("jaw_lower", "jaw_higher")]


def test_jaw_friction_holds_a_squeezed_rectangle_inside_its_sticky_band() -> None:
    """10 × 4 rectangle: d(θ) = 10|sin θ| + 4|cos θ| = √116·cos(θ − θ*), θ* = atan(10/4)
    = 68.2° (its maximum), so |d′/d| = |tan(θ − θ*)|. The jaws' friction couple μF·d
    holds the squeeze couple F·|d′| while |d′| ≤ μd: with μ = 0.3 every θ within
    atan 0.3 = 16.7° of θ* stays put. θ = 60° is 8.2° inside that band: frictionless
    jaws turn it to the minimum at 0°, μ = 0.3 jaws hold it. θ = 45° is 6.5° outside,
    and |d′/d| only grows on the way down to 0°, so it still turns all the way."""
    part = load_part(shapes.rectangle(10.0, 4.0))
    frictionless = PlanarGripperSim(part, SimConfig())
    sticky = PlanarGripperSim(part, replace(SimConfig(), jaw_friction=0.3))
    assert _pair_friction(frictionless) == [0.0, 0.0]
    assert _pair_friction(sticky) == pytest.approx([0.3, 0.3], abs=1e-12)
    theta_star, band = math.degrees(math.atan2(10.0, 4.0)), math.degrees(math.atan(0.3))
    assert 45.0 + 5.0 < theta_star - band < 60.0 - 5.0  # each start 5°+ clear of the band's edge
    assert abs(_final_deg(frictionless, "squeeze", 60.0)) < 1.0
    assert abs(_final_deg(sticky, "squeeze", 60.0) - 60.0) < 0.5
    assert abs(_final_deg(sticky, "squeeze", 45.0)) < 1.0


def test_centre_of_mass_offset_moves_the_push_boundary() -> None:
    """10 mm square pushed up (+y) by a frictionless jaw from φ0 = −38°: its lowest
    vertex (5, −5) mm is the contact. The push turns the part about its centre of
    friction, the true centre of mass c, towards the flat edge on the side c lies:
    the basin boundary is where that vertex is straight below c, φ = atan2(5, 5 − c_x)
    − 90°. Drawn centre (c = 0): boundary −45°, so −38° turns to 0°. True centre 2 mm
    along +x: boundary atan2(5, 3) − 90° = −31.0°, so −38° turns the other way, to
    −90°. The body's inertia must say the same: centre of mass at the offset and the
    central polar moment m((a² + b²)/12 − |c|²) (parallel axes)."""
    part = load_part(dict(shapes.rectangle(10.0, 10.0), units="mm"))
    offset = (2e-3, 0.0)
    sims = {c: PlanarGripperSim(part, replace(SimConfig(), com_offset_m=c)) for c in ((0.0, 0.0), offset)}
    cfg = sims[offset].cfg
    body = sims[offset].plant.GetBodyByName("part")
    M_BBo = body.default_spatial_inertia()
    np.testing.assert_allclose(M_BBo.get_com(), [2e-3, 0.0, 0.0], atol=1e-15)
    central = M_BBo.Shift(M_BBo.get_com()).CalcRotationalInertia().get_moments()
    assert M_BBo.get_mass() == cfg.part_mass_kg
    assert central[2] == pytest.approx(cfg.part_mass_kg * ((0.01**2 + 0.01**2) / 12 - 2e-3**2), rel=1e-6)
    for boundary in (-45.0, math.degrees(math.atan2(5.0, 3.0)) - 90.0):
        assert abs(-38.0 - boundary) > 5.0  # well clear of the unstable orientation
    assert abs(_final_deg(sims[(0.0, 0.0)], "push_grasp", -38.0)) < 1.0
    assert abs(_final_deg(sims[offset], "push_grasp", -38.0) + 90.0) < 1.0


def test_a_solver_failure_repeats_the_run_on_the_next_fallback(monkeypatch: pytest.MonkeyPatch) -> None:
    """Drake's SAP solver occasionally fails at a friction cone's edge (seen: 6 of 64 lens
    squeezes at μ 0.4); which runs fail depends on rounding, so the failure is injected
    where Drake raises it. The run is repeated on the triangle-quadrature variant and
    still ends where statics says: the 10 × 4 rectangle from θ = 30° (below the maximum
    of d at 68.2°) turns to 0°. When every variant fails, the last failure is raised."""
    from algrasp.sim import model

    real_run = model.PlanarGripperSim._run
    failing = {0}

    def run(self: model.PlanarGripperSim, *args: Any) -> Any:
        if self.variant in failing:
            raise RuntimeError("The SAP solver failed to converge at simulation time = 0.4.")
        return real_run(self, *args)

    monkeypatch.setattr(model.PlanarGripperSim, "_run", run)
    sim = PlanarGripperSim(load_part(shapes.rectangle(10.0, 4.0)), SimConfig())
    assert abs(_final_deg(sim, "squeeze", 30.0)) < 1.0
    assert sim.fallback_runs == 1 and sim.sim_seconds > 0.3
    failing.update(range(len(model.SOLVER_FALLBACKS)))
    with pytest.raises(RuntimeError, match="SAP solver failed"):
        _final_deg(sim, "squeeze", 30.0)


def test_a_diverged_contact_step_is_repeated_at_a_quarter_step() -> None:
    """Issue 30: the bracket (20.5 mm reach, Froude-similar 2 ms step) squeezed from 200°
    in the lightest, least-held corner of the default ranges (μ_s 0.2, 10 g, 1.6 N,
    frictionless jaws) turns fast onto the flat edge at d's minimum at 180°; at 2 ms SAP
    then flung part and jaw away (φ ended at about −1.2·10⁶°). The speed monitor stops that
    run and it is repeated on the finest-step variant, which ends at the minimum."""
    import json
    from pathlib import Path

    from algrasp.sim import model
    from algrasp.sim.config import similar_config
    from algrasp.sim.geometry import part_geometry

    doc = json.loads((Path(__file__).resolve().parents[3] / "algrasp" / "examples" / "bracket.json").read_text())
    part = load_part(doc)
    cfg = SimConfig(support_friction=0.2, part_mass_kg=0.01, jaw_force_n=1.6)
    cfg = similar_config(cfg, part_geometry(part, cfg).reach_m)
    assert cfg.time_step_s > 2e-3  # the step the divergence was seen at
    sim = PlanarGripperSim(part, cfg)
    assert abs(_final_deg(sim, "squeeze", 200.0) - 180.0) < 1.0
    assert sim.fallback_runs == 1
    assert list(sim._fallbacks) == [len(model.SOLVER_FALLBACKS) - 1]
    assert model.SOLVER_FALLBACKS[-1][1] == 0.25
