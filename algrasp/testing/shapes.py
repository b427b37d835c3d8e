"""Generators of part documents: the paper's parts and random test/benchmark parts.

Each returns a plain part document (conventions §5), so everything downstream goes
through the same validation as a user's file.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from algrasp.geometry.angles import to_deg, to_rad

Doc = dict[str, Any]


def _pt(r: float, deg: float, c: tuple[float, float] = (0.0, 0.0)) -> list[float]:
    return [c[0] + r * math.cos(to_rad(deg)), c[1] + r * math.sin(to_rad(deg))]


def pie(radius: float = 5.0, half_angle_deg: float = 20.0, com: tuple[float, float] | None = None) -> Doc:
    """Circular sector with apex at the origin, symmetric about +y (the paper's pie)."""
    a, b = 90.0 - half_angle_deg, 90.0 + half_angle_deg
    doc: Doc = {"name": f"pie-{half_angle_deg:g}", "boundary": [
        {"type": "line", "start": [0.0, 0.0], "end": _pt(radius, a)},
        {"type": "arc", "center": [0.0, 0.0], "radius": radius, "start_deg": a, "end_deg": b},
        {"type": "line", "start": _pt(radius, b), "end": [0.0, 0.0]}]}
    if com is not None:
        doc["center_of_mass"] = list(com)
    return doc


def rectangle(width: float, height: float) -> Doc:
    return {"name": f"rect-{width:g}x{height:g}", "polygon": [[0, 0], [width, 0], [width, height], [0, height]]}


def regular_polygon(sides: int, radius: float = 1.0, phase_deg: float = 0.0) -> Doc:
    return {"name": f"regular-{sides}", "polygon": [_pt(radius, phase_deg + 360.0 * k / sides) for k in range(sides)]}


def disk_with_flats(radius: float = 1.0, z_deg: float = 10.0) -> Doc:
    """Fig. 11: a disk with two parallel flats whose chords subtend 2z at the centre."""
    z = z_deg
    return {"name": f"flats-{z_deg:g}", "boundary": [
        {"type": "arc", "center": [0, 0], "radius": radius, "start_deg": -90 + z, "end_deg": 90 - z},
        {"type": "line", "start": _pt(radius, 90 - z), "end": _pt(radius, 90 + z)},
        {"type": "arc", "center": [0, 0], "radius": radius, "start_deg": 90 + z, "end_deg": 270 - z},
        {"type": "line", "start": _pt(radius, 270 - z), "end": _pt(radius, 270 + z)}]}


def disk(radius: float = 1.0) -> Doc:
    return {"name": "disk", "boundary": [{"type": "arc", "center": [0, 0], "radius": radius,
                                          "start_deg": 0, "end_deg": 360}]}


def reuleaux(width: float = 1.0) -> Doc:
    """Reuleaux triangle: three arcs of radius ``width`` centred on the opposite vertices."""
    r = width / math.sqrt(3.0)
    v = [_pt(r, 90 + 120 * k) for k in range(3)]
    segs = []
    for k in range(3):
        c = v[(k + 2) % 3]  # arc from v[k] to v[k+1], centred at the third vertex
        a0 = to_deg(math.atan2(v[k][1] - c[1], v[k][0] - c[0]))
        segs.append({"type": "arc", "center": c, "radius": width, "start_deg": a0, "end_deg": a0 + 60.0})
    return {"name": "reuleaux", "boundary": segs}


def random_polygon(n: int, seed: int = 0) -> Doc:
    """A simple polygon with n vertices, star-shaped about the origin.

    Angles are jittered around a uniform grid so every angular gap is below π (which
    keeps the polygon simple); radii are uniform in [0.5, 1].
    """
    rng = np.random.default_rng(seed)
    ang = 2 * np.pi * (np.arange(n) + rng.uniform(0.0, 0.8, n)) / n
    rad = rng.uniform(0.5, 1.0, n)
    return {"name": f"random-{n}-{seed}", "polygon": np.column_stack([rad * np.cos(ang), rad * np.sin(ang)]).tolist()}


def bezier_blob(n: int, seed: int = 0, wobble: float = 0.25) -> Doc:
    """A smooth closed star-shaped curve of n cubic Bezier segments (C¹ joints)."""
    rng = np.random.default_rng(seed)
    ang = 2 * np.pi * (np.arange(n) + rng.uniform(-0.3, 0.3, n)) / n
    rad = 1.0 + wobble * rng.uniform(-1.0, 1.0, n)
    p = np.column_stack([rad * np.cos(ang), rad * np.sin(ang)])
    tangent = (np.roll(p, -1, axis=0) - np.roll(p, 1, axis=0)) / 6.0  # Catmull-Rom
    segs = []
    for i in range(n):
        j = (i + 1) % n
        segs.append({"type": "bezier", "points": [p[i].tolist(), (p[i] + tangent[i]).tolist(),
                                                  (p[j] - tangent[j]).tolist(), p[j].tolist()]})
    return {"name": f"bezier-blob-{n}-{seed}", "boundary": segs}


def bezier_cam(scale: float = 2.0) -> Doc:
    """A cam of a line and two Bezier arcs (cubic and quintic), about 13 × 9 mm at scale 2."""
    def sc(pts: list[list[float]]) -> list[list[float]]:
        return [[scale * x, scale * y] for x, y in pts]

    return {"name": "bezier-cam", "boundary": [
        {"type": "line", "start": sc([[0, 0]])[0], "end": sc([[4, 0]])[0]},
        {"type": "bezier", "points": sc([[4, 0], [6.5, 1.0], [5.0, 4.0], [2.0, 4.2]])},
        {"type": "bezier", "points": sc([[2.0, 4.2], [0.5, 4.3], [-0.8, 2.5], [-0.5, 1.5], [-0.3, 0.6], [0, 0]])}]}
