"""Limit searches after a refusal (algrasp/planning/limits.py, conventions §8): the
screen of several ranges in one probe gives the same limits as searching each range
alone, and ``limits="none"`` refuses after one planning attempt."""

from __future__ import annotations

import pickle
from collections.abc import Callable
from typing import Any

import pytest

from algrasp.errors import NotOrientableError
from algrasp.pipeline import WARM_UP_PART
from algrasp.planning import limits as lim
from algrasp.planning.analysis import ROBUST, Model, analyse_document
from algrasp.planning.physics import DEFAULT_PHYSICS, IDEAL_CELL, Physics
from algrasp.planning.plans import make_plan, plan_once
from algrasp.testing import shapes

PARTS = {"triangle": WARM_UP_PART, "random 5-gon": shapes.random_polygon(5, 3), "random 8-gon": shapes.random_polygon(8, 3),
         "pie 40°": shapes.pie(1.0, 40.0)}


def _refused_limits(doc: dict[str, Any], action: str) -> dict[str, Any] | None:
    analysis = analyse_document(doc, ROBUST)
    try:
        plan_once(analysis, action)  # type: ignore[arg-type]
    except NotOrientableError:
        return lim.limits(analysis, action, plan_once, refused=True)
    return None


@pytest.mark.parametrize("name", PARTS)
@pytest.mark.parametrize("action", ["squeeze", "push_grasp"])
def test_screened_limits_equal_one_search_per_range(name: str, action: str, monkeypatch: pytest.MonkeyPatch) -> None:
    screened = _refused_limits(PARTS[name], action)
    if screened is None:
        pytest.skip("planned under the default ranges: nothing refused to screen")
    monkeypatch.setattr(lim, "SCREENS", ())
    assert screened == _refused_limits(PARTS[name], action)


