"""Time-optimal chains against closed-form bang-bang profiles."""

from __future__ import annotations

import math

import numpy as np
import pytest

from optimisation.chains import INTERVALS_PER_SEGMENT, Chain, solve_chains


def test_triangular_rotation_matches_closed_form() -> None:
    """Rest to rest over Δ with |a| ≤ A, never reaching the speed limit: T = 2√(Δ/A)."""
    (p,) = solve_chains([Chain((0.0, 0.7), (6.0,), 30.0)])
    assert p.duration_s == pytest.approx(2 * math.sqrt(0.7 / 30.0), rel=2e-3)


def test_trapezoid_matches_closed_form() -> None:
    """Δ = 0.02 m at v ≤ 0.05, a ≤ 0.5: T = Δ/v + v/a = 0.5 s. The knot grid cannot place
    the switching times exactly, so the optimum is approached from above."""
    (p,) = solve_chains([Chain((0.0, 0.02), (0.05,), 0.5)])
    assert 0.5 <= p.duration_s <= 0.5 * 1.01


def test_slow_zone_and_limits_hold_everywhere() -> None:
    """Fast approach then contact speed: speed ≤ 0.01 inside the slow segment (exactly:
    velocity is piecewise linear), acceleration within its limit, waypoints met."""
    chain = Chain((0.0, 0.006, 0.009), (0.05, 0.01), 0.5)
    (p,) = solve_chains([chain])
    assert np.all(np.abs(p.a) <= 0.5 * (1 + 1e-6))
    assert np.all(np.abs(p.v) <= 0.05 * (1 + 1e-6))
    slow = np.arange(INTERVALS_PER_SEGMENT, 2 * INTERVALS_PER_SEGMENT + 1)
    assert np.all(np.abs(p.v[slow]) <= 0.01 * (1 + 1e-6))
    assert p.q[INTERVALS_PER_SEGMENT] == pytest.approx(0.006, abs=1e-9) and p.q[-1] == pytest.approx(0.009, abs=1e-9)
    # Lower bound by hand: 3 mm at ≤ 10 mm/s, then a stop from 10 mm/s.
    assert p.duration_s >= 0.3
    t = np.linspace(0.0, p.duration_s, 2001)
    q = p.sample(t)
    assert np.all(np.diff(q) >= -1e-12)  # no overshoot and return


def test_many_chains_solve_independently() -> None:
    alone = [solve_chains([c])[0].duration_s for c in (Chain((0.0, 1.0), (6.0,), 30.0), Chain((0.0, -0.01), (0.05,), 0.5))]
    together = [p.duration_s for p in solve_chains([Chain((0.0, 1.0), (6.0,), 30.0), Chain((0.0, -0.01), (0.05,), 0.5)])]
    assert together == pytest.approx(alone, rel=1e-6)
