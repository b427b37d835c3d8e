"""Jerk-limited time-optimal chains: a CasADi/IPOPT NLP, warm-started from the closed form.

With a jerk limit the minimum-time profile through waypoints with per-segment speed
limits has no simple closed form (S-curves whose junction speeds interact), so it is
solved numerically: a triple integrator with piecewise-constant jerk, N intervals per
segment of free duration T_i / N (position, speed and acceleration exact between knots);
speed and acceleration limits are imposed at the knots (acceleration is linear between
knots, so its limit holds everywhere; speed may exceed its limit between two knots by
at most J·h²/8). The objective is Σ T_i. The uniform grid costs time where the limit is
loose: starting and stopping each ramp over a whole interval (≤ 2/N of a segment).

One SX function per segment count, built once per process (``expand``: a few ms to
solve a chain) and shared by every plan; positions are scaled so the chain's top speed
is 1. The closed-form, jerk-free profile is the warm start and a lower bound: no
jerk-limited motion can be faster (checked on every solve).
"""

from __future__ import annotations

from functools import lru_cache
from typing import Any

import numpy as np

from algrasp.errors import AlgraspError
from optimisation.chains import Chain, Profile1D, time_optimal

INTERVALS_PER_SEGMENT = 16
IPOPT_OPTIONS: dict[str, Any] = {"print_level": 0, "sb": "yes", "max_iter": 500, "tol": 1e-9}
ARRIVAL_TOL = 1e-6
"""A solution whose waypoint, final speed or acceleration error (scaled units) exceeds
this has not converged."""
MIN_WARM_START_S = 1e-3
"""Shortest segment duration the warm start offers IPOPT (a zero-length start stalls it)."""
LOWER_BOUND_SLACK = 1e-6
"""Relative slack when checking that the NLP is no faster than the jerk-free closed form."""


@lru_cache(maxsize=8)
def _solver(count: int) -> Any:
    """CasADi function (dq, vlim, amax, jmax, T0) → (T, J) for a chain of ``count`` segments."""
    import casadi as ca

    N = INTERVALS_PER_SEGMENT
    opti = ca.Opti()
    dq, vlim = opti.parameter(count), opti.parameter(count)
    amax, jmax = opti.parameter(), opti.parameter()
    T, J = opti.variable(count), opti.variable(count, N)
    q: Any = 0
    v: Any = 0
    a: Any = 0
    target: Any = 0
    for i in range(count):
        h = T[i] / N
        target = target + dq[i]
        if i:
            opti.subject_to(opti.bounded(-vlim[i], v, vlim[i]))  # entering speed, under this segment's limit
        for k in range(N):
            jk = J[i, k]
            q = q + v * h + a * h**2 / 2 + jk * h**3 / 6
            v = v + a * h + jk * h**2 / 2
            a = a + jk * h
            opti.subject_to(opti.bounded(-vlim[i], v, vlim[i]))
            opti.subject_to(opti.bounded(-amax, a, amax))
        opti.subject_to(opti.bounded(-jmax, J[i, :], jmax))
        opti.subject_to(q == target)
        opti.subject_to(T[i] >= ca.fabs(dq[i]) / vlim[i])
    opti.subject_to(v == 0)
    opti.subject_to(a == 0)
    opti.minimize(ca.sum1(T))
    opti.solver("ipopt", {"print_time": False, "expand": True, "error_on_fail": False}, IPOPT_OPTIONS)
    return opti.to_function("jerk_chain", [dq, vlim, amax, jmax, T], [T, J])


def jerk_limited(c: Chain, jerk_limit: float) -> Profile1D:
    """The minimum-time rest-to-rest motion of ``c`` with |jerk| ≤ ``jerk_limit`` (unit/s³).
    Raises AlgraspError if the solver does not converge. Cost: one IPOPT solve of
    ~17·K variables (a few ms to tens of ms)."""
    lower = time_optimal(c)
    if lower.duration_s == 0.0:
        return lower
    s = max(c.speed_limits)
    d = np.diff(c.waypoints) / s
    K = len(d)
    # Warm start: the closed form's segment durations plus a ramp of a/j at each end.
    ends = [0, *lower.segment_ends]
    t0 = [max(float(lower.t[b] - lower.t[a]), MIN_WARM_START_S) + 2 * c.accel_limit / jerk_limit / K for a, b in zip(ends, ends[1:])]
    T, J = (np.asarray(x) for x in _solver(K)(d, np.asarray(c.speed_limits) / s, c.accel_limit / s, jerk_limit / s, t0))
    prof = _profile(c, s, T.ravel(), J * s)
    if prof is None or prof.duration_s < lower.duration_s * (1 - LOWER_BOUND_SLACK):
        raise AlgraspError(f"jaw timing: the jerk-limited solver did not converge for the move through "
                           f"{', '.join(f'{q:.6g}' for q in c.waypoints)}")
    return prof


def _profile(c: Chain, s: float, T: Any, J: Any) -> Profile1D | None:
    """Knots of the solved chain (original units), or None if it missed a waypoint or
    did not come to rest."""
    N = INTERVALS_PER_SEGMENT
    h = np.repeat(T / N, N)
    j = np.asarray(J).ravel()
    t = np.concatenate([[0.0], np.cumsum(h)])
    q, v, a = [c.waypoints[0]], [0.0], [0.0]
    for hk, jk in zip(h, j):
        q.append(q[-1] + v[-1] * hk + a[-1] * hk**2 / 2 + jk * hk**3 / 6)
        v.append(v[-1] + a[-1] * hk + jk * hk**2 / 2)
        a.append(a[-1] + jk * hk)
    ends = tuple(N * (k + 1) for k in range(len(T)))
    err = max(abs(q[e] - w) for e, w in zip(ends, c.waypoints[1:])) / s
    if not np.isfinite(err) or err > ARRIVAL_TOL or abs(v[-1]) / s > ARRIVAL_TOL or abs(a[-1]) / s > ARRIVAL_TOL:
        return None
    return Profile1D(t, np.array(q), np.array(v), np.array(a[:-1]), ends, j)
