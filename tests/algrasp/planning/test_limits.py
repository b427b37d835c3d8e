"""Limit searches after a refusal (algrasp/planning/limits.py, conventions §8): the
screen of several ranges in one probe gives the same limits as searching each range
alone, and ``limits="none"`` refuses after one planning attempt."""

from __future__ import annotations

import pickle
from typing import Any

import pytest

from algrasp.errors import NotOrientableError
from algrasp.pipeline import WARM_UP_PART
from algrasp.planning import limits as lim
from algrasp.planning.analysis import ROBUST, analyse_document
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
    the sentence) equal an eager search of the same part, made here apart."""
    analysis = analyse_document(PARTS["random 5-gon"], ROBUST)
    eager = lim.limits(analysis, "squeeze", plan_once, refused=True)
    eager["push_grasp_orients"] = lim.plan_exists(analysis, analysis.robust.physics, "push_grasp", plan_once, 0.0)  # type: ignore[union-attr]
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
