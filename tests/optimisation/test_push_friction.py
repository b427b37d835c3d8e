"""The push law with jaw friction (conventions §8): a pusher with friction never turns the
part faster than a frictionless one, and the stick and slide regimes meet continuously.

Checked against the quasi-static equations solved here directly: for a sticking contact
the part's twist (v, ω) on the ellipsoidal limit surface (v ∝ F, ω ∝ M / c²) must move
the contact point q = (q_x, −r) with the jaw at unit speed along n, and the force must lie
in the friction cone; for a sliding one the force is on the cone's edge."""

from __future__ import annotations

import numpy as np
import pytest

from optimisation.push import PushModel


def _model(mu: float) -> PushModel:
    z = np.zeros(2)
    return PushModel(z, z, 1.0, 1.0, z, mu)


def _rate_by_equations(q: float, r: float, c: float, mu: float) -> float:
    """|ω| per unit push from a 3×3 solve of the twist with the contact stuck, else the
    sliding twist with the force on the cone's edge (the edge that opposes the slip)."""
    # unknowns (Fx, Fy, ω) with v = F (unit scale), ω c² = M = q_x F_y + r F_x;
    # stuck contact velocity: v + ω × q = (0, 1) → Fx + ω r = 0, Fy + ω q = 1.
    A = np.array([[r, q, -c * c], [1.0, 0.0, r], [0.0, 1.0, q]])
    Fx, Fy, w = np.linalg.solve(A, [0.0, 0.0, 1.0])
    if abs(Fx) <= mu * abs(Fy) + 1e-15:
        return abs(w)
    best = 0.0
    for s in (-1.0, 1.0):  # F = λ(s μ, 1): M = λ(q + r s μ), v_y = λ, contact: λ(1 + q (q + r s μ)/c²) = 1
        lam = 1.0 / (1.0 + q * (q + r * s * mu) / (c * c))
        omega = lam * (q + r * s * mu) / (c * c)
        slip = lam * s * mu + omega * r  # tangential contact velocity: friction must oppose it
        if lam > 0 and slip * s <= 0:
            best = abs(omega)
    return best


@pytest.mark.parametrize("mu", [0.05, 0.1, 0.3])
def test_rate_matches_the_equations_and_never_beats_frictionless(mu: float) -> None:
    rng = np.random.default_rng(4)
    q = rng.uniform(0.01, 20.0, 400)
    r = rng.uniform(0.5, 20.0, 400)
    c = rng.uniform(1.0, 15.0, 400)
    got = _model(mu).rate(q, r, c)
    frictionless = q / (c * c + q * q)
    assert np.all(got <= frictionless + 1e-12)
    want = np.array([_rate_by_equations(a, b, k, mu) for a, b, k in zip(q, r, c)])
    assert got == pytest.approx(want, rel=1e-9, abs=1e-12)


def test_zero_friction_is_the_frictionless_law() -> None:
    q = np.linspace(0.1, 5.0, 50)
    assert _model(0.0).rate(q, np.full(50, 3.0), np.full(50, 2.0)) == pytest.approx(q / (4.0 + q * q), rel=1e-12)
