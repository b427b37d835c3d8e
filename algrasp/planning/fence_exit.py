"""The exit guide (conventions §9): how the part leaves the last fence, and the orientation
a fence design claims downstream of it. Pure: no I/O; angles in radians.

A part comes off a straight fence's tip turned towards the belt direction by some
t ∈ [0, β] (:func:`~algrasp.planning.fence_model.exit_turn`): on the last fence the design
knows the part within its uncertainty, past its tip only within β. So the last fence
continues, on the same rail, as an **exit guide**: a straight wall from its tip at a small
steepness β_e (default 2°). The part arrives at the guide turned by at most β_N from its
orientation on the last fence (the kink at the tip is convex, as the tip itself is); the
guide pushes it as any fence does, ``p(φ − α_e) + α_e``, back onto the same edge (the
arrival arc must collapse again, checked here), and at the guide's own end it turns by at
most β_e. The claim downstream is that arc: the guide's image widened by β_e towards the
belt direction, its middle the final orientation, its half-width plus the image's
uncertainty the final uncertainty. A smaller β_e claims more precisely but the guide is
longer (the push the part needs at β_e takes a slide cot β_e as long).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from algrasp.errors import ConfigError
from algrasp.geometry.angles import to_deg, to_rad
from algrasp.geometry.tolerances import MAX_UNCERTAINTY_RAD, UNCERTAINTY_FLOOR_RAD
from algrasp.planning.analysis import Analysis
from algrasp.planning.fence_model import EXIT_STEEPNESS_RAD, FenceDesign, exit_turn, guide_angle, push_of, to_guide
from algrasp.planning.planner import GUARD_RAD
from algrasp.planning.plans import _edge_tilt

DEFAULT_EXIT_STEEPNESS_DEG = float(to_deg(EXIT_STEEPNESS_RAD))
"""β_e: the exit guide's angle to the belt; the claim downstream is ±β_e/2 wider."""
MAX_EXIT_STEEPNESS_DEG = 10.0
"""A guide steeper than a fence's least steepness would be a fence: refused."""
EXACT_GOAL_RAD = 1e-9


@dataclass(frozen=True)
class ExitGuide:
    """The exit guide of a fence design and the claim downstream of it (radians).

    Attributes
    ----------
    angle : float
        α_e, the guide's world angle (β_e on the right rail, π − β_e on the left).
    side : int
        The last fence's rail (0 right, 1 left).
    steepness : float
        β_e.
    input : (float, float)
        The arc (relative to α_e, lifted) the part arrives at the guide in.
    image : (float, float)
        The arc (relative to α_e) the guide leaves it in, before its end.
    final_orientations : tuple of float
        World orientations the part leaves the guide in, [0, 2π), one per period T.
    final_uncertainty : float
        Half-width around each: the image's uncertainty plus β_e / 2.
    """

    angle: float
    side: int
    steepness: float
    input: tuple[float, float]
    image: tuple[float, float]
    final_orientations: tuple[float, ...]
    final_uncertainty: float


def exit_steepness(value: float | None) -> float:
    """β_e (radians) from degrees (None: the default, ``EXIT_STEEPNESS_RAD``).

    Raises ConfigError (``exit_steepness_deg``) unless 0 < β_e ≤ 10°."""
    deg = DEFAULT_EXIT_STEEPNESS_DEG if value is None else value
    if not (isinstance(deg, (int, float)) and np.isfinite(deg) and 0.0 < deg <= MAX_EXIT_STEEPNESS_DEG):
        raise ConfigError("exit_steepness_deg", f"expected 0 < β_e ≤ {MAX_EXIT_STEEPNESS_DEG:g}° (the exit guide's "
                          f"angle to the belt), got {value!r}")
    return float(to_rad(float(deg)))


def exit_guide(analysis: Analysis, design: FenceDesign, steepness: float) -> ExitGuide | None:
    """The exit guide of ``design`` at steepness β_e (radians), or None when the guide's
    push does not bring the arc the part arrives in back to one orientation (the last
    fence is then the claim's end, widened by its own steepness). O(1) arc pushes."""
    push = push_of(analysis, design.rules.friction)
    a_n, side = design.angles[-1], design.sides[-1]
    alpha = float(guide_angle(a_n, steepness))
    if len(design.angles) == 1:  # from every start: the first fence's image of the circle
        lo, hi = (np.atleast_1d(x) for x in push.circle_at(a_n))
    else:
        lo, hi = push.image(np.array([design.inputs[-1][0]]), np.array([design.inputs[-1][1]]), a_n)
    lo, hi = to_guide(lo, hi, a_n, alpha)
    glo, ghi = push.image(lo, hi, alpha)
    goal = EXACT_GOAL_RAD if push.exact else 2.0 * MAX_UNCERTAINTY_RAD
    if float(ghi[0] - glo[0]) > goal:
        return None
    flo, fhi = exit_turn(glo, ghi, alpha)
    image_unc = 0.0 if push.exact else max(0.5 * float(ghi[0] - glo[0]) + GUARD_RAD
                                           + _edge_tilt(analysis, float(glo[0]), float(ghi[0])), UNCERTAINTY_FLOOR_RAD)
    mid = 0.5 * float(flo[0] + fhi[0]) + alpha
    T = push.symmetry
    finals = tuple(sorted(float(np.mod(mid + i * T, 2 * np.pi)) for i in range(int(round(2 * np.pi / T)))))
    return ExitGuide(float(alpha), side, float(steepness), (float(lo[0]), float(hi[0])),
                     (float(glo[0]), float(ghi[0])), finals, image_unc + 0.5 * float(steepness))
