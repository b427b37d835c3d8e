"""Physics as ranges (conventions §8) against independent truth.

* Sticky bands by hand: with jaw friction μ_j a squeezed polygon rests where
  |d′| ≤ μ_j·d + s_d; for one pair of contact vertices d = L·cos(θ − θ₀), so without
  support friction that is |θ − θ₀| ≤ atan μ_j around every maximum of d.
* Brute force over sampled cells of the ranges (tests/algrasp/brute.py, which uses no
  algrasp): real parts perturbed within the profile tolerance, the centre of mass moved
  within its disk, support and jaw friction, mass and force drawn from their ranges, and
  for ``placement="any"`` a partial push by either jaw before every squeeze; 3,000 starts
  per cell, every outcome within the plan's claimed φ ± u.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from algrasp.errors import ConfigError, NotOrientableError
from algrasp.geometry.arcforms import document
from algrasp.planning.analysis import Model, analyse_document
from algrasp.planning.physics import DEFAULT_PHYSICS, IDEAL_CELL, PARAMETERS, Physics, cell_from_text
from algrasp.planning.plans import make_plan
from tests.algrasp.brute import ExactPart, Flow, worst_miss_deg
from tests.algrasp.test_robust import _generalized_polygon, _lens

STARTS = np.random.default_rng(11).uniform(0.0, 2 * math.pi, 3000)
GRID_SLACK_DEG = 0.003
CELL_GRID_DEG = 0.12  # the set-valued functions' cells (GRID_RAD, 0.115°)
G = 9.81


def _rectangle(w: float, h: float) -> tuple[dict, np.ndarray]:
    pts = np.array([[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]])
    return {"name": "rect", "units": "mm", "polygon": pts.tolist()}, pts


def _zones_deg(analysis: object, name: str) -> list[tuple[float, float]]:
    S = getattr(analysis.robust, name)  # type: ignore[attr-defined]
    return [(math.degrees(a), math.degrees(b)) for a, b in S.rest_zones]


def _maxima_deg(pts: np.ndarray) -> list[float]:
    """Maxima of the polygon's diameter function on a 0.001° grid (brute force)."""
    theta = np.radians(np.arange(0.0, 180.0, 0.001))
    psi = np.pi / 2 - theta
    u = np.stack([np.cos(psi), np.sin(psi)], axis=1)
    proj = u @ pts.T
    d = proj.max(axis=1) - proj.min(axis=1)
    i = np.nonzero((d > np.roll(d, 1)) & (d >= np.roll(d, -1)))[0]
    return [float(np.degrees(theta[k])) for k in i]


@pytest.mark.parametrize("mu", [0.1, 0.3])
def test_polygon_sticky_bands_are_atan_mu_around_maxima(mu: float) -> None:
    doc, pts = _rectangle(4.0, 2.0)
    cell = IDEAL_CELL.with_values(support_friction=(0.0, 0.0), jaw_friction=(0.0, mu))
    a = analyse_document(doc, Model(physics=cell))
    zones = _zones_deg(a, "squeeze")
    half = math.degrees(math.atan(mu))
    maxima = _maxima_deg(pts)
    assert len(zones) == len(maxima) == 2
    for m in maxima:
        z = min(zones, key=lambda z: abs((0.5 * (z[0] + z[1]) - m + 90) % 180 - 90))
        assert (0.5 * (z[0] + z[1]) - m + 90) % 180 - 90 == pytest.approx(0.0, abs=CELL_GRID_DEG)
        assert 0.5 * (z[1] - z[0]) == pytest.approx(half, abs=CELL_GRID_DEG)


def test_support_term_widens_the_band_as_derived() -> None:
    """|L sin φ| ≤ μ_j L cos φ + s, solved for φ by bisection here (L the diagonal)."""
    doc, pts = _rectangle(4.0, 2.0)
    mu = 0.2
    cell = IDEAL_CELL.with_values(jaw_friction=(0.0, mu))
    a = analyse_document(doc, Model(physics=cell))
    s = a.robust.band.stall_hi  # μ_s m g r̄ / F (tested against Monte Carlo r̄ in test_robust)
    L = math.hypot(4.0, 2.0)
    lo, hi = 0.0, math.pi / 4
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if L * math.sin(mid) <= mu * L * math.cos(mid) + s else (lo, mid)
    zones = _zones_deg(a, "squeeze")
    assert all(0.5 * (b - a_) == pytest.approx(math.degrees(lo), abs=CELL_GRID_DEG) for a_, b in zones)


