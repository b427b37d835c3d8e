"""Exact operations on one drawing segment (a part-document segment dict): its parameter
range, the point at a parameter, the nearest parameter to a point, and the sub-segment
between two parameters — so that entities split where another entity ends on them
(`algrasp.io.cad.arrange`) stay lines, arcs, ellipse arcs and rational Beziers.

Parameters: a line and a Bezier run over [0, 1]; an arc or ellipse arc over
[start_deg, end_deg] (degrees, as the document writes them; either order).

>>> s = {"type": "arc", "center": [0.0, 0.0], "radius": 2.0, "start_deg": 0.0, "end_deg": 180.0}
>>> t, d = project(s, [0.0, 2.5])
>>> round(t, 9), round(d, 9)
(90.0, 0.5)
>>> sub(s, 0.0, t)["end_deg"]
90.0
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from algrasp.geometry.angles import to_deg, to_rad
from algrasp.geometry.tolerances import PARAM_END
from algrasp.io.cad.chain import Segment, point_at, samples

PROJECT_SAMPLES = 64
"""Samples along a curve (Bezier, ellipse arc) that seed the nearest-point search."""
PROJECT_ROUNDS = 6
"""Rounds refining the nearest parameter: each resamples the bracket around the nearest
sample 33 times, keeping 1/16 of it (6 rounds: ~6e-8 of a sample interval)."""


def t_range(s: Segment) -> tuple[float, float]:
    """The parameter at the start and at the end of the segment."""
    if s["type"] in ("line", "bezier"):
        return 0.0, 1.0
    return float(s["start_deg"]), float(s["end_deg"])


def at(s: Segment, t: float) -> np.ndarray:
    """The point of the segment at parameter t, shape (2,)."""
    kind = s["type"]
    if kind == "line":
        a, b = np.asarray(s["start"], float), np.asarray(s["end"], float)
        return a + t * (b - a)
    if kind == "bezier":
        return _bezier_point(s, t)
    return point_at({**s, "start_deg": t}, False)


def _homogeneous(s: Segment) -> np.ndarray:
    P = np.asarray(s["points"], float)
    w = np.asarray(s.get("weights", np.ones(len(P))), float)
    return np.column_stack([P * w[:, None], w])


def _bezier_point(s: Segment, t: float) -> np.ndarray:
    H = _homogeneous(s)
    while len(H) > 1:  # de Casteljau in homogeneous coordinates: exact for rational curves
        H = (1 - t) * H[:-1] + t * H[1:]
    return np.asarray(H[0, :2] / H[0, 2])


def _split_bezier(H: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray]:
    left, right = [H[0]], [H[-1]]
    while len(H) > 1:
        H = (1 - t) * H[:-1] + t * H[1:]
        left.append(H[0])
        right.append(H[-1])
    return np.array(left), np.array(right[::-1])


def _from_homogeneous(s: Segment, H: np.ndarray) -> Segment:
    out: Segment = {**s, "points": (H[:, :2] / H[:, 2:3]).tolist()}
    if "weights" in s:
        w = H[:, 2] / H[0, 2]  # weights are defined up to scale: keep the first at 1
        out["weights"] = w.tolist()
    return out


def sub(s: Segment, t0: float, t1: float) -> Segment:
    """The part of the segment from parameter t0 to t1 (t0 may exceed t1: then reversed
    relative to the segment), exact. O(degree²) for a Bezier."""
    kind = s["type"]
    if kind == "line":
        return {**s, "start": at(s, t0).tolist(), "end": at(s, t1).tolist()}
    if kind in ("arc", "ellipse_arc"):
        return {**s, "start_deg": float(t0), "end_deg": float(t1)}
    lo, hi = sorted((t0, t1))
    H = _homogeneous(s)
    if hi < 1.0:
        H = _split_bezier(H, hi)[0]
    if lo > 0.0:
        H = _split_bezier(H, lo / hi)[1]
    piece = _from_homogeneous(s, H)
    if t0 > t1:
        piece["points"] = piece["points"][::-1]
        if "weights" in piece:
            piece["weights"] = piece["weights"][::-1]
    return piece


def project(s: Segment, p: Any) -> tuple[float, float]:
    """The parameter of the point of the segment nearest to p, and the distance. Exact for
    lines and circular arcs; sampled then refined (PROJECT_SAMPLES, PROJECT_ROUNDS) for
    ellipse arcs and Beziers, whose distance to a point can have several minima."""
    q = np.asarray(p, float)
    kind = s["type"]
    if kind == "line":
        a, b = np.asarray(s["start"], float), np.asarray(s["end"], float)
        v = b - a
        t = float(np.clip(np.dot(q - a, v) / max(float(np.dot(v, v)), np.finfo(float).tiny), 0.0, 1.0))
        return t, float(np.linalg.norm(a + t * v - q))
    if kind == "arc":
        return _project_arc(s, q)
    return _project_sampled(s, q)


def _project_arc(s: Segment, q: np.ndarray) -> tuple[float, float]:
    c = np.asarray(s["center"], float)
    a0, a1 = t_range(s)
    ang = to_deg(math.atan2(q[1] - c[1], q[0] - c[0]))
    lo = min(a0, a1)
    ang = lo + (ang - lo) % 360.0  # the angle's copy at or after the sweep's low end
    candidates = [a0, a1] + ([ang] if ang <= max(a0, a1) else [])
    best = min(candidates, key=lambda t: float(np.linalg.norm(at(s, t) - q)))
    return float(best), float(np.linalg.norm(at(s, best) - q))


def _bezier_points(s: Segment, ts: np.ndarray) -> np.ndarray:
    """The points at parameters ``ts`` (shape (K,)) at once, shape (K, 2): de Casteljau in
    homogeneous coordinates over all parameters together."""
    H = np.broadcast_to(_homogeneous(s), (len(ts), *_homogeneous(s).shape)).copy()
    t = ts[:, None, None]
    while H.shape[1] > 1:
        H = (1 - t) * H[:, :-1] + t * H[:, 1:]
    return np.asarray(H[:, 0, :2] / H[:, 0, 2:3])


def _project_sampled(s: Segment, q: np.ndarray) -> tuple[float, float]:
    t0, t1 = t_range(s)
    ts = np.linspace(t0, t1, PROJECT_SAMPLES + 1)
    k, lo, hi = _nearest(s, q, ts)
    for _ in range(PROJECT_ROUNDS):  # resample around the nearest sample: 16× narrower each round
        k, lo, hi = _nearest(s, q, np.linspace(lo, hi, 33))
    t = float((lo + hi) / 2)
    return t, float(np.linalg.norm(at(s, t) - q))


def _nearest(s: Segment, q: np.ndarray, ts: np.ndarray) -> tuple[int, float, float]:
    """The sample of ``ts`` nearest to q and the parameters of its neighbours."""
    pts = _bezier_points(s, ts) if s["type"] == "bezier" else np.array([at(s, t) for t in ts])
    k = int(np.argmin(np.linalg.norm(pts - q, axis=1)))
    return k, float(ts[max(k - 1, 0)]), float(ts[min(k + 1, len(ts) - 1)])


def length(s: Segment) -> float:
    """Arc length: exact for lines and arcs; a chord sum of the sampled curve otherwise."""
    if s["type"] == "line":
        return float(np.linalg.norm(np.subtract(s["end"], s["start"])))
    if s["type"] == "arc":
        return float(s["radius"]) * to_rad(abs(s["end_deg"] - s["start_deg"]))
    pts = samples(s, PROJECT_SAMPLES)
    return float(np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=1)))


def midpoint(s: Segment) -> np.ndarray:
    """The point at the middle parameter (tells two half-circles on the same ends apart)."""
    t0, t1 = t_range(s)
    return at(s, (t0 + t1) / 2)


LEAVING_STEP = 1e-3
"""Share of a curve's parameter range used to find the direction it leaves a vertex in."""


def leaving_angle(s: Segment, from_end: bool) -> float:
    """The direction (radians) in which the segment leaves its start (or, ``from_end``, its
    end, walking backwards): towards a point a small step along, so two curves leaving a
    vertex on the same tangent (a circle touching a line) are still ordered by curvature."""
    t0, t1 = t_range(s)
    if from_end:
        t0, t1 = t1, t0
    a = at(s, t0)
    b = at(s, t1) if s["type"] == "line" else at(s, t0 + LEAVING_STEP * (t1 - t0))
    return math.atan2(float(b[1] - a[1]), float(b[0] - a[0]))


def is_closed_curve(s: Segment) -> bool:
    """A full circle or ellipse (its ends meet by construction)."""
    return s["type"] in ("arc", "ellipse_arc") and abs(s["end_deg"] - s["start_deg"]) >= 360.0 - PARAM_END
