"""Conveyor fences (conventions §9), held to values computed here independently: every
design is run from 3,600 starts by composing p(φ − α) + α of the brute-force push of
``tests.algrasp.brute`` (which uses nothing of algrasp) with the fence's friction: the part
descends on r′ + s μ r (s = +1 on the right rail, −1 on the left) for μ sampled over the
fence friction range; counts are checked against a square and a rectangle by hand and an
independent breadth-first search over angle grids, every fence angle against the
admissibility rules, and a disk is refused."""

from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from algrasp.errors import ConfigError, NotOrientableError
from algrasp.planning.analysis import EXACT, IDEAL, Model, analyse_document
from algrasp.planning.fence_model import push_of
from algrasp.planning.fences import FenceDesign, FenceRules, _search, design_fences, fence_rules
from algrasp.planning.physics import DEFAULT_PHYSICS
from tests.algrasp import brute

ROOT = Path(__file__).resolve().parents[3]
EXAMPLES = ROOT / "algrasp" / "examples"
SQUARE = [[0, 0], [4, 0], [4, 4], [0, 4]]
RECT = [[0, 0], [4, 0], [4, 2], [0, 2]]
TRIANGLE = [[0, 0], [5, 0], [1, 3]]
STARTS = np.linspace(0.0, 2 * np.pi, 3600, endpoint=False) + 1e-4  # off any unstable equilibrium
BERRETTY = FenceRules(exit_steepness=None, exit_turns=False)
"""Berretty et al.'s model: the part keeps its orientation between fences, no exit guide
(the exit model is held to the brute force in ``test_fence_exit.py``)."""


def _poly(vertices: list[list[float]], name: str = "p") -> dict[str, object]:
    return {"name": name, "boundary": vertices}


def _exact_part(vertices: list[list[float]]) -> brute.ExactPart:
    v = np.array(vertices, dtype=float)
    x, y = v[:, 0], v[:, 1]
    cross = x * np.roll(y, -1) - np.roll(x, -1) * y
    area = cross.sum() / 2
    com = ((x + np.roll(x, -1)) * cross).sum() / (6 * area), ((y + np.roll(y, -1)) * cross).sum() / (6 * area)
    return brute.ExactPart(v, (), com)


_FLOWS: dict[tuple[int, float], tuple[brute.ExactPart, brute.Flow]] = {}


def fence_flow(part: brute.ExactPart, alpha: float, mu: float) -> brute.Flow:
    """The brute-force push of a fence at world angle α with wall friction μ: the part
    descends on r′ + s μ r, s = +1 on the right rail (α < 90°: it slides downstream along
    the wall's direction, friction against it), −1 on the left."""
    key = (id(part), mu if alpha < math.pi / 2 else -mu)
    if key not in _FLOWS:  # the part is kept with its flow, so its id is not reused
        _FLOWS[key] = (part, brute.Flow(part.radius, 0.0, wall_friction=key[1]))
    return _FLOWS[key][1]


def _simulate(part: brute.ExactPart, angles: tuple[float, ...], starts: np.ndarray = STARTS,
              mu: float = 0.0) -> np.ndarray:
    """World orientations after the fences, by the brute-force push with wall friction μ (radians, [0, 2π))."""
    phi = starts.copy()
    for a in angles:
        phi = fence_flow(part, a, mu)(phi - a) + a
    return np.mod(phi, 2 * np.pi)


def mus(rules: FenceRules) -> np.ndarray:
    """Wall frictions sampled over the rules' fence friction range (its ends included)."""
    return np.linspace(rules.friction[0], rules.friction[1], 3)


def _worst_over_friction(part: brute.ExactPart, design: FenceDesign, angles: tuple[float, ...] | None = None,
                         turn: float = 0.0) -> float:
    """The worst miss (degrees) over the sampled frictions, the final orientations turned back by ``turn``."""
    return max(_worst_miss_deg(np.mod(_simulate(part, angles or design.angles, mu=float(mu)) - turn, 2 * np.pi), design)
               for mu in mus(design.rules))


