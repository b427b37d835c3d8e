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

from algrasp.geometry.curves import FloatArray
from algrasp.planning.analysis import Analysis
from algrasp.planning.fence_model import FenceDesign, Push, exit_turn, guide_image, leave, on_belt, push_of
from algrasp.planning.motion import Motion, merged_arcs, motion, periodic_copies


def fence_motion(analysis: Analysis, design: FenceDesign, exit_angle: float | None = None) -> Motion:
    """The :class:`Motion` of ``design``: the push on the belt (:func:`on_belt`; the set
    of the robust model, the exact function otherwise) at each fence's angle, the turn
    over each tip between fences where ``design.rules.exit_turns``; with ``exit_angle``
    (the exit guide's world angle, radians) one more ``after`` entry: the last tip's turn,
    the guide's push and its own tip's turn. Every push is tilted by the fence friction
    (:meth:`Push.image` with the fence's angle); ``images`` are the frictionless push's. O(n · N)."""
    belt = on_belt(analysis)
    bounds = None if belt.robust is None else belt.robust.push
    steps = tuple(SimpleNamespace(gripper_angle=float(a)) for a in design.angles)
    first = motion(SimpleNamespace(bounds=bounds, transfer=belt.push, steps=steps[:1]))  # the images, fence 1's arcs
    push = push_of(analysis, design.rules.friction)
    a0 = design.angles[0]
    lo, hi = _ends(first.after[0], -a0)
    after = [_world_image(push, lo, hi, a0)]  # every start: the rests, moved by the friction where they move
    for prev, a in zip(design.angles, design.angles[1:]):
        lo, hi = leave(*_ends(after[-1]), prev, design.rules.exit_turns)
        after.append(_world_image(push, lo - a, hi - a, a))
    if exit_angle is not None:
        last = design.angles[-1]
        lo, hi = guide_image(push, *_ends(after[-1], -last), last, exit_angle)
        after.append(merged_arcs(*periodic_copies(*exit_turn(lo + exit_angle, hi + exit_angle, exit_angle), push.symmetry)))
    return Motion(first.period, first.images, tuple(after))


def _ends(arcs: tuple[tuple[float, float], ...], shift: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """The arcs' lower and upper ends as arrays, shifted."""
    return np.array([a for a, _ in arcs]) + shift, np.array([b for _, b in arcs]) + shift


def _world_image(push: Push, lo: np.ndarray, hi: np.ndarray, alpha: float) -> tuple[tuple[float, float], ...]:
    """The push's image of the arcs [lo, hi] (relative to a fence at α) as world arcs with
    every symmetric copy (the image lands in one period)."""
    glo, ghi = push.image(lo, hi, alpha)
    return merged_arcs(*periodic_copies(glo + alpha, ghi + alpha, push.symmetry))


def follow(analysis: Analysis, design: FenceDesign, starts: FloatArray,
           exit_angle: float | None = None) -> FloatArray:
    """The world arc [lo, hi] (radians, lifted) each start φ₀ of ``starts`` (m,) is in
    after each fence and, with ``exit_angle``, past the exit guide (its push, then its own
    tip's turn): an array (m, N or N + 1, 2). The same composition as :meth:`FenceDesign.run`
    (the push tilted by the fence friction at each fence's angle, the turn over each tip
    in the design's model, the last tip's turn before the guide always); what a page
    animates a single start with, since the tilted push is not one function it could read
    off :func:`fence_motion`'s ``images``. O(m · N · log n)."""
    push = push_of(analysis, design.rules.friction)
    out = design.run_each(push, np.asarray(starts, dtype=float))
    if exit_angle is not None:
        last = design.angles[-1]
        lo, hi = out[-1]
        glo, ghi = guide_image(push, lo - last, hi - last, last, exit_angle)
        out.append(exit_turn(glo + exit_angle, ghi + exit_angle, exit_angle))
    return np.stack([np.stack(pair, axis=-1) for pair in out], axis=1)
