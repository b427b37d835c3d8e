"""Time-optimal point-to-point motion chains with CasADi (one axis each).

A *chain* is a motion of one axis (a jaw's position, the gripper's angle) from rest to
rest through waypoints q₀ → q₁ → … → q_K; segment i (q_i → q_{i+1}) has its own speed
limit (the jaws' contact speed where they may touch the part, their top speed
elsewhere) and the whole chain one acceleration limit. The model is a double
integrator with piecewise-constant acceleration: N intervals per segment of free
duration T_i / N, so position is exactly piecewise quadratic and velocity exactly
piecewise linear — the limits hold everywhere, not only at the knots (jerk is not
modelled). The objective is Σ T_i.

Every chain of a plan goes into one NLP (the chains are independent, so the problem is
block separable); the CasADi function is built once per *structure* (the tuple of
segment counts) and cached, because building costs about as much as solving.
Positions are scaled so that the chain's speed limit is O(1) before IPOPT sees them.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from algrasp.errors import AlgraspError
from algrasp.geometry.curves import FloatArray

INTERVALS_PER_SEGMENT = 12
IPOPT_OPTIONS: dict[str, Any] = {"print_level": 0, "sb": "yes", "max_iter": 400, "mu_strategy": "adaptive", "tol": 1e-8}
FEASIBLE_SLACK = 1.25
"""A solution slower than this times a simple feasible profile has not converged (the
knot grid alone costs a few per cent: switching times fall between knots)."""
ARRIVAL_TOL = 1e-6
"""A chain whose waypoint or final-speed error (in scaled units) exceeds this has failed."""


@dataclass(frozen=True)
class Chain:
    """Waypoints q₀ … q_K (any unit), K speed limits (unit/s), one acceleration limit."""

    waypoints: tuple[float, ...]
    speed_limits: tuple[float, ...]
    accel_limit: float

    def __post_init__(self) -> None:
        if len(self.waypoints) != len(self.speed_limits) + 1 or not self.speed_limits:
            raise ValueError("a chain needs K ≥ 1 speed limits and K + 1 waypoints")


@dataclass(frozen=True)
class Profile1D:
    """A solved chain: knot times (s) and states; exact between knots.

    ``t`` (M+1,), ``q`` (M+1,), ``v`` (M+1,), ``a`` (M,) piecewise-constant acceleration;
    ``segment_ends`` the knot index where each segment ends.
    """

    t: FloatArray
    q: FloatArray
    v: FloatArray
    a: FloatArray
    segment_ends: tuple[int, ...]

    @property
    def duration_s(self) -> float:
        return float(self.t[-1])

    def sample(self, times: FloatArray) -> FloatArray:
        """Exact position at ``times`` (s, clipped to [0, duration]); shape like ``times``."""
        times = np.clip(np.asarray(times, dtype=float), 0.0, self.duration_s)
        if not len(self.a):
            return np.full(times.shape, self.q[0])
        i = np.clip(np.searchsorted(self.t, times, side="right") - 1, 0, len(self.a) - 1)
        dt = times - self.t[i]
        return self.q[i] + self.v[i] * dt + 0.5 * self.a[i] * dt * dt


@lru_cache(maxsize=64)
def _solver(structure: tuple[int, ...]) -> Any:
    """CasADi function (dq, vlim, amax, T0) → (T, U) for chains of the given segment counts.

    All inputs are flat over the segments of all chains, in scaled units."""
    import casadi as ca

    N = INTERVALS_PER_SEGMENT
    opti = ca.Opti()
    M = sum(structure)
    dq, vlim, amax = opti.parameter(M), opti.parameter(M), opti.parameter(M)
    T, U = opti.variable(M), opti.variable(M, N)
    cost: Any = 0
    i = 0
    for count in structure:
        q, v = ca.MX(0), ca.MX(0)
        target = ca.MX(0)
        for j in range(count):
            h = T[i] / N
            target = target + dq[i]
            if j:
                # The junction velocity obeys the slower of the two segments' limits.
                opti.subject_to(opti.bounded(-vlim[i], v, vlim[i]))
            for k in range(N):
                q = q + v * h + U[i, k] * h * h / 2
                v = v + U[i, k] * h
                opti.subject_to(opti.bounded(-vlim[i], v, vlim[i]))
            opti.subject_to(opti.bounded(-amax[i], U[i, :], amax[i]))
            opti.subject_to(q == target)
            # A valid lower bound (distance / top speed) that keeps IPOPT away from the
            # degenerate T → 0 corner, where the bilinear dynamics make it report infeasible.
            opti.subject_to(T[i] >= ca.fmax(ca.fabs(dq[i]) / vlim[i], ARRIVAL_TOL))
            cost += T[i]
            i += 1
        opti.subject_to(v == 0)
    opti.minimize(cost)
    opti.solver("ipopt", {"print_time": False, "expand": True, "error_on_fail": False}, IPOPT_OPTIONS)
    return opti.to_function("chains", [dq, vlim, amax, T], [T, U])


def solve_chains(chains: list[Chain]) -> list[Profile1D]:
    """Time-optimal profiles of independent chains: one NLP for the distinct moving
    chains (tens of milliseconds for a plan; repeated moves are solved once); a chain
    that NLP leaves unconverged is solved again alone."""
    unique = list(dict.fromkeys(c for c in chains if any(b != a for a, b in zip(c.waypoints, c.waypoints[1:]))))
    first = dict(zip(unique, _solve_together(unique))) if unique else {}
    solved: dict[Chain, Profile1D] = {}
    for c, p in first.items():
        if p is None or p.duration_s > trapezoid_duration(c) * FEASIBLE_SLACK:
            p = _solve_together([c])[0]
        if p is None or p.duration_s > trapezoid_duration(c) * FEASIBLE_SLACK:
            raise AlgraspError(f"jaw timing: the time-optimal solver did not converge for the move through "
                               f"{', '.join(f'{q:.6g}' for q in c.waypoints)}")
        solved[c] = p
    return [solved[c] if c in solved else _at_rest(c) for c in chains]


def _at_rest(c: Chain) -> Profile1D:
    """The profile of a chain that does not move (zero duration)."""
    return Profile1D(np.zeros(1), np.array([c.waypoints[0]]), np.zeros(1), np.zeros(0), tuple(0 for _ in c.speed_limits))


def trapezoid_duration(c: Chain) -> float:
    """Duration of rest-to-rest trapezoids (or triangles) on every segment at its own
    limit, in closed form: the constant-speed reference profile, and a feasible profile
    the optimum can only beat (a much longer solution did not converge)."""
    total = 0.0
    for d, v in zip(np.abs(np.diff(c.waypoints)), c.speed_limits):
        a = c.accel_limit
        total += d / v + v / a if d >= v * v / a else 2 * float(np.sqrt(d / a))
    return total


def _solve_together(chains: list[Chain]) -> list[Profile1D | None]:
    scale = [max(c.speed_limits) for c in chains]  # 1 s of top speed = 1 unit
    dq, vl, am, t0 = [], [], [], []
    for c, s in zip(chains, scale):
        d = np.diff(c.waypoints) / s
        lim = np.asarray(c.speed_limits) / s
        dq += list(d)
        vl += list(lim)
        am += [c.accel_limit / s] * len(d)
        t0 += list(np.abs(d) / lim + 2 * lim / (c.accel_limit / s))
    fn = _solver(tuple(len(c.speed_limits) for c in chains))
    T, U = (np.asarray(x) for x in fn(dq, vl, am, t0))
    out: list[Profile1D | None] = []
    i = 0
    for c, s in zip(chains, scale):
        K = len(c.speed_limits)
        out.append(_profile(c, s, T.ravel()[i:i + K], U[i:i + K]))
        i += K
    return out


def _profile(c: Chain, s: float, T: FloatArray, U: FloatArray) -> Profile1D | None:
    """The chain's knots from the solver output, or None if it missed a waypoint."""
    N, K = INTERVALS_PER_SEGMENT, len(c.speed_limits)
    h = np.repeat(T / N, N)
    a = U.ravel() * s
    t = np.concatenate([[0.0], np.cumsum(h)])
    v = np.concatenate([[0.0], np.cumsum(a * h)])
    q = c.waypoints[0] + np.concatenate([[0.0], np.cumsum(v[:-1] * h + 0.5 * a * h * h)])
    ends = tuple(N * (k + 1) for k in range(K))
    err = float(np.max(np.abs(q[list(ends)] - np.asarray(c.waypoints[1:])))) / s
    if not np.isfinite(err) or err > ARRIVAL_TOL or abs(v[-1]) / s > ARRIVAL_TOL:
        return None
    return Profile1D(t, q, v, a, ends)