def _count_probes(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """A list that grows by one at each limit probe (``_plan_exists``) from now on."""
    calls: list[int] = []
    real = lim._plan_exists

    def counted(*args: Any) -> bool:
        calls.append(1)
        return real(*args)

    monkeypatch.setattr(lim, "_plan_exists", counted)
    return calls


def test_the_screen_saves_probes_when_no_single_range_helps(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(lim, "_reads", lambda *a: None)  # every probe planned: the screen's own saving
    calls = _count_probes(monkeypatch)
    found = _refused_limits(PARTS["random 5-gon"], "squeeze")
    screened = len(calls)
    assert found is not None and all(found[n]["value"] is None for n in sum(lim.SCREENS, ()))
    calls.clear()
    monkeypatch.setattr(lim, "SCREENS", ())
    assert _refused_limits(PARTS["random 5-gon"], "squeeze") == found
    assert len(calls) == screened + 3  # five single probes where the screen made two


def test_limits_none_refuses_after_one_attempt_without_searching(monkeypatch: pytest.MonkeyPatch) -> None:
    analysis = analyse_document(PARTS["random 5-gon"], ROBUST)
    with pytest.raises(NotOrientableError) as searched:
        make_plan(analysis, "squeeze")
    assert searched.value.limits is not None  # searched now, before probes are forbidden
    monkeypatch.setattr(lim, "_plan_exists", lambda *a: pytest.fail("a limit probe under limits='none'"))
    with pytest.raises(NotOrientableError) as bare:
        make_plan(analysis, "squeeze", limits="none")
    assert bare.value.reason == searched.value.reason and bare.value.limits is None
    assert "not searched" in bare.value.message


@pytest.mark.parametrize("read", ["limits", "message", "to_dict", "pickle"])
def test_a_refusal_searches_its_limits_when_first_read(read: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """The refusal of make_plan probes nothing until its limits are read; then they (and
    the sentence) equal an eager search of the same part, made here apart (on an analysis
    of its own: one analysis's probes share their answers)."""
    apart = analyse_document(PARTS["random 5-gon"], ROBUST)
    eager = lim.limits(apart, "squeeze", plan_once, refused=True)
    eager["push_grasp_orients"] = lim.plan_exists(apart, apart.robust.physics, "push_grasp", plan_once, 0.0)  # type: ignore[union-attr]
    analysis = analyse_document(PARTS["random 5-gon"], ROBUST)
    calls = _count_probes(monkeypatch)
    with pytest.raises(NotOrientableError) as refused:
        make_plan(analysis, "squeeze")
    err = refused.value
    assert calls == [] and err.limits_pending and err.reason == "uncertain"
    got = {"limits": lambda: err.limits, "message": lambda: err.message, "to_dict": err.to_dict,
           "pickle": lambda: pickle.loads(pickle.dumps(err))}[read]()
    assert calls and not err.limits_pending
    assert err.limits == eager and "Under the given ranges: " + str(eager["advice"]) in err.message
    if read == "pickle":
        assert got.limits == eager and got.message == err.message
    assert str(err) == err.message and err.to_dict()["limits"] == eager


@pytest.mark.parametrize("action", ["squeeze", "push_grasp"])
def test_shared_set_functions_give_the_limits_of_fresh_ones(action: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """The probes share the set-valued functions built on one analysis (RobustAnalysis.sets);
    building every probe's afresh finds the same limits."""
    doc = PARTS["random 8-gon"]
    analysis = analyse_document(doc, ROBUST)
    shared = lim.limits(analysis, action, plan_once, margin_deg=0.0)
    built = len(analysis.robust.sets) if analysis.robust else 0
    real = lim.robust_analysis
    monkeypatch.setattr(lim, "robust_analysis", lambda *args: real(*args[:-1], None))
    fresh = lim.limits(analyse_document(doc, ROBUST), action, plan_once, margin_deg=0.0)
    assert fresh == shared and built > 3


def test_the_set_memo_crosses_no_process() -> None:
    """A pickled analysis (a worker's answer) carries no memoised functions."""
    analysis = analyse_document(PARTS["triangle"], ROBUST)
    assert analysis.robust is not None and analysis.robust.sets
    assert pickle.loads(pickle.dumps(analysis.robust)).sets == {}


def _fresh_answer(doc: dict[str, Any], physics: Physics, action: str, margin_deg: float = 0.0) -> bool:
    """Whether a plan exists, from an analysis of the part under ``physics`` made for it
    alone: no probe, memo or limit search involved."""
    try:
        plan_once(analyse_document(doc, Model(physics=physics)), action, margin_deg)  # type: ignore[arg-type]
    except NotOrientableError:
        return False
    return True


def _lo_moved(physics: Physics, key: str) -> Physics:
    """The range ``key`` with its low end moved (to its high end, or half of it)."""
    lo, hi = getattr(physics, key)
    return physics.with_range(key, (hi, hi) if lo != hi else (0.5 * hi, hi))


VARIANTS: dict[str, tuple[Callable[[Physics, float], Physics], Callable[[Physics], bool]]] = {
    # name: (the physics from a base and the part's profile floor, whether a plan reads it alike)
    "support μ lo": (lambda p, _: _lo_moved(p, "support_friction"), lambda p: p.creep),  # creep: the weakest hold holds nothing
    "part mass lo": (lambda p, _: _lo_moved(p, "part_mass_kg"), lambda p: p.creep),
    "jaw μ lo": (lambda p, _: _lo_moved(p, "jaw_friction"), lambda p: True),  # only the largest jaw μ is read
    "profile tolerance given as its floor": (lambda p, floor: p.with_values(profile_tolerance=floor), lambda p: True),
    "jaw μ hi": (lambda p, _: p.with_range("jaw_friction", (p.jaw_friction[0], p.jaw_friction[1] + 0.1)), lambda p: False),
    "creep": (lambda p, _: p.with_values(creep=not p.creep), lambda p: False),
}
BASES = {"default": DEFAULT_PHYSICS, "near-ideal": IDEAL_CELL.with_values(creep=True, support_friction=(0.2, 0.3))}


@pytest.mark.parametrize("name", PARTS)
@pytest.mark.parametrize("action", ["squeeze", "push_grasp"])
@pytest.mark.parametrize("base_name", BASES)
def test_probes_alike_in_what_the_plan_reads_share_the_answer_of_fresh_ones(name: str, action: str, base_name: str,
                                                                           monkeypatch: pytest.MonkeyPatch) -> None:
    """A probe whose physics reads alike (:func:`~algrasp.planning.analysis.plan_reads`)
    to one already made on the analysis is answered by it, not planned: that answer is
    the one an analysis under its physics alone finds; physics that read differently are
    planned."""
    doc, base = PARTS[name], BASES[base_name]
    analysis = analyse_document(doc, Model(physics=base))
    assert analysis.robust is not None and analysis.robust.terms is not None
    floor = lim.profile_floor(analysis.part, base, analysis.robust.terms.nominal_size)
    assert lim.plan_exists(analysis, base, action, plan_once, 0.0) == _fresh_answer(doc, base, action)
    calls = _count_probes(monkeypatch)
    for label, (vary, alike) in VARIANTS.items():
        physics = vary(base, floor)
        calls.clear()
        got = lim.plan_exists(analysis, physics, action, plan_once, 0.0)
        assert (calls == []) == alike(base), label
        assert got == _fresh_answer(doc, physics, action), label
    assert analysis.robust.sets.plans and pickle.loads(pickle.dumps(analysis.robust)).sets.plans == {}


def test_a_plan_made_answers_the_probe_that_reads_the_same(monkeypatch: pytest.MonkeyPatch) -> None:
    """make_plan notes its answer (a plan, or a refusal) on the analysis: a probe of the
    same action under the same physics (a squeeze refusal's ``push_grasp_orients``) is
    not planned again, and under another margin it is."""
    analysis = analyse_document(PARTS["triangle"], ROBUST)
    assert analysis.robust is not None
    make_plan(analysis, "push_grasp")
    calls = _count_probes(monkeypatch)
    assert lim.plan_exists(analysis, analysis.robust.physics, "push_grasp", plan_once, 0.0) and calls == []
    assert lim.plan_exists(analysis, analysis.robust.physics, "push_grasp", plan_once, 1.0) == \
        _fresh_answer(PARTS["triangle"], DEFAULT_PHYSICS, "push_grasp", 1.0) and calls == [1]

