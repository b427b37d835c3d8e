"""What a fence design does to orientations, for pictures (conventions §9): the push's own
images as the fences see it and, per fence, the world arcs the part can be in after it
from any start, the same :class:`~algrasp.planning.motion.Motion` a plan has. Passing fence
i maps φ to p(φ − α_i) + α_i, a gripper action at α_i with the push p on the belt, and in
the design's model the part then turns over the fence's tip (:func:`leave`) before the
next one; an exit guide is one more push at its angle, then its own tip's turn. A page
follows a start along the belt with these alone (no planner of its own). Radians.

>>> from algrasp.planning.analysis import EXACT, analyse_document
>>> from algrasp.planning.fences import design_fences
>>> a = analyse_document({"name": "r", "boundary": [[0, 0], [4, 0], [4, 2], [0, 2]]}, EXACT)
>>> d = design_fences(a)
>>> m = fence_motion(a, d)
>>> len(m.after) == len(d.angles), [round(lo - hi, 9) for lo, hi in m.after[-1]]
(True, [0.0, 0.0])
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from algrasp.planning.analysis import Analysis
from algrasp.planning.fence_model import FenceDesign, exit_turn, leave, on_belt, push_of
from algrasp.planning.motion import Motion, merged_arcs, motion


def fence_motion(analysis: Analysis, design: FenceDesign, exit_angle: float | None = None) -> Motion:
    """The :class:`Motion` of ``design``: the push on the belt (:func:`on_belt`; the set
    of the robust model, the exact function otherwise) at each fence's angle, the turn
    over each tip between fences where ``design.rules.exit_turns``; with ``exit_angle``
    (the exit guide's world angle, radians) one more ``after`` entry: the last tip's turn,
    the guide's push and its own tip's turn. O(n · N)."""
    belt = on_belt(analysis)
    bounds = None if belt.robust is None else belt.robust.push
    steps = tuple(SimpleNamespace(gripper_angle=float(a)) for a in design.angles)
    plain = motion(SimpleNamespace(bounds=bounds, transfer=belt.push, steps=steps))
    if not design.rules.exit_turns and exit_angle is None:
        return plain
    push = push_of(analysis)
    lo = np.array([a for a, _ in plain.after[0]])
    hi = np.array([b for _, b in plain.after[0]])
    after = [plain.after[0]]
    angles = [*design.angles, *([] if exit_angle is None else [exit_angle])]
    guide = len(design.angles) if exit_angle is not None else -1  # its index in ``angles``
    for i in range(1, len(angles)):
        a = angles[i]
        lo, hi = leave(lo, hi, angles[i - 1], design.rules.exit_turns or i == guide)  # a guide's input always turned
        lo, hi = push.image(lo - a, hi - a)
        lo, hi = lo + a, hi + a
        if i == guide:  # and off the guide's own tip
            lo, hi = exit_turn(lo, hi, a)
        arcs = merged_arcs(*_copies(lo, hi, push.symmetry))  # the image lands in one period: every copy
        after.append(arcs)
        lo, hi = np.array([x for x, _ in arcs]), np.array([y for _, y in arcs])
    return Motion(plain.period, plain.images, tuple(after))


def _copies(lo: np.ndarray, hi: np.ndarray, period: float) -> tuple[np.ndarray, np.ndarray]:
    """The arcs [lo, hi] and their copies shifted by every multiple of ``period`` round the circle."""
    k = np.arange(max(1, round(2 * np.pi / period))) * period
    return (lo[None, :] + k[:, None]).ravel(), (hi[None, :] + k[:, None]).ravel()
