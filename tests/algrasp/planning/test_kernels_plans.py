"""The compiled passes of planning and verification (algrasp.planning._lookups, read
directly by plans, planner and verification) against the numpy / plain-float path they
replace: every verdict and every float bit for bit, on plans of random polygons, symmetric
polygons, arcs and Bezier curves under random physics, and on the same plans disturbed
(gripper angles moved, uncertainty shrunk, few samples) so that verdicts go both ways.
The numpy path is the reference (run here with the hooks switched off)."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from algrasp.compiled import KERNELS
from algrasp.errors import NotOrientableError
from algrasp.planning import planner, plans, transfer, verification
from algrasp.planning.analysis import Model, analyse_document
from algrasp.planning.physics import Physics
from algrasp.planning.plans import Plan, PlanStep, make_plan
from algrasp.testing.kernels import bits, both, families

pytestmark = pytest.mark.skipif(KERNELS is None, reason="compiled kernels not built (or ALGRASP_PURE set)")


DOCS = families("polygon", "regular", "flats", "pie", "blob")
PHYSICS = st.builds(lambda jaw, sup, tol, placement: Physics(jaw_friction=(0.0, jaw), support_friction=sup,
                                                            profile_tolerance=tol, placement=placement),
                    st.sampled_from([0.0, 0.05, 0.1, 0.3]), st.sampled_from([(0.2, 0.45), (0.3, 0.3), (0.0, 0.1)]),
                    st.sampled_from([None, 0.0, 1e-3, 0.01]), st.sampled_from(["any", "centred"]))


def _plan(shape: str, seed: int, n: int, physics: Physics, action: str) -> Plan | None:
    try:
        return make_plan(analyse_document(DOCS[shape](seed, n), Model(physics=physics)), action, limits="none")  # type: ignore[arg-type]
    except NotOrientableError:
        return None


def _disturbed(plan: Plan, shift: float, k: int, shrink: float) -> Plan:
    """The plan with action k's gripper angle moved by ``shift`` and its uncertainty times ``shrink``."""
    steps = list(plan.steps)
    if steps:
        s = steps[k % len(steps)]
        steps[k % len(steps)] = PlanStep(s.gripper_angle + shift, s.margin)
    return replace(plan, steps=tuple(steps), final_uncertainty=plan.final_uncertainty * shrink)


@settings(max_examples=120, deadline=None)
@given(shape=st.sampled_from(sorted(DOCS)), seed=st.integers(0, 10_000), n=st.integers(3, 11), physics=PHYSICS,
       action=st.sampled_from(["squeeze", "push_grasp"]), shift=st.sampled_from([0.0, 1e-9, -1e-3, 0.05, 0.5]),
       k=st.integers(0, 8), shrink=st.sampled_from([1.0, 0.5, 0.0]), samples=st.sampled_from([3600, 0, 1, 2, 7]))
def test_verify_set_is_bit_identical(shape: str, seed: int, n: int, physics: Physics, action: str, shift: float, k: int,
                                     shrink: float, samples: int) -> None:
    plan = _plan(shape, seed, n, physics, action)
    if plan is None or plan.bounds is None:
        return
    arcs = plan.bounds.circle_images()
    p = _disturbed(plan, shift, k, shrink)
    for circle in [arcs[0], *arcs[1:2], (arcs[0][0], arcs[0][0])]:  # the hull, another arc, a point
        compiled, numpy_ = both(lambda c=circle: verification.verify_set(p, c, samples))
        assert bits(compiled) == bits(numpy_)


ENDS = st.floats(-7.0, 14.0) | st.sampled_from([0.0, -0.0, np.pi, -np.pi, 2.0 * np.pi, 1e-12])
WIDTHS = st.floats(0.0, 1.0) | st.sampled_from([0.0, 1e-9, np.pi / 3, np.pi, 2.0 * np.pi])


@settings(max_examples=400, deadline=None)
@given(arcs=st.lists(st.tuples(ENDS, WIDTHS), min_size=0, max_size=transfer.FEW_ARCS),
       T=st.sampled_from([np.pi, 2.0 * np.pi, np.pi / 3, 1.0]))
def test_arcs_holding_is_bit_identical(arcs: list[tuple[float, float]], T: float) -> None:
    """Intervals anywhere (several periods off, ±0.0, touching, as wide as T)."""
    lo, hi = [a for a, _ in arcs], [a + w for a, w in arcs]
    compiled, numpy_ = both(lambda: transfer.arcs_holding(lo, hi, T))
    assert bits(compiled) == bits(numpy_)


def _planbits(plan: Plan) -> Any:
    """Everything a plan says but its timings."""
    return (plan.action, plan.symmetry_period, plan.intervals, [(s.gripper_angle, s.margin) for s in plan.steps],
            plan.final_orientations, plan.verified, plan.final_uncertainty)


