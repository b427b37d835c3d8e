"""Brute-force execution of plans on *exact* parts, independent of the planner.

A part is given as its hull-relevant vertices and circular arcs; its support function is
evaluated directly (max over vertices and arcs), d and r on a fine grid, slopes by central
differences. A squeeze (push) moves the part downhill on d (r) while the slope beats the
stall threshold s and stops at the first orientation where |slope| ≤ s or where the slope
changes sign (quasi-static rest, conventions §7 with σ = 0). Nothing here uses algrasp.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

GRID_DEG = 0.001


@dataclass(frozen=True)
class ExactPart:
    vertices: np.ndarray  # (n, 2)
    arcs: tuple[tuple[float, float, float, float, float], ...]  # (cx, cy, R, a0_rad, a1_rad), a0 < a1
    com: tuple[float, float]

    def support(self, psi: np.ndarray) -> np.ndarray:
        u = np.stack([np.cos(psi), np.sin(psi)], axis=-1)
        h = (u @ self.vertices.T).max(axis=-1) if len(self.vertices) else np.full(psi.shape, -np.inf)
        for cx, cy, R, a0, a1 in self.arcs:
            inside = np.mod(psi - a0, 2 * np.pi) <= (a1 - a0)
            h = np.where(inside, np.maximum(h, cx * u[..., 0] + cy * u[..., 1] + R), h)
        return h

    def diameter(self, theta: np.ndarray) -> np.ndarray:
        psi = np.pi / 2 - theta
        return self.support(psi) + self.support(psi + np.pi)

    def radius(self, theta: np.ndarray) -> np.ndarray:
        psi = np.pi / 2 - theta
        return self.com[0] * np.cos(psi) + self.com[1] * np.sin(psi) + self.support(psi + np.pi)


class Flow:
    """Quasi-static descent on f with stall threshold s, tabulated on a grid over 2π.

    With jaw friction μ (a squeeze: two contacts f apart) the part also rests where
    |f′| ≤ μ·f + s: the friction couple μ·F·f against the squeeze couple F·f′. With
    ``wall_friction`` s μ (a fence the part slides along) it descends on f′ + s μ f."""

    def __init__(self, f, stall: float, jaw_friction: float = 0.0, wall_friction: float = 0.0) -> None:
        n = int(round(360.0 / GRID_DEG))
        self.theta = np.arange(n) * (2 * np.pi / n)
        h = 1e-6
        g = (f(self.theta + h) - f(self.theta - h)) / (2 * h)
        # A fence (one contact, sliding along it): the reaction N(n − s μ t) on the edge of
        # the friction cone has moment −N (f′ + s μ f) about the centre of mass (jaw frame,
        # f the distance to the wall): ``wall_friction`` is s μ, s = +1 on the right rail.
        g = g + wall_friction * f(self.theta)
        self.n = n
        hold = stall + jaw_friction * f(self.theta)
        right = g < -hold  # moves to larger θ
        left = g > hold
        idx = np.arange(n)
        # first index ≥ i (cyclic) that does not move right; last index ≤ i that does not move left
        stop_r = np.nonzero(~right)[0]
        stop_l = np.nonzero(~left)[0]
        ext_r = np.concatenate([stop_r, stop_r + n])
        ext_l = np.concatenate([stop_l - n, stop_l])
        self.dest = idx.copy()
        r = right
        self.dest[r] = ext_r[np.searchsorted(ext_r, idx[r], side="left")]
        lmask = left
        self.dest[lmask] = ext_l[np.searchsorted(ext_l, idx[lmask], side="right") - 1]
        self.step = 2 * np.pi / n

    def __call__(self, theta: np.ndarray) -> np.ndarray:
        k = np.floor(theta / (2 * np.pi))
        i = np.rint((theta - k * 2 * np.pi) / self.step).astype(int) % self.n
        return k * 2 * np.pi + self.dest[i] * self.step


def run_plan(part: ExactPart, stall: float | list[float], plan_doc: dict, starts: np.ndarray,
             jaw_friction: float = 0.0) -> np.ndarray:
    """Final world orientations (radians) after executing a plan document's steps in one
    cell (``stall`` a number, or a one-value range [s, s])."""
    if isinstance(stall, list):
        assert stall[0] == stall[1], "one cell at a time"
        stall = stall[0]
    squeeze = Flow(part.diameter, stall, jaw_friction)
    push = Flow(part.radius, stall) if plan_doc["action"] == "push_grasp" else None
    phi = np.asarray(starts, dtype=float)
    for step in plan_doc["steps"]:
        alpha = math.radians(step["gripper_angle_deg"])
        theta = phi - alpha
        if push is not None:
            theta = push(theta)
        phi = squeeze(theta) + alpha
    return np.mod(phi, 2 * np.pi)


def worst_miss_deg(finals: np.ndarray, plan_doc: dict) -> float:
    """Largest distance (degrees) from a final orientation to the nearest claimed one."""
    want = np.radians(plan_doc["final_orientations_deg"])
    diff = np.abs((finals[:, None] - want[None, :] + np.pi) % (2 * np.pi) - np.pi).min(axis=1)
    return float(np.degrees(diff.max()))


def fig11(R: float = 10.0, z_deg: float = 11.0) -> ExactPart:
    z = math.radians(z_deg)
    s, c = R * math.sin(z), R * math.cos(z)
    verts = np.array([[s, c], [-s, c], [-s, -c], [s, -c]])
    arcs = ((0.0, 0.0, R, math.pi / 2 + z, 3 * math.pi / 2 - z), (0.0, 0.0, R, -math.pi / 2 + z, math.pi / 2 - z))
    return ExactPart(verts, arcs, (0.0, 0.0))


def pie(R: float = 5.0, half_deg: float = 20.0, com: tuple[float, float] | None = None) -> ExactPart:
    h = math.radians(half_deg)
    verts = np.array([[0.0, 0.0], [R * math.sin(h), R * math.cos(h)], [-R * math.sin(h), R * math.cos(h)]])
    a0, a1 = math.pi / 2 - h, math.pi / 2 + h
    if com is None:  # area centroid of a circular sector
        com = (0.0, 2 * R * math.sin(h) / (3 * h))
    return ExactPart(verts, ((0.0, 0.0, R, a0, a1),), com)
