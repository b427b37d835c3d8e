"""Independent references for tests: nothing here uses algrasp's geometry."""

from __future__ import annotations

import numpy as np


def wrapped_close(a: float, b: float, period: float, tol: float) -> bool:
    """Whether angles a and b (same unit as period) agree modulo the period."""
    d = (a - b) % period
    return min(d, period - d) <= tol


def match_angles(got: list[float], want: list[float], period: float, tol: float) -> None:
    """Assert two sets of angles agree one-to-one modulo the period."""
    assert len(got) == len(want), f"{sorted(got)} vs {sorted(want)}"
    left = list(want)
    for g in got:
        k = next((i for i, w in enumerate(left) if wrapped_close(g, w, period, tol)), None)
        assert k is not None, f"{g} not in {left}"
        left.pop(k)


def diameter_of_points(points: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """d(θ) of a point set by brute force (conventions §3): max − min of ⟨R(θ)p, e_y⟩."""
    proj = np.outer(np.sin(theta), points[:, 0]) + np.outer(np.cos(theta), points[:, 1])
    return proj.max(axis=1) - proj.min(axis=1)


def squeeze_by_flow(points: np.ndarray, theta0: float, step: float = 1e-4, max_steps: int = 200000) -> float:
    """Brute-force squeeze: move θ downhill on d (point-set brute force) until it stops."""
    theta = theta0
    d0 = diameter_of_points(points, np.array([theta]))[0]
    for _ in range(max_steps):
        cand = np.array([theta - step, theta + step])
        vals = diameter_of_points(points, cand)
        k = int(np.argmin(vals))
        if vals[k] >= d0:
            return theta
        theta, d0 = float(cand[k]), float(vals[k])
    raise AssertionError("flow did not stop")