@settings(max_examples=60, deadline=None)
@given(shape=st.sampled_from(sorted(DOCS)), seed=st.integers(0, 10_000), n=st.integers(3, 11), physics=PHYSICS,
       action=st.sampled_from(["squeeze", "push_grasp"]), margin=st.sampled_from([0.0, 0.5, 3.0]))
def test_plans_are_bit_identical(shape: str, seed: int, n: int, physics: Physics, action: str, margin: float) -> None:
    """A′'s search (the compiled widest tables, sink widths, images), the gripper angles and
    the verification: the same plan, or the same refusal, either way."""
    analysis = analyse_document(DOCS[shape](seed, n), Model(physics=physics))
    compiled, numpy_ = both(lambda: _planbits(plans.plan_once(analysis, action, margin)))  # type: ignore[arg-type]
    assert bits(compiled) == bits(numpy_)


@settings(max_examples=80, deadline=None)
@given(shape=st.sampled_from(sorted(DOCS)), seed=st.integers(0, 10_000), n=st.integers(3, 11), physics=PHYSICS,
       action=st.sampled_from(["squeeze", "push_grasp"]), rooms=st.lists(st.floats(0.0, 7.0), min_size=1, max_size=6))
def test_widest_is_bit_identical(shape: str, seed: int, n: int, physics: Physics, action: str, rooms: list[float]) -> None:
    """The widest fit of every box height, on a fresh lifting each way (its table made there)."""
    analysis = analyse_document(DOCS[shape](seed, n), Model(physics=physics))
    S = None if analysis.robust is None else getattr(analysis.robust, action)
    if S is None:
        return
    compiled, numpy_ = both(lambda: [planner._widest(S.lower, planner.Lifted.of(S.lower, S.upper), r) for r in rooms])
    assert bits(compiled) == bits(numpy_)


def _tilt_edge_by_edge(analysis: Any, lo: float, hi: float) -> float:
    """plans._edge_tilt as it was written, one edge at a time (the reference)."""
    eps, tilt = analysis.robust.band.value_err, 0.0
    for (ax, ay), (bx, by) in analysis.part.hull.edges:
        t = 2.0 * eps / float(np.hypot(bx - ax, by - ay))
        rel = (np.pi / 2 - np.arctan2(-(bx - ax), by - ay) - lo + t + plans.EDGE_NORMAL_RAD) % np.pi
        if rel <= (hi - lo) + 2.0 * (t + plans.EDGE_NORMAL_RAD):
            tilt = max(tilt, t)
    return tilt


@settings(max_examples=150, deadline=None)
@given(shape=st.sampled_from(sorted(DOCS)), seed=st.integers(0, 10_000), n=st.integers(3, 11), physics=PHYSICS,
       lo=st.floats(-7.0, 7.0), width=st.floats(0.0, 0.5) | st.sampled_from([0.0, 1e-9]))
def test_edge_tilt_is_edge_by_edge(shape: str, seed: int, n: int, physics: Physics, lo: float, width: float) -> None:
    """Every edge at once gives each edge's floats as one at a time (numpy's hypot and
    arctan2 alike on arrays and scalars), and the same first largest tilt."""
    analysis = analyse_document(DOCS[shape](seed, n), Model(physics=physics))
    if analysis.robust is None:
        return
    flats = [np.pi / 2 - np.arctan2(-(b[0] - a[0]), b[1] - a[1]) for a, b in analysis.part.hull.edges]
    for x in [lo, *flats[:3]]:  # anywhere, and at edges lying flat
        assert bits(plans._edge_tilt(analysis, x, x + width)) == bits(_tilt_edge_by_edge(analysis, x, x + width))


@settings(max_examples=400, deadline=None)
@given(arcs=st.lists(st.tuples(ENDS, WIDTHS), min_size=0, max_size=12), nxt=st.tuples(ENDS, WIDTHS),
       alpha=ENDS, need=st.sampled_from([0.0, 1e-12, 0.01, 0.3]) | st.floats(-1.0, 1.0),
       periods=st.sampled_from([(np.pi, np.pi), (2.0 * np.pi, np.pi / 3), (np.pi, np.pi / 2), (2.0 * np.pi, 2.0 * np.pi)]))
def test_first_choice_is_bit_identical(arcs: list[tuple[float, float]], nxt: tuple[float, float], alpha: float,
                                       need: float, periods: tuple[float, float]) -> None:
    """Arcs anywhere, some too wide to fit, rooms on both sides of the symmetry tolerance,
    ties of turning (equal arcs), and none fitting (both raise alike)."""
    lifted = [(a, a + w) for a, w in arcs]
    a, b = nxt[0], nxt[0] + nxt[1]
    fit = [0.5 * ((b - a) - (hi - lo)) for lo, hi in lifted]
    compiled, numpy_ = both(lambda: planner.first_choice(lifted, fit, need, (a, b), alpha, *periods))
    assert bits(compiled) == bits(numpy_)