def _perturbed(part: ExactPart, t: float, eps_c: float, rng: np.random.Generator) -> ExactPart:
    """The real part: every vertex and arc centre within t of the drawing, the centre
    of mass within ε_c of the drawn one."""
    def jitter(n: int, r: float) -> np.ndarray:
        a = rng.uniform(0.0, 2 * math.pi, n)
        rr = r * np.sqrt(rng.uniform(0.0, 1.0, n))
        return np.stack([rr * np.cos(a), rr * np.sin(a)], axis=1)

    verts = part.vertices + jitter(len(part.vertices), t)
    shift = jitter(len(part.arcs), t)
    arcs = tuple((cx + dx, cy + dy, R, a0, a1) for (cx, cy, R, a0, a1), (dx, dy) in zip(part.arcs, shift))
    com = np.asarray(part.com) + jitter(1, eps_c)[0]
    return ExactPart(verts, arcs, (float(com[0]), float(com[1])))


def _run_cell(real: ExactPart, plan: dict, stall: float, mu_j: float, any_placement: bool,
              rng: np.random.Generator) -> np.ndarray:
    """Final world orientations from STARTS in one cell, by brute force."""
    squeeze = Flow(real.diameter, stall, mu_j)
    push = Flow(real.radius, stall)
    phi = STARTS.copy()
    for step in plan["steps"]:
        alpha = math.radians(step["gripper_angle_deg"])
        theta = phi - alpha
        if plan["action"] == "push_grasp":
            theta = push(theta)
        elif any_placement:  # the first jaw to touch pushes the part some way first
            by_h = rng.uniform(size=len(theta)) < 0.5
            dest = np.where(by_h, push(theta + np.pi) - np.pi, push(theta))
            theta = theta + rng.uniform(size=len(theta)) * (dest - theta)
        phi = squeeze(theta) + alpha
    return np.mod(phi, 2 * np.pi)


