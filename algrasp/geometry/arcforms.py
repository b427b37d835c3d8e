"""Part documents written the ways CAD tools write them: an arc as an ``arc``, an
``ellipse_arc`` with rx = ry, rational quadratic Beziers (NURBS, STEP), degree-elevated
rational cubics, cubic Bezier approximations (SVG, PDF) and polygons (``"64gon"``: mesh
projections, polyline exports). For tests and benchmarks of conventions §7: the same
part in every form must give the same (exact forms) or a safe (approximations) plan.

An outline is a list of ("line", start, end) and ("arc", (cx, cy), R, a0_deg, a1_deg).

>>> doc = document(fig11_outline(), "cubic")
>>> [s["type"] for s in doc["boundary"]][:3]
['line', 'bezier', 'bezier']
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from algrasp.geometry.angles import to_rad
from algrasp.geometry.tolerances import PARAM_END

Outline = list[tuple[Any, ...]]


def _pieces(a0: float, a1: float, max_deg: float = 90.0) -> list[tuple[float, float]]:
    n = max(1, math.ceil(abs(a1 - a0) / max_deg - PARAM_END))
    return [(a0 + (a1 - a0) * i / n, a0 + (a1 - a0) * (i + 1) / n) for i in range(n)]


def _pt(c: tuple[float, float], R: float, a_deg: float) -> list[float]:
    a = to_rad(a_deg)
    return [c[0] + R * math.cos(a), c[1] + R * math.sin(a)]


def _rational(c: tuple[float, float], R: float, a0: float, a1: float) -> tuple[np.ndarray, np.ndarray]:
    h = to_rad(a1 - a0) / 2
    m = to_rad(a1 + a0) / 2
    mid = [c[0] + R * math.cos(m) / math.cos(h), c[1] + R * math.sin(m) / math.cos(h)]
    return np.array([_pt(c, R, a0), mid, _pt(c, R, a1)]), np.array([1.0, math.cos(h), 1.0])


def _elevate(P: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    H = np.column_stack([P * w[:, None], w])
    E = np.array([H[0], (H[0] + 2 * H[1]) / 3, (2 * H[1] + H[2]) / 3, H[2]])
    return E[:, :2] / E[:, 2:], E[:, 2]


def arc_segments(form: str, c: tuple[float, float], R: float, a0: float, a1: float) -> list[dict[str, Any]]:
    """One arc (degrees, a0 → a1) in the given form."""
    if form == "arc":
        return [{"type": "arc", "center": list(c), "radius": R, "start_deg": a0, "end_deg": a1}]
    if form == "ellipse":
        return [{"type": "ellipse_arc", "center": list(c), "rx": R, "ry": R, "rotation_deg": 17.0,
                 "start_deg": a0 - 17.0, "end_deg": a1 - 17.0}]
    out: list[dict[str, Any]] = []
    if form.endswith("gon"):
        n = int(form[:-3])
        step = 360.0 / n
        k0, k1 = sorted((a0 / step, a1 / step))
        inner = [k * step for k in range(math.floor(k0) + 1, math.ceil(k1))]
        angles = [a0, *(inner if a1 > a0 else inner[::-1]), a1]
        return [{"type": "line", "start": _pt(c, R, x), "end": _pt(c, R, y)} for x, y in zip(angles[:-1], angles[1:])]
    for x, y in _pieces(a0, a1):
        if form == "cubic":
            k = 4.0 / 3.0 * math.tan(to_rad(y - x) / 4)
            p0, p3 = np.array(_pt(c, R, x)), np.array(_pt(c, R, y))
            t0 = np.array([-math.sin(to_rad(x)), math.cos(to_rad(x))])
            t3 = np.array([-math.sin(to_rad(y)), math.cos(to_rad(y))])
            pts = [p0, p0 + k * R * t0, p3 - k * R * t3, p3]
            out.append({"type": "bezier", "points": [list(map(float, p)) for p in pts]})
        else:
            P, w = _rational(c, R, x, y)
            if form == "rational_cubic":
                P, w = _elevate(P, w)
            out.append({"type": "bezier", "points": P.tolist(), "weights": w.tolist()})
    return out


FORMS = ("arc", "ellipse", "rational", "rational_cubic", "cubic", "64gon", "360gon")


def document(outline: Outline, form: str, **extra: Any) -> dict[str, Any]:
    """A part document of ``outline`` with every arc written in ``form`` (see FORMS)."""
    boundary: list[dict[str, Any]] = []
    for item in outline:
        if item[0] == "line":
            boundary.append({"type": "line", "start": list(item[1]), "end": list(item[2])})
        else:
            boundary.extend(arc_segments(form, *item[1:]))
    return {"name": f"part-{form}", "boundary": boundary, **extra}


def fig11_outline(R: float = 10.0, z_deg: float = 11.0) -> Outline:
    """The paper's Fig. 11 part: a disk with two parallel flats whose chords subtend 2z."""
    s, c = R * math.sin(to_rad(z_deg)), R * math.cos(to_rad(z_deg))
    return [("line", (s, c), (-s, c)), ("arc", (0.0, 0.0), R, 90 + z_deg, 270 - z_deg),
            ("line", (-s, -c), (s, -c)), ("arc", (0.0, 0.0), R, -90 + z_deg, 90 - z_deg)]


def pie_outline(R: float = 5.0, half_deg: float = 20.0) -> Outline:
    """The paper's pie: a circular sector with apex at the origin, symmetric about +y."""
    h = to_rad(half_deg)
    a, b = (R * math.sin(h), R * math.cos(h)), (-R * math.sin(h), R * math.cos(h))
    return [("line", (0.0, 0.0), a), ("arc", (0.0, 0.0), R, 90 - half_deg, 90 + half_deg), ("line", b, (0.0, 0.0))]
