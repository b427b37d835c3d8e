"""Set verification (algrasp/planning/verification.py): checking each distinct outcome
of the second action once gives the answer of running every sample through every action."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from algrasp.geometry.tolerances import PROBE_RAD
from algrasp.pipeline import WARM_UP_PART
from algrasp.planning.actions import Action
from algrasp.planning.analysis import ROBUST, Model, analyse_document
from algrasp.planning.physics import IDEAL_CELL
from algrasp.planning.plans import Plan, make_plan
from algrasp.planning.verification import FINAL_CLUSTER_RAD, VERIFY_SAMPLES, run_steps, verify_set
from algrasp.testing import shapes


def _every_sample(plan: Plan, circle: tuple[float, float]) -> bool:
    """verify_set's claim, sample by sample: every start in the arc (and every piece
    boundary's neighbours, and the arc as a whole) after the first action ends within
    the uncertainty of a claimed final orientation."""
    S = plan.bounds
    assert S is not None
    c0, c1 = circle
    out = np.array(S.outcomes)
    rel = np.mod(out[:, 0] - c0 + FINAL_CLUSTER_RAD, S.symmetry) - FINAL_CLUSTER_RAD
    if np.any(rel + (out[:, 1] - out[:, 0]) > c1 - c0 + FINAL_CLUSTER_RAD):
        return False
    a1 = plan.steps[0].gripper_angle
    cuts = [c0 + (p.start - c0) % S.symmetry for F in (S.lower, S.upper) for p in F.pieces]
    inner = np.array([c for c in cuts if c <= c1])
    pts = np.clip(np.concatenate([np.linspace(c0, c1, VERIFY_SAMPLES), inner - PROBE_RAD, inner, inner + PROBE_RAD]),
                  c0, c1) + a1
    starts = [(x, x) for x in pts] + [(c0 + a1, c1 + a1)]
    for lo, hi in starts:
        end_lo, end_hi = run_steps(S, plan.steps[1:], np.array([lo]), np.array([hi]))
        mid, half = 0.5 * (end_lo[0] + end_hi[0]), 0.5 * (end_hi[0] - end_lo[0])
        off = min(abs((mid - f + np.pi) % (2 * np.pi) - np.pi) for f in plan.final_orientations)
        if not off + half <= plan.final_uncertainty + FINAL_CLUSTER_RAD:
            return False
    return True


@pytest.mark.parametrize(("doc", "action"), [(WARM_UP_PART, "push_grasp"), (shapes.rectangle(3.0, 1.0), "squeeze"),
                                             (shapes.pie(5.0, 20.0), "push_grasp")])
def test_verify_set_equals_running_every_sample(doc: dict[str, object], action: Action) -> None:
    analysis = analyse_document(doc, ROBUST)
    plan = make_plan(analysis, action, limits="none")
    assert plan.bounds is not None
    circle = plan.bounds.circle_images()[0]
    answers = []
    u = plan.final_uncertainty
    for shift in (0.0, 0.5 * u, 0.999 * u, 1.001 * u, 2.0 * u):  # claimed finals moved: the check must notice
        p = dataclasses.replace(plan, final_orientations=tuple(f + shift for f in plan.final_orientations))
        answers.append(verify_set(p, circle))
        assert answers[-1] == _every_sample(p, circle)
    assert answers[0] and not answers[-1]


@pytest.mark.parametrize(("doc", "action"), [(WARM_UP_PART, "push_grasp"), (shapes.rectangle(3.0, 1.0), "squeeze"),
                                             (shapes.pie(5.0, 20.0), "push_grasp")])
def test_verify_set_in_floats_answers_as_vectorised(doc: dict[str, object], action: Action,
                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    """The plain-float path (few distinct images) and the vectorised one give the same
    answer, for claimed finals on and off the truth."""
    from algrasp.planning import verification

    plan = make_plan(analyse_document(doc, ROBUST), action, limits="none")
    assert plan.bounds is not None
    circle = plan.bounds.circle_images()[0]
    u = plan.final_uncertainty
    for shift in (0.0, 0.999 * u, 1.001 * u, 2.0 * u):
        p = dataclasses.replace(plan, final_orientations=tuple(f + shift for f in plan.final_orientations))
        answers = []
        for few in (0, 10**9):  # never, always in floats
            monkeypatch.setattr(verification, "FEW_ARCS", few)
            answers.append(verify_set(p, circle))
        assert answers[0] == answers[1]


@pytest.mark.parametrize("doc", [shapes.random_polygon(7, 4), shapes.bezier_blob(50, 2)])
def test_verify_set_switching_to_floats_mid_plan_answers_as_every_sample(doc: dict[str, object],
                                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    """Long plans whose images still run in more than ``FEW_ARCS`` arcs after the second
    action: each later action runs over the runs the one before left, and the floats take
    over wherever the count falls below the threshold (never, at once, midway): the
    answer is the sample-by-sample one, for claimed finals on and off the truth."""
    from algrasp.planning import verification

    physics = IDEAL_CELL.with_values(creep=True, support_friction=(0.2, 0.3))
    plan = make_plan(analyse_document(doc, Model(physics=physics)), "push_grasp", limits="none")
    assert plan.bounds is not None and len(plan.steps) > 4
    truths = []
    u = plan.final_uncertainty
    for circle in plan.bounds.circle_images():  # the plan was placed on one of them
        for shift in (0.0, 1.001 * u):
            p = dataclasses.replace(plan, final_orientations=tuple(f + shift for f in plan.final_orientations))
            truths.append(_every_sample(p, circle))
            for few in (0, 4, 16, 32, 10**9):
                monkeypatch.setattr(verification, "FEW_ARCS", few)
                assert verify_set(p, circle) == truths[-1], (circle, shift, few)
    assert any(truths) and not all(truths)
