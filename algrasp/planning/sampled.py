"""Sampled views of an analysis, for drawing it: the outline, holes and hull as polylines
and d, r, Γ, p, Γ∘p on a regular θ grid (``POST /v1/analyses?samples=N``, the workbench).

The exact results stay in the analysis document (extrema, steps, ramps); these samples
only draw them. Angles in degrees, lengths in the part's unit (conventions §1).
"""

from __future__ import annotations

import numpy as np

from algrasp.geometry.angles import TWO_PI, to_deg, to_rad
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.segments import loop_polyline
from algrasp.planning.analysis import Analysis

MAX_TURN_DEG = 3.0
"""Largest tangent turn between two outline points: smooth at any drawing size."""

SIGNIFICANT_DIGITS = 7
"""Digits kept in sampled values: sub-pixel at any scale, a third of the bytes of repr."""

MAX_SAMPLES = 3600


def _round(values: FloatArray) -> list[float]:
    return [float(f"{v:.{SIGNIFICANT_DIGITS}g}") for v in np.asarray(values, dtype=float).ravel()]


def _points(pts: FloatArray) -> list[list[float]]:
    return [_round(p) for p in np.asarray(pts, dtype=float)]


def geometry(analysis: Analysis) -> dict[str, object]:
    """Closed polylines (first point not repeated) of the boundary, each hole and the
    convex hull, in the part frame, and the centre of mass. O(segments + hull features)."""
    part = analysis.part
    outline, _ = loop_polyline(part.boundary, to_rad(MAX_TURN_DEG))
    holes = [loop_polyline(h, to_rad(MAX_TURN_DEG))[0] for h in part.holes]
    hull = part.hull.outline(to_rad(MAX_TURN_DEG))[:-1]
    return {"outline": _points(outline), "holes": [_points(h) for h in holes], "hull": _points(hull),
            "center_of_mass": _round(np.asarray(part.center_of_mass))}


def curves(analysis: Analysis, n: int) -> dict[str, list[float]]:
    """d, r and the exact transfer functions at ``n`` orientations θ = 360°·k/n.

    Transfer values are lifted (continuous in θ across the period), in degrees.
    O(n log m) for m pieces.
    """
    theta = np.linspace(0.0, TWO_PI, n, endpoint=False)
    return {"theta_deg": _round(to_deg(theta)), "diameter": _round(analysis.diameter.values(theta)),
            "radius": _round(analysis.radius.values(theta)),
            "squeeze_deg": _round(to_deg(analysis.squeeze.apply(theta))),
            "push_deg": _round(to_deg(analysis.push.apply(theta))),
            "push_grasp_deg": _round(to_deg(analysis.push_grasp.apply(theta)))}


def sampled(analysis: Analysis, n: int) -> dict[str, object]:
    """``{"geometry": ..., "curves": ...}`` added to the analysis document.

    >>> from algrasp import analyse
    >>> doc = {"polygon": [[0, 0], [4, 0], [4, 2], [0, 2]]}
    >>> out = sampled(analyse(doc), 4)
    >>> out["curves"]["theta_deg"], out["curves"]["diameter"]
    ([0.0, 90.0, 180.0, 270.0], [2.0, 4.0, 2.0, 4.0])
    >>> len(out["geometry"]["hull"])
    4
    """
    return {"geometry": geometry(analysis), "curves": curves(analysis, n)}
