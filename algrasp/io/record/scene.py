"""The Foxglove scene of a plan without a simulation: the part at each action's outcome
between the jaws, so a plan-only record shows something in the 3-D panel.

Frames (t, x, y, φ, α, q_lower, q_higher) in SI units, as the simulated trajectories the
recorder writes on ``/tf``: the part's centre of mass stays at the world origin; at
``t = 0`` it is at the start orientation with the jaws open along the first action's angle;
at ``t = k`` s it is where the plan leaves it after action k (:meth:`Plan.trace`: for a
robust plan the middle of the interval it can be in), with both jaws touching it.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from algrasp.geometry.angles import to_rad

Frame = tuple[float, float, float, float, float, float, float]
START_DEG = 0.0
"""The start orientation the scene follows (world, degrees)."""
OPEN = 1.5
"""Open jaws stand this many times the part's reach from its centre."""


def plan_frames(plan: Any, outline_m: np.ndarray, phi0: float = to_rad(START_DEG)) -> list[Frame]:
    """The frames of the plan from ``phi0`` (radians): the start, then one per action."""
    reach = float(np.max(np.hypot(*np.asarray(outline_m).T)))
    trace = plan.trace(phi0)
    first = plan.steps[0].gripper_angle
    frames: list[Frame] = [(0.0, 0.0, 0.0, float(phi0), float(first), -OPEN * reach, OPEN * reach)]
    for k, (step, phi) in enumerate(zip(plan.steps, trace[1:]), 1):
        lo, hi = support(outline_m, phi, step.gripper_angle)
        frames.append((float(k), 0.0, 0.0, float(phi), float(step.gripper_angle), lo, hi))
    return frames


def support(outline_m: np.ndarray, phi: float, alpha: float) -> tuple[float, float]:
    """Least and greatest offset (m) of the part at orientation φ along the jaws' closing
    normal n = (−sin α, cos α): where the lower and higher jaw touch it."""
    c, s = np.cos(phi), np.sin(phi)
    pts = np.asarray(outline_m) @ np.array([[c, s], [-s, c]])
    proj = pts @ np.array([-np.sin(alpha), np.cos(alpha)])
    return float(proj.min()), float(proj.max())