def _worst_miss_deg(finals: np.ndarray, design: FenceDesign) -> float:
    want = np.array(design.final_orientations)
    diff = np.abs((finals[:, None] - want[None, :] + np.pi) % (2 * np.pi) - np.pi).min(axis=1)
    return float(np.degrees(diff.max()))


def _admissible(design: FenceDesign, rules: FenceRules) -> None:
    """Every angle in its side's admissible set, sides alternating, consecutive differences
    in the derived interval: (2 atan μ_f, 180° − 2β_min] right → left, the negative left → right."""
    psi = math.atan(rules.friction[1])
    for a, s in zip(design.angles, design.sides):
        beta = a if s == 0 else math.pi - a
        assert rules.min_steepness - 1e-9 <= beta < math.pi / 2 - psi, (a, s)
        assert (a < math.pi / 2) == (s == 0)
    for (a0, s0), (a1, s1) in zip(zip(design.angles, design.sides), zip(design.angles[1:], design.sides[1:])):
        assert s0 != s1
        d = a1 - a0 if s0 == 0 else a0 - a1
        assert 2 * psi < d <= math.pi - 2 * rules.min_steepness + 1e-9


def test_square_needs_one_fence() -> None:
    """By hand: a square (T = 90°) pushed by any wall comes to rest with a side flat on it."""
    design = design_fences(analyse_document(_poly(SQUARE), EXACT), BERRETTY)
    assert len(design.angles) == 1
    assert math.degrees(design.symmetry) == pytest.approx(90.0)
    assert _worst_over_friction(_exact_part(SQUARE), design) < 0.01


def test_rectangle_needs_two_fences_in_the_derived_window() -> None:
    """By hand: after one fence a 4 × 2 rectangle lies on a long or a short side (90° apart,
    T = 180°): relative to the next fence, turned by δ, at x = 90° − δ and x + 90°. The
    long-side basin is (26.57°, 153.43°) (vertices at 90° ± atan 2); the fence's friction
    moves both its ends by s atan μ (s = +1 right rail, −1 left), so over μ ∈ [0.1, 0.3]
    both arcs must lie in (26.57° + atan 0.3, 153.43° + atan 0.1) on the right rail and in
    (26.57° − atan 0.1, 153.43° − atan 0.3) on the left, i.e. x or x − 90° in (a, b − 90°)."""
    rules = BERRETTY
    design = design_fences(analyse_document(_poly(RECT), EXACT), rules)
    assert len(design.angles) == 2
    _admissible(design, rules)
    lo_mu, hi_mu = (math.degrees(math.atan(m)) for m in rules.friction)
    a, b = (26.57 + hi_mu, 153.43 + lo_mu) if design.sides[1] == 0 else (26.57 - lo_mu, 153.43 - hi_mu)
    x = (90.0 - math.degrees(design.angles[1] - design.angles[0])) % 90.0
    assert a < x < b - 90.0 or a < x + 90.0 < b - 90.0
    assert _worst_over_friction(_exact_part(RECT), design) < 0.01


def _fig11_doc(z_deg: float = 11.0, R: float = 10.0) -> dict[str, object]:
    """The paper's Fig. 11 part with exact arcs (the example file draws them as cubics)."""
    z = math.radians(z_deg)
    sx, c = R * math.sin(z), R * math.cos(z)
    arc = {"type": "arc", "center": [0, 0], "radius": R}
    return {"name": "fig11", "boundary": [
        {"type": "line", "start": [sx, c], "end": [-sx, c]}, {**arc, "start_deg": 90 + z_deg, "end_deg": 270 - z_deg},
        {"type": "line", "start": [-sx, -c], "end": [sx, -c]}, {**arc, "start_deg": -90 + z_deg, "end_deg": 90 - z_deg}]}


