"""Time-optimal chains against hand-computed bang-bang profiles, the CasADi NLP on a
knot grid (independent: it can only be slower), and laws on random chains."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from optimisation.chains import Chain, Profile1D, solve_chains, time_optimal, trapezoid_duration
from optimisation.chains_nlp import INTERVALS_PER_SEGMENT, jerk_limited


def test_triangular_rotation_matches_closed_form() -> None:
    """Rest to rest over Δ with |a| ≤ A, never reaching the speed limit: T = 2√(Δ/A)."""
    p = time_optimal(Chain((0.0, 0.7), (6.0,), 30.0))
    assert p.duration_s == pytest.approx(2 * math.sqrt(0.7 / 30.0), rel=1e-12)


def test_trapezoid_matches_closed_form() -> None:
    """Δ = 0.02 m at v ≤ 0.05, a ≤ 0.5: T = Δ/v + v/a = 0.5 s."""
    assert time_optimal(Chain((0.0, -0.02), (0.05,), 0.5)).duration_s == pytest.approx(0.5, rel=1e-12)


def test_fast_then_slow_by_hand() -> None:
    """6 mm fast (0.05 m/s) then 3 mm at 0.01 m/s, a = 0.5. By hand: 0.1 s to reach
    0.05 m/s (2.5 mm), brake to 0.01 m/s in 0.08 s (2.4 mm), so 1.1 mm cruise (0.022 s);
    then 2.9 mm at 0.01 m/s (0.29 s) and a 0.02 s stop (0.1 mm)."""
    p = time_optimal(Chain((0.0, 0.006, 0.009), (0.05, 0.01), 0.5))
    assert p.duration_s == pytest.approx(0.1 + 0.022 + 0.08 + 0.29 + 0.02, rel=1e-12)
    assert p.q[p.segment_ends[0]] == 0.006 and p.q[-1] == 0.009


def test_reversal_stops_the_axis() -> None:
    """Out and back: two independent rest-to-rest moves."""
    p = time_optimal(Chain((0.0, 1.0, 0.5), (6.0, 6.0), 30.0))
    assert p.duration_s == pytest.approx(2 * math.sqrt(1 / 30) + 2 * math.sqrt(0.5 / 30), rel=1e-12)
    assert p.v[p.segment_ends[0]] == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("chain", [Chain((0.0, 0.7), (6.0,), 30.0), Chain((0.0, 0.006, 0.009), (0.05, 0.01), 0.5),
                                   Chain((0.03, 0.012, 0.004), (0.05, 0.01), 0.5),
                                   Chain((0.004, 0.0052, 0.03), (0.01, 0.05), 0.5)])
def test_a_jerk_limit_only_costs_time(chain: Chain) -> None:
    """CasADi's jerk-limited optimum is never faster than the closed form (its lower
    bound), approaches it as the limit grows (within the knot grid's cost: with a loose
    limit, starting and stopping each still ramp over one of the N intervals of a
    segment, ≤ 2/N), and respects every limit at its knots."""
    exact = time_optimal(chain).duration_s
    loose, tight = jerk_limited(chain, 1e4 * chain.accel_limit), jerk_limited(chain, 10 * chain.accel_limit)
    assert exact * (1 - 1e-6) <= loose.duration_s <= exact * (1 + 2 / INTERVALS_PER_SEGMENT)
    assert tight.duration_s >= loose.duration_s * (1 - 1e-6)
    assert tight.j is not None and np.all(np.abs(tight.j) <= 10 * chain.accel_limit * (1 + 1e-6))
    assert np.all(np.abs(tight.a) <= chain.accel_limit * (1 + 1e-6))
    assert tight.q[-1] == pytest.approx(chain.waypoints[-1], abs=1e-6 * max(chain.speed_limits))


def test_jerk_limited_rotation_matches_the_closed_form_s_curve() -> None:
    """Rest to rest over Δ with only a jerk limit binding (speed and acceleration limits
    loose): the optimum is the symmetric bang-bang jerk profile, T = 4·(Δ/(2J))^(1/3)."""
    delta, jerk = 0.02, 5.0
    p = jerk_limited(Chain((0.0, delta), (100.0,), 1000.0), jerk)
    assert p.duration_s == pytest.approx(4 * (delta / (2 * jerk)) ** (1 / 3), rel=0.02)


def _check_limits(c: Chain, p: Profile1D) -> None:
    """Limits everywhere (acceleration per piece; speed at knots bounds speed between
    them, velocity being piecewise linear), waypoints in order, rest at both ends."""
    assert np.all(np.abs(p.a) <= c.accel_limit * (1 + 1e-9))
    assert p.v[0] == 0.0 and abs(p.v[-1]) <= 1e-9 * max(c.speed_limits)
    start = 0
    for j, end in enumerate(p.segment_ends):
        assert np.all(np.abs(p.v[start:end + 1]) <= c.speed_limits[j] * (1 + 1e-9))
        assert p.q[end] == pytest.approx(c.waypoints[j + 1], abs=1e-9)
        start = end
    dt = np.diff(p.t)
    assert np.allclose(p.q[1:], p.q[:-1] + p.v[:-1] * dt + 0.5 * p.a * dt * dt, atol=1e-9)


chains = st.integers(1, 4).flatmap(lambda k: st.builds(
    Chain, st.lists(st.floats(-1.0, 1.0), min_size=k + 1, max_size=k + 1).map(tuple),
    st.lists(st.floats(0.01, 5.0), min_size=k, max_size=k).map(tuple), st.floats(0.1, 50.0)))


@settings(max_examples=200, deadline=None)
@given(chains)
def test_random_chains_respect_limits_and_beat_the_naive_profile(c: Chain) -> None:
    p = time_optimal(c)
    _check_limits(c, p)
    lower = sum(abs(b - a) / v for a, b, v in zip(c.waypoints, c.waypoints[1:], c.speed_limits))
    assert lower * (1 - 1e-9) <= p.duration_s <= trapezoid_duration(c) * (1 + 1e-9)


@settings(max_examples=100, deadline=None)
@given(chains, st.floats(0.1, 10.0))
def test_time_scales_as_the_law_says(c: Chain, k: float) -> None:
    """Scaling positions and speed limits by k, acceleration by k: same duration."""
    scaled = Chain(tuple(k * q for q in c.waypoints), tuple(k * v for v in c.speed_limits), k * c.accel_limit)
    assert time_optimal(scaled).duration_s == pytest.approx(time_optimal(c).duration_s, rel=1e-9, abs=1e-12)


def test_repeated_chains_are_solved_once() -> None:
    c = Chain((0.0, 1.0), (6.0,), 30.0)
    a, b, rest = solve_chains([c, c, Chain((0.0, 0.0), (1.0,), 1.0)])
    assert a is b and rest.duration_s == 0.0