def _cells(physics: Physics, rbar: float, eps_c: float, n: int, rng: np.random.Generator) -> list[tuple[float, float]]:
    """(stall, μ_j) of n cells: the corners of (μ_s, m, F, μ_j) first, then uniform draws."""
    out = []
    for corner in list(physics.corners())[: n // 2]:
        out.append((corner.support_friction[0] * corner.part_mass_kg[0] * G * rbar / corner.grip_force_n[0],
                    corner.jaw_friction[0]))
    while len(out) < n:
        mu, m, F, mj = (rng.uniform(*getattr(physics, k)) for k in ("support_friction", "part_mass_kg", "grip_force_n",
                                                                    "jaw_friction"))
        out.append((mu * m * G * (rbar + rng.uniform(-eps_c, eps_c)) / F, mj))
    return out


CASES = [
    ("gpolygon", _generalized_polygon, "push_grasp", DEFAULT_PHYSICS),
    ("lens", _lens, "squeeze", DEFAULT_PHYSICS),
    ("gpolygon-jaw-0.15", _generalized_polygon, "squeeze",
     DEFAULT_PHYSICS.with_values(jaw_friction=(0.0, 0.15), placement="centred")),
]


@pytest.mark.parametrize("name,make,action,physics", CASES, ids=[c[0] for c in CASES])
def test_plans_hold_in_every_sampled_cell(name: str, make: object, action: str, physics: Physics) -> None:
    outline, exact = make()  # type: ignore[operator]
    doc = document(outline, "arc")
    doc["center_of_mass"] = list(exact.com)
    plan = make_plan(analyse_document(doc, Model(physics=physics)), action).to_dict()  # type: ignore[arg-type]
    band = plan["dead_band"]
    rng = np.random.default_rng(5)
    for stall, mu_j in _cells(physics, band["mean_radius"], band["com_tolerance"], 8, rng):
        real = _perturbed(exact, band["profile_floor_per_rad"], band["com_tolerance"], rng)
        finals = _run_cell(real, plan, stall, mu_j, physics.placement == "any", rng)
        assert worst_miss_deg(finals, plan) <= plan["final_uncertainty_deg"] + GRID_SLACK_DEG, (stall, mu_j)


def _star_polygon(seed: int, n: int = 7, size: float = 20.0) -> np.ndarray:
    """A star-shaped polygon of n vertices (sorted random angles, radii 0.5–1 of size/2)."""
    rng = np.random.default_rng(seed)
    a = np.sort(rng.uniform(0.0, 2 * math.pi, n))
    r = rng.uniform(0.5, 1.0, n) * size / 2
    return np.column_stack([r * np.cos(a), r * np.sin(a)]).round(4)


def test_refusal_names_the_limits_and_a_plan_at_the_limit_holds() -> None:
    """A 20 mm polygon cannot be push-grasped into an orientation under the default ranges:
    its profile tolerance is too large. The refusal says the largest that works; a plan
    made with it holds by brute force on parts perturbed that much."""
    pts = _star_polygon(8)
    doc = {"name": "star-8", "units": "mm", "polygon": pts.tolist()}
    a = analyse_document(doc, Model())
    exact = ExactPart(pts, (), tuple(a.part.center_of_mass))  # type: ignore[arg-type]
    with pytest.raises(NotOrientableError) as err:
        make_plan(a, "push_grasp")
    limit = err.value.limits["profile_tolerance_max"]  # type: ignore[index]
    assert limit["bounded"] and limit["value"] > 0.0
    assert "profile tolerance ≤" in err.value.message
    at_limit = DEFAULT_PHYSICS.with_values(profile_tolerance=limit["value"])
    plan = make_plan(analyse_document(doc, Model(physics=at_limit)), "push_grasp").to_dict()
    band = plan["dead_band"]
    rng = np.random.default_rng(2)
    for stall, mu_j in _cells(at_limit, band["mean_radius"], band["com_tolerance"], 4, rng):
        real = _perturbed(exact, limit["value"], band["com_tolerance"], rng)
        finals = _run_cell(real, plan, stall, mu_j, False, rng)
        assert worst_miss_deg(finals, plan) <= plan["final_uncertainty_deg"] + GRID_SLACK_DEG


def test_largest_jaw_friction_is_where_plans_stop() -> None:
    """The reported jaw-friction limit separates μ_j at which a plan exists from those
    at which none does (checked just below and above it)."""
    outline, exact = _generalized_polygon()
    doc = document(outline, "arc")
    physics = IDEAL_CELL
    plan = make_plan(analyse_document(doc, Model(physics=physics)), "squeeze", limits="headline")
    got = plan.limits["jaw_friction_max"]  # type: ignore[index]
    assert got["bounded"]
    mu = got["value"]
    below = physics.with_values(jaw_friction=(0.0, 0.98 * mu))
    above = physics.with_values(jaw_friction=(0.0, 1.05 * mu))
    make_plan(analyse_document(doc, Model(physics=below)), "squeeze")
    with pytest.raises(NotOrientableError):
        make_plan(analyse_document(doc, Model(physics=above)), "squeeze")


@pytest.mark.parametrize("raw,field", [({"support_friction": 50}, "physics.support_friction"),
                                       ({"jaw_friction": [0.3, 0.1]}, "physics.jaw_friction"),
                                       ({"part_mass_kg": [0.1, 0.2, 0.3]}, "physics.part_mass_kg"),
                                       ({"grip_force_n": 0}, "physics.grip_force_n"),
                                       ({"placement": "sideways"}, "physics.placement"),
                                       ({"com_tolerance": -1}, "physics.com_tolerance"),
                                       ({"wobble": 1}, "physics.wobble")])
def test_bad_physics_is_refused_naming_the_field(raw: dict, field: str) -> None:
    with pytest.raises(ConfigError) as err:
        Physics.from_mapping(raw)
    assert err.value.field == field


def test_cells_and_presets() -> None:
    assert cell_from_text("ideal") == IDEAL_CELL
    assert cell_from_text('{"jaw_friction": 0.2}').jaw_friction == (0.2, 0.2)
    assert len(list(DEFAULT_PHYSICS.corners())) == 16  # μ_s, μ_j, m, F vary; gravity is one value
    with pytest.raises(ConfigError):
        cell_from_text("[1, 2]")


@pytest.mark.parametrize("changes", [{"jaw_friction": 0.3}, {"support_friction": [0.1, 0.2], "part_mass_kg": (1, 2)},
                                     {"profile_tolerance": 1, "placement": "centred", "creep": False},
                                     {"com_tolerance": None}, {}])
def test_with_values_equals_a_physics_built_whole(changes: dict[str, Any]) -> None:
    """with_values checks only the fields it is given: the copy equals (and hashes as)
    the physics constructed from every field, the changed ones included."""
    from dataclasses import asdict

    base = Physics(support_friction=(0.3, 0.4), com_tolerance=0.5)
    whole = Physics(**{**asdict(base), **changes})
    got = base.with_values(**changes)
    assert got == whole and hash(got) == hash(whole) and got.to_dict() == whole.to_dict()
    assert all(type(v) is float for n in PARAMETERS for v in getattr(got, n))


@pytest.mark.parametrize("changes", [{"jaw_friction": -1}, {"creep": 1}, {"placement": "x"}, {"profile_tolerance": -2},
                                     {"grip_force_n": 0.0}, {"part_mass_kg": [1, 2, 3]}])
def test_with_values_refuses_what_construction_refuses(changes: dict[str, Any]) -> None:
    with pytest.raises(ConfigError) as whole:
        Physics(**changes)
    with pytest.raises(ConfigError) as copied:
        DEFAULT_PHYSICS.with_values(**changes)
    assert str(copied.value) == str(whole.value)
