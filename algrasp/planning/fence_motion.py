"""What a fence design does to orientations, for pictures (conventions §9): the push's own
images as the fences see it and, per fence, the world arcs the part can be in after it
from any start, the same :class:`~algrasp.planning.motion.Motion` a plan has. Passing fence
i maps φ to p(φ − α_i) + α_i, a gripper action at α_i with the push p on the belt, so a page
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

from algrasp.planning.analysis import Analysis
from algrasp.planning.fence_model import FenceDesign, on_belt
from algrasp.planning.motion import Motion, motion


def fence_motion(analysis: Analysis, design: FenceDesign) -> Motion:
    """The :class:`Motion` of ``design``: the push on the belt (:func:`on_belt`; the set
    of the robust model, the exact function otherwise) at each fence's angle. O(n · N)."""
    belt = on_belt(analysis)
    bounds = None if belt.robust is None else belt.robust.push
    steps = tuple(SimpleNamespace(gripper_angle=float(a)) for a in design.angles)
    return motion(SimpleNamespace(bounds=bounds, transfer=belt.push, steps=steps))
