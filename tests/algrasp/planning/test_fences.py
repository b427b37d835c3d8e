"""Conveyor fences (conventions §9), held to values computed here independently: every
design is run from 3,600 starts by composing p(φ − α) + α of the brute-force push of
``tests.algrasp.brute`` (which uses nothing of algrasp), counts are checked against a
square and a rectangle by hand and an independent breadth-first search over angle grids,
every fence angle against the admissibility rules, and a disk is refused."""

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
from algrasp.planning.fences import FenceDesign, FenceRules, design_fences, fence_rules
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


_FLOWS: dict[int, tuple[brute.ExactPart, brute.Flow]] = {}


def _simulate(part: brute.ExactPart, angles: tuple[float, ...], starts: np.ndarray = STARTS) -> np.ndarray:
    """World orientations after the fences, by the brute-force push (radians, [0, 2π))."""
    if id(part) not in _FLOWS:  # the part is kept with its flow, so its id is not reused
        _FLOWS[id(part)] = (part, brute.Flow(part.radius, 0.0))
    push = _FLOWS[id(part)][1]
    phi = starts.copy()
    for a in angles:
        phi = push(phi - a) + a
    return np.mod(phi, 2 * np.pi)


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
    finals = _simulate(_exact_part(SQUARE), design.angles)
    assert _worst_miss_deg(finals, design) < 0.01


def test_rectangle_needs_two_fences_in_the_derived_window() -> None:
    """By hand: after one fence a 4 × 2 rectangle lies on a long or a short side (90° apart,
    T = 180°); its long-side basin is 2·atan 2 = 126.87° wide, so one more fence turned by δ
    with [90° − δ, 180° − δ] inside a long-side basin, δ ∈ (−63.43°, −26.57°) mod 180°,
    collapses it. Alternation: right → left δ ∈ (33.4°, 160°] leaves δ ∈ (116.57°, 153.43°);
    left → right δ ∈ [−160°, −33.4°) leaves δ ∈ (−63.43°, −33.4°)."""
    rules = BERRETTY
    design = design_fences(analyse_document(_poly(RECT), EXACT), rules)
    assert len(design.angles) == 2
    _admissible(design, rules)
    d = math.degrees(design.angles[1] - design.angles[0])
    low, high = (116.57, 153.43) if design.sides[0] == 0 else (-63.43, -33.39)
    assert low < d < high
    assert _worst_miss_deg(_simulate(_exact_part(RECT), design.angles), design) < 0.01


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


@pytest.mark.parametrize("name", ["bracket", "pie", "fig11", "triangle"])
def test_designs_hold_from_3600_starts_by_brute_force(name: str) -> None:
    """Exact designs, run by the brute-force push from 3,600 starts, end at the claimed
    orientations; every angle is admissible; margins are at least the asked 1°."""
    doc, model = _cases()[name]
    analysis = analyse_document(doc, EXACT)
    rules = BERRETTY
    design = design_fences(analysis, rules)
    _admissible(design, rules)
    assert min(design.margins) >= math.radians(1.0) - 1e-12
    finals = _simulate(model(analysis.part.center_of_mass), design.angles)  # type: ignore[operator]
    assert _worst_miss_deg(finals, design) < 0.01


@pytest.mark.parametrize("name", ["bracket", "triangle"])
def test_robust_designs_hold_by_brute_force_and_margins(name: str) -> None:
    """Robust designs (real-cell ranges) hold for the exact part within their uncertainty,
    and still do with any fence turned by its margin (the others as designed): the last
    fence's error turns the final orientation with it (it sets the world frame, as the
    last gripper angle of a plan does)."""
    doc, model = _cases()[name]
    analysis = analyse_document(doc, Model(physics=DEFAULT_PHYSICS))
    design = design_fences(analysis, BERRETTY)
    _admissible(design, design.rules)
    part = model(analysis.part.center_of_mass)  # type: ignore[operator]
    tol = math.degrees(design.final_uncertainty) + 0.01
    assert _worst_miss_deg(_simulate(part, design.angles), design) <= tol
    for i, m in enumerate(design.margins):
        for sign in (-1.0, 1.0):
            angles = list(design.angles)
            angles[i] += sign * m * 0.999
            turn = angles[-1] - design.angles[-1]
            assert _worst_miss_deg(np.mod(_simulate(part, tuple(angles)) - turn, 2 * np.pi), design) <= tol


def _brute_fewest(part: brute.ExactPart, T: float, step_deg: float = 1.0, depth: int = 4) -> int | None:
    """Fewest alternating fences on a ``step_deg`` grid of each side's admissible angles
    (default rules) collapsing 360 starts to one orientation mod T: exhaustive
    breadth-first search, states merged when their orientation sets agree to 0.01°.
    Independent of the planner (Berretty et al.'s model, brute force)."""
    push = brute.Flow(part.radius, 0.0)
    beta_max = 90.0 - math.degrees(math.atan(0.3))
    betas = np.radians(np.arange(10.0, beta_max, step_deg))
    grids = (betas, np.pi - betas)
    starts = np.linspace(0.0, 2 * np.pi, 360, endpoint=False) + 1e-4
    frontier = [(s, float(a), np.mod(push(starts - a) + a, 2 * np.pi)) for s in (0, 1) for a in grids[s]]
    for n in range(1, depth + 1):
        for _, _, phi in frontier:
            r = np.mod(phi - phi[0] + 0.5 * T, T) - 0.5 * T
            if np.ptp(r) < math.radians(0.05):
                return n
        nxt: list[tuple[int, float, np.ndarray]] = []
        seen: set[tuple[object, ...]] = set()
        for s, _, phi in frontier:
            for a in grids[1 - s]:
                out = np.mod(push(phi - a) + a, 2 * np.pi)
                key = (1 - s, float(a), tuple(np.unique(np.round(np.degrees(out), 2))))
                if key not in seen:
                    seen.add(key)
                    nxt.append((1 - s, float(a), out))
        frontier = nxt
    return None


@pytest.mark.parametrize("vertices", [RECT, TRIANGLE, [[0, 0], [6, 0], [5, 2], [1, 3]]])
def test_fence_counts_equal_an_independent_brute_force_search(vertices: list[list[float]]) -> None:
    """Berretty et al.'s model on small polygons: the planner's count (no margin asked)
    equals exhaustive search over 1° angle grids with the brute-force push."""
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
    """Fig. 11 with 2z = 44°: each fence shrinks the arc by at most z, and with μ_f ≤ 0.3 the
    alternating window forbids the turns needed within 12 fences; the refusal names the
    friction limit, and a design exists there."""
    analysis = analyse_document(_fig11_doc(22.0), EXACT)
    with pytest.raises(NotOrientableError) as e:
        design_fences(analysis, BERRETTY)
    assert e.value.reason == "no_fence_design"
    assert e.value.limits is not None
    mu = e.value.limits["fence_friction_max"]
    assert isinstance(mu, float) and 0.0 < mu < 0.3
    assert f"{mu:.3g}" in e.value.message
    design = design_fences(analysis, replace(fence_rules([0.0, mu]), exit_steepness=None, exit_turns=False))
    _admissible(design, design.rules)


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
    assert _worst_miss_deg(_simulate(_exact_part(vertices), design.angles), design) < 0.01