def _cases() -> dict[str, tuple[dict[str, object], object]]:
    """Part documents and their brute-force models (a function of the analysed centre of mass)."""
    bracket = json.loads((EXAMPLES / "bracket.json").read_text())
    pie = json.loads((EXAMPLES / "pie-20.json").read_text())
    return {
        "bracket": (bracket, lambda com: brute.ExactPart(np.array([[0.0, 0.0], [36, 0], [36, 9], [27, 18], [6, 24]]),
                                                         ((27.0, 9.0, 9.0, 0.0, math.pi / 2),), com)),
        "pie": (pie, lambda com: brute.pie(com=com)),
        "fig11": (_fig11_doc(30.0), lambda com: brute.fig11(10.0, 30.0)),
        "triangle": (_poly(TRIANGLE), lambda com: brute.ExactPart(np.array(TRIANGLE, dtype=float), (), com)),
    }


ROBUST_FRICTION = {"triangle": (0.1, 0.15)}
"""The robust triangle's range: with the shape and centre-of-mass bands it has a design up
to μ_f,hi = 0.188 only."""
FRICTION = {"pie": (0.0, 0.1)}
"""Fence friction ranges other than the default: pie-20's rest on its arc (a smooth
minimum of r) moves with the friction (±18.4° at 0.3) and no design holds over 0.1–0.3."""


@pytest.mark.parametrize("name", ["bracket", "pie", "fig11", "triangle"])
def test_designs_hold_from_3600_starts_by_brute_force(name: str) -> None:
    """Exact designs, run by the brute-force push with the fence's friction (μ over the
    range) from 3,600 starts, end at the claimed orientations; every angle is admissible;
    margins are at least the asked 1°."""
    doc, model = _cases()[name]
    analysis = analyse_document(doc, EXACT)
    rules = replace(BERRETTY, friction=FRICTION.get(name, BERRETTY.friction))
    design = design_fences(analysis, rules)
    _admissible(design, rules)
    assert min(design.margins) >= math.radians(1.0) - 1e-12
    assert _worst_over_friction(model(analysis.part.center_of_mass), design) < 0.01  # type: ignore[operator]


@pytest.mark.parametrize("name", ["bracket", "triangle"])
def test_robust_designs_hold_by_brute_force_and_margins(name: str) -> None:
    """Robust designs (real-cell ranges) hold for the exact part within their uncertainty
    over the fence friction range, and still do with any fence turned by its margin (the
    others as designed): the last fence's error turns the final orientation with it (it
    sets the world frame, as the last gripper angle of a plan does)."""
    doc, model = _cases()[name]
    analysis = analyse_document(doc, Model(physics=DEFAULT_PHYSICS))
    design = design_fences(analysis, replace(BERRETTY, friction=ROBUST_FRICTION.get(name, BERRETTY.friction)))
    _admissible(design, design.rules)
    part = model(analysis.part.center_of_mass)  # type: ignore[operator]
    tol = math.degrees(design.final_uncertainty) + 0.01
    assert _worst_over_friction(part, design) <= tol
    for i, m in enumerate(design.margins):
        for sign in (-1.0, 1.0):
            angles = list(design.angles)
            angles[i] += sign * m * 0.999
            assert _worst_over_friction(part, design, tuple(angles), angles[-1] - design.angles[-1]) <= tol


def test_bracket_design_over_the_friction_range_needs_it() -> None:
    """The bracket's centre of mass lies 2.4° beyond one edge's end ((ln r)′ = 0.042 on its
    near side), so on the left rail any μ above 0.042 makes that edge a rest too: the
    design over μ ∈ [0.1, 0.3] holds there (brute force) and misses by far at μ = 0."""
    doc, model = _cases()["bracket"]
    analysis = analyse_document(doc, EXACT)
    design = design_fences(analysis, BERRETTY)
    part = model(analysis.part.center_of_mass)  # type: ignore[operator]
    assert _worst_over_friction(part, design) < 0.01
    assert _worst_miss_deg(_simulate(part, design.angles, mu=0.0), design) > 45.0


