"""Part quantities for the simulation, in metres (pure: no pydrake)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from algrasp.geometry.curves import FloatArray
from algrasp.geometry.part import Part
from algrasp.geometry.tolerances import ROUNDING, TINY
from algrasp.geometry.units import meters_per_unit
from algrasp.planning.deadband import mean_radius
from algrasp.sim.config import MIN_THICKNESS_M, SimConfig


@dataclass(frozen=True)
class Geometry:
    """Part quantities in metres, relative to the centre of mass."""

    outline_m: FloatArray  # (N, 2) tessellated hull, counter-clockwise
    reach_m: float  # largest distance from the centre of mass to the hull
    mean_radius_m: float  # r̄: mean distance of the region's points from the centre of mass
    chord_error_m: float  # tessellation bound ρ_max Δψ² / 8
    polar_per_area_m2: float  # ∬|r|² dA / A


def jaw_size_m(geom: Geometry) -> tuple[float, float]:
    """Length and thickness (m) of the jaws as drawn in run records (the simulator's
    jaws are planes): long enough to cover the part at any offset."""
    return 5.0 * geom.reach_m, max(0.3 * geom.reach_m, MIN_THICKNESS_M)


def extent_midpoint(outline_m: FloatArray, x: float, y: float, theta: float, n: FloatArray) -> float:
    """Midpoint of the part's extent along direction n when its centre of mass is at
    (x, y) and its orientation is θ (outline relative to the centre of mass, metres)."""
    c, s = np.cos(theta), np.sin(theta)
    proj = (outline_m @ np.array([[c, s], [-s, c]]) + [x, y]) @ n
    return float((proj.max() + proj.min()) / 2)


def part_geometry(part: Part, cfg: SimConfig) -> Geometry:
    s = meters_per_unit(part.units)
    com = np.asarray(part.center_of_mass)
    # Chords as fine as the turn allows, but ≥ 0.5% of the part and ≥ 50 µm: Drake rejects
    # smaller collision faces as degenerate.
    outline, chord_error = collision_outline(part, cfg.tessellation_turn_rad, max(0.005 * part.size, 50e-6 / s))
    rel = (outline - com) * s
    reach = float(np.max(np.hypot(*rel.T)))
    return Geometry(rel, reach, mean_radius(part) * s, chord_error * s, part.polar_moment / part.area * s * s)


def collision_outline(part: Part, turn_rad: float, min_chord: float) -> tuple[FloatArray, float]:
    """Tessellated hull (N, 2) in the part's unit, and its largest chord error.

    Every corner and every end of a curve feature is kept exactly; a curve feature is
    split into chords that turn by at most ``turn_rad`` but are no shorter than
    ``min_chord`` (tiny chords make degenerate faces in Drake's collision hull). The chord
    error of a chord of length c on a curve of radius ρ is ρ(1 − cos(c / 2ρ)) ≈ c²/8ρ;
    the bound reported is the largest over all chords, measured on the exact curves.
    """
    pts: list[FloatArray] = []
    corners: list[FloatArray] = []
    worst = 0.0
    for i, f in enumerate(part.hull.features):
        if f.kind == "point":
            pts.append(np.asarray(f.center)[None, :])
            corners.append(np.array([True]))
            continue
        dense = part.hull.feature_points(i, np.linspace(f.psi0, f.psi1, max(2, int(np.ceil((f.psi1 - f.psi0) / 0.002)) + 1)))
        keep = _chord_ends(dense, f.psi1 - f.psi0, turn_rad, min_chord)
        for a, b in zip(keep[:-1], keep[1:]):
            seg = dense[a:b + 1]
            d = seg[-1] - seg[0]
            n = np.array([-d[1], d[0]]) / max(float(np.hypot(*d)), TINY)
            worst = max(worst, float(np.max(np.abs((seg - seg[0]) @ n))))
        pts.append(dense[keep])
        corners.append(np.zeros(len(keep), dtype=bool))
    return _space(np.concatenate(pts), np.concatenate(corners), min_chord), worst


CHORD_WINDOW = 64
"""Points beyond the first admissible one whose chords are measured in one numpy pass."""


def _chord_ends(dense: FloatArray, span: float, turn_rad: float, min_chord: float) -> list[int]:
    """Indices of ``dense`` (M, 2) kept as chord ends: from each kept point, the first
    later point at least ``turn_rad`` of the feature's ``span`` (rad) and ``min_chord``
    away; the first and last points always. The same indices as testing every point in
    turn (the same float operations), with the chords of a window measured at once:
    O(M) numpy work in passes of ``CHORD_WINDOW``."""
    last = len(dense) - 1
    first = 1  # the fewest points a chord spans to turn by turn_rad (the same test as per point)
    while first < last and span * first / last < turn_rad:
        first += 1
    keep = [0]
    k = 0
    while True:
        i = k + first
        found = None
        while i < last and found is None:
            j = min(i + CHORD_WINDOW, last)
            d = dense[i:j] - dense[k]
            hits = np.flatnonzero(np.hypot(d[:, 0], d[:, 1]) >= min_chord)
            found = i + int(hits[0]) if len(hits) else None
            i = j
        if found is None:
            break
        keep.append(found)
        k = found
    keep.append(last)
    return keep


def _space(pts: FloatArray, corner: np.ndarray, gap: float) -> FloatArray:
    """Drop points closer than ``gap`` to a kept neighbour, never a corner (curve ends at
    smooth junctions may go: their neighbours lie on the same smooth curve)."""
    kept: list[int] = []
    for i in range(len(pts)):
        if kept and float(np.hypot(*(pts[i] - pts[kept[-1]]))) < gap:
            if not corner[i]:
                continue
            if not corner[kept[-1]]:
                kept.pop()
            elif float(np.hypot(*(pts[i] - pts[kept[-1]]))) < ROUNDING:
                continue
        kept.append(i)
    while len(kept) > 3 and float(np.hypot(*(pts[kept[-1]] - pts[kept[0]]))) < gap and not corner[kept[-1]]:
        kept.pop()
    return pts[kept]
