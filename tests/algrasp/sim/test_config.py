"""Froude-similar simulation settings (pure: no pydrake)."""

from __future__ import annotations

import math

import pytest

from algrasp.sim.config import DEFAULT_SIM, SimConfig, similar_config


def _slide(cfg: SimConfig, v0: float) -> tuple[float, float]:
    """Brute force, written here: a block released at v0 under the regularised support
    friction the simulator uses, a = −μg·v/√(v² + v_s²), stepped semi-implicitly at the
    config's time step until it has (nearly) stopped. Returns (distance m, time s)."""
    mu_g = cfg.support_friction * cfg.gravity_m_s2
    x, v, t = 0.0, v0, 0.0
    while v > 1e-3 * v0:
        v -= cfg.time_step_s * mu_g * v / math.hypot(v, cfg.stiction_speed_m_s)
        x += cfg.time_step_s * v
        t += cfg.time_step_s
    return x, t


def test_small_parts_keep_the_settings_as_written() -> None:
    assert similar_config(DEFAULT_SIM, 0.5 * DEFAULT_SIM.similarity_reach_m) is DEFAULT_SIM
    assert similar_config(SimConfig(similarity_reach_m=0.0), 1.0).jaw_speed_m_s == DEFAULT_SIM.jaw_speed_m_s


def test_speeds_and_times_scale_with_the_square_root_of_size() -> None:
    ref = DEFAULT_SIM.similarity_reach_m
    big = similar_config(DEFAULT_SIM, 4 * ref)  # k = 2
    assert big.jaw_speed_m_s == pytest.approx(2 * DEFAULT_SIM.jaw_speed_m_s)
    assert big.open_speed_m_s == pytest.approx(2 * DEFAULT_SIM.open_speed_m_s)
    assert big.settle_rate_rad_s == pytest.approx(DEFAULT_SIM.settle_rate_rad_s / 2)
    assert big.time_step_s == pytest.approx(min(2 * DEFAULT_SIM.time_step_s, DEFAULT_SIM.max_time_step_s))
    # The quasi-static margin, coasting distance over reach, is the same for both parts.
    mu_g = DEFAULT_SIM.support_friction * DEFAULT_SIM.gravity_m_s2
    assert big.jaw_speed_m_s**2 / (2 * mu_g * 4 * ref) == pytest.approx(DEFAULT_SIM.jaw_speed_m_s**2 / (2 * mu_g * ref))


def test_the_time_step_is_capped() -> None:
    huge = similar_config(DEFAULT_SIM, 10_000 * DEFAULT_SIM.similarity_reach_m)
    assert huge.time_step_s == DEFAULT_SIM.max_time_step_s
    assert huge.relaxation_time_s / huge.time_step_s == pytest.approx(DEFAULT_SIM.relaxation_time_s / DEFAULT_SIM.time_step_s)


@pytest.mark.parametrize("factor", [1.7, 2.5])
def test_a_released_block_slides_the_same_fraction_of_its_size(factor: float) -> None:
    """The law behind the scaling: in similar settings the discrete motion is the same
    motion, lengths × L, times × √L (below the step cap)."""
    ref = DEFAULT_SIM.similarity_reach_m
    small = DEFAULT_SIM
    big = similar_config(small, factor * ref)
    k = math.sqrt(factor)
    assert big.time_step_s < big.max_time_step_s
    d0, t0 = _slide(small, small.jaw_speed_m_s)
    d1, t1 = _slide(big, big.jaw_speed_m_s)
    assert d1 / (factor * ref) == pytest.approx(d0 / ref, rel=1e-9)
    assert t1 / k == pytest.approx(t0, rel=1e-9)


def test_with_jaw_friction_the_step_is_never_longer_than_the_friction_step() -> None:
    """Issue 30: FRICTION_TIME_STEP_S is the step whose convergence was measured; a large
    part's similar step must not exceed it (the bracket's 1 ms one let the release kick)."""
    from algrasp.sim.config import FRICTION_TIME_STEP_S

    cfg = SimConfig(jaw_friction=0.1, time_step_s=FRICTION_TIME_STEP_S)
    big = similar_config(cfg, 16 * cfg.similarity_reach_m)  # k = 4
    assert big.time_step_s == FRICTION_TIME_STEP_S
    assert big.relaxation_time_s / big.time_step_s == pytest.approx(cfg.relaxation_time_s / cfg.time_step_s)
    assert big.jaw_speed_m_s == pytest.approx(4 * cfg.jaw_speed_m_s)  # the motion still scales
    assert similar_config(SimConfig(), 16 * cfg.similarity_reach_m).time_step_s > FRICTION_TIME_STEP_S
