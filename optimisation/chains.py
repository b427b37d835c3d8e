"""Time-optimal point-to-point motion chains, in closed form (one axis each).

A *chain* is a motion of one axis (a jaw's position, the gripper's angle) from rest to
rest through waypoints q₀ → q₁ → … → q_K; segment i (q_i → q_{i+1}) has its own speed
limit (the jaws' contact speed where they may touch the part, their top speed
elsewhere) and the whole chain one acceleration limit. Jerk is not limited.

The minimum-time motion of a double integrator under a position-dependent speed limit
is the classic forward/backward sweep: the speed at distance x along the path is the
smallest of the segment's limit, the speed reachable accelerating from the start and
the speed from which the axis can still brake for every later limit. Per segment that
is at most accelerate–cruise–brake at the limits, so the profile is exact (bang-bang
with cruise, switching times solved in closed form) and costs O(K). Where the path
reverses, the axis stops.

This profile replaces an IPOPT solve that rediscovered it on a knot grid for every
plan (1.2 s per plan, now microseconds). CasADi keeps the moves a closed form cannot
give: jerk-limited S-curves (``optimisation.chains_nlp``), for which this profile is
the warm start and a lower bound.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from algrasp.geometry.curves import FloatArray


@dataclass(frozen=True)
class Chain:
    """Waypoints q₀ … q_K (any unit), K speed limits (unit/s), one acceleration limit."""

    waypoints: tuple[float, ...]
    speed_limits: tuple[float, ...]
    accel_limit: float

    def __post_init__(self) -> None:
        if len(self.waypoints) != len(self.speed_limits) + 1 or not self.speed_limits:
            raise ValueError("a chain needs K ≥ 1 speed limits and K + 1 waypoints")
        if min(self.speed_limits) <= 0.0 or self.accel_limit <= 0.0:
            raise ValueError("speed and acceleration limits must be positive")


@dataclass(frozen=True)
class Profile1D:
    """A solved chain: knot times (s) and states; exact between knots.

    ``t`` (M+1,), ``q`` (M+1,), ``v`` (M+1,), ``a`` (M,) the acceleration at the start of
    each piece, ``j`` (M,) its constant jerk (None: zero, acceleration piecewise constant);
    ``segment_ends`` the knot index where each segment ends.
    """

    t: FloatArray
    q: FloatArray
    v: FloatArray
    a: FloatArray
    segment_ends: tuple[int, ...]
    j: FloatArray | None = None

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
        jerk = 0.0 if self.j is None else self.j[i] * dt**3 / 6
        return self.q[i] + self.v[i] * dt + 0.5 * self.a[i] * dt * dt + jerk  # type: ignore[no-any-return]


def _junction_caps(c: Chain) -> list[float]:
    """Largest speed at each waypoint: 0 at both ends and where the path reverses, else
    the smaller limit of the segments meeting there (zero-length segments included)."""
    d = np.diff(c.waypoints)
    caps = [0.0] + [min(c.speed_limits[j - 1], c.speed_limits[j]) for j in range(1, len(d))] + [0.0]
    last = 0.0  # direction (±1) of the last moving segment: signs, since products of tiny steps underflow
    for j, dj in enumerate(d):
        if dj == 0.0:
            continue
        direction = 1.0 if dj > 0.0 else -1.0
        if last == -direction:
            caps[j] = 0.0
        last = direction
    for j, dj in enumerate(d):  # a zero-length segment caps the speed through its point
        if dj == 0.0:
            caps[j] = min(caps[j], c.speed_limits[j])
            caps[j + 1] = min(caps[j + 1], c.speed_limits[j])
    return caps


def _boundary_speeds(c: Chain) -> list[float]:
    """Speed at each waypoint of the time-optimal motion (forward, then backward sweep)."""
    a, lengths, caps = c.accel_limit, np.abs(np.diff(c.waypoints)), _junction_caps(c)
    fwd = [0.0]
    for j, D in enumerate(lengths):
        fwd.append(min(caps[j + 1], c.speed_limits[j], math.sqrt(fwd[j] ** 2 + 2 * a * D)))
    out = fwd[:]
    for j in range(len(lengths) - 1, -1, -1):
        out[j] = min(fwd[j], c.speed_limits[j], math.sqrt(out[j + 1] ** 2 + 2 * a * lengths[j]))
    return out


def _phases(D: float, s: float, e: float, V: float, a: float) -> list[tuple[float, float]]:
    """(duration, signed acceleration in the direction of travel) of one segment of
    length D entered at speed s, left at e, under limit V: accelerate, cruise, brake."""
    peak = math.sqrt(max((s * s + e * e + 2 * a * D) / 2, 0.0))
    if peak <= V:
        return [((peak - s) / a, a), ((peak - e) / a, -a)]
    cruise = (D - (V * V - s * s) / (2 * a) - (V * V - e * e) / (2 * a)) / V
    return [((V - s) / a, a), (max(cruise, 0.0), 0.0), ((V - e) / a, -a)]


def time_optimal(c: Chain) -> Profile1D:
    """The minimum-time rest-to-rest motion of a chain (exact; O(K)).

    >>> p = time_optimal(Chain((0.0, 0.02), (0.05,), 0.5))  # trapezoid: Δ/v + v/a
    >>> round(p.duration_s, 12)
    0.5
    """
    speeds, a = _boundary_speeds(c), c.accel_limit
    t, q, v, acc, ends = [0.0], [c.waypoints[0]], [0.0], [], []
    for j, (q0, q1) in enumerate(zip(c.waypoints, c.waypoints[1:])):
        sign = 1.0 if q1 >= q0 else -1.0
        for dt, ac in _phases(abs(q1 - q0), speeds[j], speeds[j + 1], c.speed_limits[j], a) if q1 != q0 else []:
            if dt <= 0.0:
                continue
            a_signed = sign * ac
            q.append(q[-1] + v[-1] * dt + 0.5 * a_signed * dt * dt)
            v.append(v[-1] + a_signed * dt)
            t.append(t[-1] + dt)
            acc.append(a_signed)
        q[-1] = q1  # the waypoint itself, not its rounding
        ends.append(len(t) - 1)
    v[-1] = 0.0
    return Profile1D(np.array(t), np.array(q), np.array(v), np.array(acc), tuple(ends))


def solve_chains(chains: list[Chain], solve: Callable[[Chain], Profile1D] = time_optimal) -> list[Profile1D]:
    """``solve`` (default: the closed form) for each chain; repeated chains solved once."""
    solved: dict[Chain, Profile1D] = {}
    for c in chains:
        if c not in solved:
            solved[c] = solve(c)
    return [solved[c] for c in chains]


def trapezoid_duration(c: Chain) -> float:
    """Duration of rest-to-rest trapezoids (or triangles) on every segment at its own
    limit, in closed form: the naive stop-at-every-waypoint reference."""
    total = 0.0
    for d, v in zip(np.abs(np.diff(c.waypoints)), c.speed_limits):
        a = c.accel_limit
        total += d / v + v / a if d >= v * v / a else 2 * float(np.sqrt(d / a))
    return total
