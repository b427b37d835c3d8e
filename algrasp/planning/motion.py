"""What a plan does to orientations, for pictures: the action's own set-valued images and,
per action, where the part can be after it from any start (conventions §4, §7).

A page or a record follows a start orientation through a plan with these alone, so the
animation shows the plan that was made (its robust bounds, when it has them) rather than
a second planner's guess. Radians here; :class:`~algrasp.planning.documents.PlanDocument`
writes them in degrees.

>>> from algrasp import plan
>>> p = plan({"name": "r", "boundary": [[0, 0], [4, 0], [4, 2], [0, 2]]}, exact=True)
>>> m = motion(p)
>>> [[round(a, 6) for a in arc] for arc in m.after[-1]]
[[0.0, 0.0], [3.141593, 3.141593]]
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

Arc = tuple[float, float]
MERGE_RAD = 1e-9


@dataclass(frozen=True)
class Motion:
    """``period``: the images repeat with it (θ + period ↦ image + period); ``images``:
    pieces ``(start, end, lower, upper)`` of the action's map in the gripper frame, over one
    period, lifted (None: θ itself); ``after``: per action, the world arcs ``[lo, hi]``
    (lo in [0, 2π)) holding every orientation the part can be in after it, from any start."""

    period: float
    images: tuple[tuple[float, float, float | None, float | None], ...]
    after: tuple[tuple[Arc, ...], ...]


def motion(plan: Any) -> Motion:
    """The :class:`Motion` of a :class:`~algrasp.planning.plans.Plan`."""
    S, F = plan.bounds, plan.transfer
    if S is not None:
        from algrasp.planning.documents import SetTransferDocument

        period = float(S.symmetry)
        images = SetTransferDocument.from_set(S).images
        first = [(float(a), float(b)) for a, b in S.outcomes]
    else:
        period = float(F.period)
        images = tuple((p.start, p.end, p.value, p.value) for p in F.pieces)
        first = [(p.start, p.end) if p.value is None else (p.value, p.value) for p in F.pieces]
    lo, hi = periodic_copies(np.array([a for a, _ in first]), np.array([b for _, b in first]), period)
    steps = plan.steps
    lo, hi = lo + steps[0].gripper_angle, hi + steps[0].gripper_angle
    after = [merged_arcs(lo, hi)]
    for s in steps[1:]:
        a = s.gripper_angle
        if S is not None:
            lo, hi = S.image(lo - a, hi - a)
        else:
            lo, hi = F.apply(lo - a), F.apply(hi - a)
        lo, hi = lo + a, hi + a
        after.append(merged_arcs(lo, hi))
    return Motion(period, tuple(images), tuple(after))


def periodic_copies(lo: np.ndarray, hi: np.ndarray, period: float) -> tuple[np.ndarray, np.ndarray]:
    """The arcs [lo, hi] and their copies shifted by every multiple of ``period`` round the
    circle: (k·n,) arrays, k = 2π / period."""
    k = np.arange(max(1, round(2 * math.pi / period))) * period
    return (lo[None, :] + k[:, None]).ravel(), (hi[None, :] + k[:, None]).ravel()


def merged_arcs(lo: np.ndarray, hi: np.ndarray) -> tuple[Arc, ...]:
    """The arcs [lo, hi] wrapped to start in [0, 2π), overlapping ones joined (one that
    reaches past 2π joins those it covers after 0)."""
    two_pi = 2 * math.pi
    start = np.mod(lo, two_pi)
    arcs = sorted(zip(start.tolist(), (start + (hi - lo)).tolist()))
    out: list[list[float]] = []
    for a, b in arcs:
        if out and a <= out[-1][1] + MERGE_RAD:
            out[-1][1] = max(out[-1][1], b)
        else:
            out.append([a, b])
    while len(out) > 1 and out[-1][1] - two_pi >= out[0][0] - MERGE_RAD:  # the last wraps over the first
        a, b = out.pop(0)
        out[-1][1] = max(out[-1][1], b + two_pi)
    return tuple((round(a, 12), round(b, 12)) for a, b in out)