def test_a_frictionless_design_fails_once_vertex_balances_move_by_atan_mu() -> None:
    """The 4 × 2 rectangle with the tip turns: the design of the frictionless push sends
    some starts to the short side once the fence friction moves each vertex balance by
    atan μ (brute force, μ = 0.2 and 0.3); the design with the friction holds over the range."""
    analysis = analyse_document(_poly(RECT), EXACT)
    rules = FenceRules()
    frictionless = _search(analysis, replace(push_of(analysis, (0.0, 0.0)), radius=None), rules, math.radians(1.0),
                           None)
    assert frictionless is not None
    part = _exact_part(RECT)
    # the fences alone, each tip turning the part by 0 (one of the turns t ∈ [0, β] modelled)
    misses = [_worst_miss_deg(_simulate(part, frictionless.angles, mu=mu), frictionless) for mu in (0.2, 0.3)]
    assert max(misses) > 45.0
    assert _worst_over_friction(part, design_fences(analysis, rules)) < 0.01


def _brute_fewest(part: brute.ExactPart, T: float, step_deg: float = 1.0, depth: int = 4) -> int | None:
    """Fewest alternating fences on a ``step_deg`` grid of each side's admissible angles
    (default rules) collapsing 360 starts, each at three wall frictions μ over the range,
    to one orientation mod T: exhaustive breadth-first search, states merged when their
    orientation sets agree to 0.01°. Independent of the planner (Berretty et al.'s model
    with the fence's friction, brute force)."""
    beta_max = 90.0 - math.degrees(math.atan(0.3))
    betas = np.radians(np.arange(10.0, beta_max, step_deg))
    grids = (betas, np.pi - betas)
    frictions = mus(BERRETTY)
    starts = np.linspace(0.0, 2 * np.pi, 360, endpoint=False) + 1e-4

    def push(phi: np.ndarray, a: float) -> np.ndarray:  # row k of phi: the starts at friction k
        return np.mod(np.stack([fence_flow(part, a, float(m))(row - a) + a for m, row in zip(frictions, phi)]),
                      2 * np.pi)

    first = np.tile(starts, (len(frictions), 1))
    frontier = [(s, float(a), push(first, float(a))) for s in (0, 1) for a in grids[s]]
    for n in range(1, depth + 1):
        for _, _, phi in frontier:
            r = np.mod(phi - phi.flat[0] + 0.5 * T, T) - 0.5 * T
            if np.ptp(r) < math.radians(0.05):
                return n
        nxt: list[tuple[int, float, np.ndarray]] = []
        seen: set[tuple[object, ...]] = set()
        for s, _, phi in frontier:
            for a in grids[1 - s]:
                out = push(phi, float(a))
                key = (1 - s, float(a), tuple(np.unique(np.round(np.degrees(out), 2))))
                if key not in seen:
                    seen.add(key)
                    nxt.append((1 - s, float(a), out))
        frontier = nxt
    return None


@pytest.mark.parametrize("vertices", [RECT, [[0, 0], [6, 0], [5, 2], [1, 3]]])
def test_fence_counts_equal_an_independent_brute_force_search(vertices: list[list[float]]) -> None:
    """Berretty et al.'s model on small polygons: the planner's count (no margin asked)
    equals exhaustive search over 1° angle grids with the brute-force push with the fence
    friction (the triangle, 6 fences over the friction range, is beyond the search's depth 4)."""
    analysis = analyse_document(_poly(vertices), EXACT)
    design = design_fences(analysis, BERRETTY, min_margin_deg=0.0)
    expected = _brute_fewest(_exact_part(vertices), design.symmetry)
    assert expected == len(design.angles)


