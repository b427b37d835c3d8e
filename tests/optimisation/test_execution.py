"""Optimised execution: every trajectory sample within the gripper's limits, cycle time
no worse than the naive profile, plan document fields, CLI and profile errors."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import yaml

from algrasp.cli import main
from algrasp.errors import ConfigError
from algrasp.geometry.part import load_part
from algrasp.planning.analysis import analyse_part
from algrasp.planning.plans import make_plan
from algrasp.testing import shapes
from optimisation.execution import Execution, optimise_execution
from optimisation.profile import DEFAULT_PROFILE, DEFAULT_PROFILE_PATH, GripperProfile, load_profile, profile_from_dict

EXAMPLE = Path(__file__).parents[2] / "algrasp" / "examples" / "pie-20.json"
SLACK = 1 + 1e-6


@pytest.fixture(scope="module", params=["squeeze", "push_grasp"])
def execution(request: pytest.FixtureRequest) -> tuple[Execution, object]:
    analysis = analyse_part(load_part(json.loads(EXAMPLE.read_text())))
    plan = make_plan(analysis, request.param)
    return optimise_execution(analysis, plan), analysis


def test_samples_respect_every_limit(execution: tuple[Execution, object]) -> None:
    """Finite differences of the samples are averages of the true speed/acceleration, so
    they must lie within the limits; where a jaw may touch the part (inside the largest
    half-width) its speed is at most the contact speed."""
    ex, analysis = execution
    pf, mm = ex.profile, 1e-3
    d_max = max(e.value for e in analysis.diameter.extrema)  # type: ignore[attr-defined]
    for s in ex.steps:
        dt = np.diff(s.t_s)
        assert np.all(dt > 0)
        for jaw in (s.lower, s.higher):
            v = np.diff(jaw) * mm / dt
            assert np.max(np.abs(v)) <= pf.jaw_max_speed_m_s * SLACK
            # 2·f[t0, t1, t2] is a weighted mean of f″ (mean value theorem for divided
            # differences), so it obeys the acceleration limit for any sample spacing.
            a = 2 * np.diff(v) / (s.t_s[2:] - s.t_s[:-2])
            assert np.max(np.abs(a)) <= pf.jaw_max_accel_m_s2 * SLACK
        w = np.diff(s.gripper_angle_rad) / dt
        assert np.max(np.abs(w)) <= pf.rotate_max_speed_rad_s * SLACK
        assert np.max(np.abs(2 * np.diff(w) / (s.t_s[2:] - s.t_s[:-2]))) <= pf.rotate_max_accel_rad_s2 * SLACK
        # Contact zone of a squeeze: a jaw inside the largest half-width may touch the part.
        inside = (np.abs(s.lower[1:]) < d_max / 2 - 1e-9) & (np.abs(s.lower[:-1]) < d_max / 2 - 1e-9)
        if s.push is None:
            v = np.abs(np.diff(s.lower)) * mm / dt
            assert np.all(v[inside] <= pf.contact_speed_m_s * SLACK)


def test_cycle_time_is_no_worse_than_naive(execution: tuple[Execution, object]) -> None:
    ex, _ = execution
    assert 0 < ex.cycle_time_s <= ex.naive_cycle_time_s
    assert ex.cycle_time_s == pytest.approx(sum(s.duration_s for s in ex.steps))


def test_squeeze_stops_at_the_force_limit(execution: tuple[Execution, object]) -> None:
    """The jaws are commanded δ = F/k past the narrowest predicted width, no further."""
    ex, analysis = execution
    delta_mm = DEFAULT_PROFILE.squeeze_overtravel_m * 1e3
    d_min = min(e.value for e in analysis.diameter.extrema)  # type: ignore[attr-defined]
    for s in ex.steps:
        assert np.min(s.higher - s.lower) >= d_min - 2 * delta_mm - 1e-9


def test_push_distances_are_positive_and_within_peshkin(execution: tuple[Execution, object]) -> None:
    ex, _ = execution
    for s in ex.steps:
        if s.push is not None:
            assert 0 < s.push.distance <= s.push.bound


def test_plan_document_gains_execution_fields(execution: tuple[Execution, object]) -> None:
    ex, _ = execution
    doc = ex.apply_to({"steps": [{"gripper_angle_deg": 0.0}] * len(ex.steps)})
    assert doc["cycle_time_s"] == ex.cycle_time_s and doc["units"] == "mm"
    for step in doc["steps"]:  # type: ignore[union-attr]
        assert set(step) >= {"push_distance", "duration_s", "trajectory"}
        assert set(step["trajectory"]) == {"t_s", "gripper_angle_deg", "lower_jaw", "higher_jaw"}


def test_sim_schedule_follows_the_samples(execution: tuple[Execution, object]) -> None:
    ex, _ = execution
    from algrasp.sim.config import execution_schedule

    sch = execution_schedule(ex)
    assert sch.phases[-1].t1 == pytest.approx(ex.cycle_time_s)
    assert len(sch.push_ends_s) == sum(s.push is not None for s in ex.steps)
    assert sch.half_open_m == pytest.approx(ex.open_half_width * 1e-3)


def test_default_profile_file_is_the_default() -> None:
    assert load_profile(DEFAULT_PROFILE_PATH) == DEFAULT_PROFILE


@pytest.mark.parametrize("data,field", [({"jaw_max_speed_m_s": -1}, "jaw_max_speed_m_s"), ({"foo": 1}, "foo"),
                                        ({"contact_speed_m_s": 1.0}, "contact_speed_m_s"), ([1, 2], "profile"),
                                        ({"hold_s": float("nan")}, "hold_s")])
def test_bad_profiles_name_the_field(data: object, field: str) -> None:
    with pytest.raises(ConfigError) as err:
        profile_from_dict(data)
    assert err.value.field == field


def test_cli_plan_optimise_json(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    prof = tmp_path / "slow.yaml"
    prof.write_text(yaml.safe_dump({"jaw_max_speed_m_s": 0.02}))
    assert main(["plan", str(EXAMPLE), "--action", "push-grasp", "--optimise", "--gripper", str(prof), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["gripper_profile"]["jaw_max_speed_m_s"] == 0.02 and doc["cycle_time_s"] > 0
    assert all(s["push_distance"] > 0 for s in doc["steps"])
    assert main(["plan", str(EXAMPLE), "--gripper", str(prof)]) == 2  # --gripper without --optimise


def test_slower_gripper_gives_longer_cycle() -> None:
    analysis = analyse_part(load_part(shapes.rectangle(10.0, 4.0)))
    plan = make_plan(analysis, "squeeze")
    fast = optimise_execution(analysis, plan)
    slow = optimise_execution(analysis, plan, GripperProfile(rotate_max_speed_rad_s=1.0))
    assert slow.cycle_time_s > fast.cycle_time_s


def test_a_jaw_jerk_limit_gives_a_slower_smoother_cycle() -> None:
    """CasADi's jerk-limited jaw moves: never faster than the closed-form cycle, and the
    jaw samples' third divided differences (means of the jerk) within the limit."""
    analysis = analyse_part(load_part(json.loads(EXAMPLE.read_text())))
    plan = make_plan(analysis, "squeeze")
    free = optimise_execution(analysis, plan)
    limited = optimise_execution(analysis, plan, profile_from_dict({"jaw_max_jerk_m_s3": 20.0, "sample_hz": 1000.0}))
    assert limited.cycle_time_s >= free.cycle_time_s * (1 - 1e-9)
    for s in limited.steps:
        for jaw in (s.lower, s.higher):
            q, t = jaw * 1e-3, s.t_s
            # 6·f[t0..t3] is a weighted mean of f‴ over [t0, t3]: bounded by the jerk limit.
            d1 = np.diff(q) / np.diff(t)
            d2 = np.diff(d1) / (t[2:] - t[:-2])
            d3 = np.diff(d2) / (t[3:] - t[:-3])
            assert np.max(np.abs(6 * d3)) <= 20.0 * (1 + 1e-3)