def test_disk_is_refused_with_its_reason() -> None:
    disk = {"name": "disk", "boundary": [{"type": "arc", "center": [0, 0], "radius": 5, "start_deg": 0, "end_deg": 360}]}
    for model in (EXACT, IDEAL):
        with pytest.raises(NotOrientableError) as e:
            design_fences(analyse_document(disk, model), BERRETTY)
        assert e.value.reason in ("no_step", "dead_band")


def test_refusal_names_the_friction_under_which_a_design_exists() -> None:
    """Pie-20 rests on its arc (a smooth minimum of r), a rest the fence friction moves (by
    up to 18.4° at μ = 0.3): over 0.1–0.3 no design holds; the refusal names the friction
    limit, a design exists there and holds by brute force over [0, limit]."""
    doc, model = _cases()["pie"]
    analysis = analyse_document(doc, EXACT)
    with pytest.raises(NotOrientableError) as e:
        design_fences(analysis, BERRETTY)
    assert e.value.reason == "no_fence_design"
    assert e.value.limits is not None
    mu = e.value.limits["fence_friction_max"]
    assert isinstance(mu, float) and 0.0 < mu < 0.3
    assert f"{mu:.3g}" in e.value.message
    design = design_fences(analysis, replace(fence_rules([0.0, mu]), exit_steepness=None, exit_turns=False))
    _admissible(design, design.rules)
    assert _worst_over_friction(model(analysis.part.center_of_mass), design) < 0.01  # type: ignore[operator]


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(beta=st.floats(0.0, 360.0))
def test_rotating_the_drawing_changes_no_fence_count(beta: float) -> None:
    """The start is every orientation, so turning the part's drawing by β only turns the
    final orientation: the count is the same."""
    c, s_ = math.cos(math.radians(beta)), math.sin(math.radians(beta))
    turned = [[c * x - s_ * y, s_ * x + c * y] for x, y in TRIANGLE]
    n0 = len(design_fences(analyse_document(_poly(TRIANGLE), EXACT), BERRETTY).angles)
    assert len(design_fences(analyse_document(_poly(turned), EXACT), BERRETTY).angles) == n0


@pytest.mark.parametrize("friction", [[0.5, 0.2], [-0.1, 0.2], [0.0, 10.0], [], [0.1, 0.2, 0.3], [float("nan")]])
def test_bad_fence_friction_is_a_config_error(friction: list[float]) -> None:
    assert fence_rules(None) == FenceRules() and fence_rules(0.2).friction == (0.2, 0.2)
    with pytest.raises(ConfigError) as e:
        fence_rules(friction)
    assert e.value.field == "fence_friction"


def _convex(points: list[tuple[float, float]]) -> list[list[float]]:
    """Counter-clockwise convex hull (monotone chain) of the points."""
    pts = sorted(set(points))

    def half(seq: list[tuple[float, float]]) -> list[tuple[float, float]]:
        out: list[tuple[float, float]] = []
        for p in seq:
            while len(out) >= 2 and ((out[-1][0] - out[-2][0]) * (p[1] - out[-2][1])
                                     - (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0])) <= 1e-9:
                out.pop()
            out.append(p)
        return out[:-1]

    return [list(p) for p in half(pts) + half(pts[::-1])]


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.integers(0, 40), st.integers(0, 40)), min_size=4, max_size=9))
def test_random_polygons_designs_hold_by_brute_force(points: list[tuple[int, int]]) -> None:
    """Any convex polygon: a design, when one exists, holds from 3,600 starts under the
    brute-force push, with admissible alternating angles; a refusal is typed."""
    from hypothesis import assume

    vertices = _convex([(float(x), float(y)) for x, y in points])
    assume(len(vertices) >= 3)
    x, y = np.array(vertices).T
    assume(0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)) > 20.0)  # not a sliver
    try:
        design = design_fences(analyse_document(_poly(vertices), EXACT), BERRETTY)
    except NotOrientableError as e:
        assert e.reason in ("no_step", "no_fence_design")
        return
    _admissible(design, design.rules)
    assert _worst_over_friction(_exact_part(vertices), design) < 0.01
