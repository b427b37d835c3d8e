"""The rounded regular polygons that benchmarks/bench_belt.py runs on the belt in Drake:
the boundary closes, each side meets its arcs tangentially, the arcs are inscribed in the
sharp polygon's corners, and the area is the closed form (the sharp polygon less, per
corner, the kite between the two tangents and the centre less the arc's sector)."""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

_BENCH = Path(__file__).parents[2] / "benchmarks" / "bench_belt.py"
_spec = importlib.util.spec_from_file_location("bench_belt", _BENCH)
assert _spec is not None and _spec.loader is not None
bench: Any = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(bench)

JOIN_MM = 1e-12  # endpoints that meet (mm)
UNIT = 1e-12  # unit-vector components that agree
AREA_REL = 1e-6  # a boundary sampled at 20,000 points per arc against the closed form


def _ends(seg: dict[str, Any]) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(start, end, unit tangent at start, unit tangent at end), counter-clockwise."""
    if seg["type"] == "line":
        a, b = np.array(seg["start"]), np.array(seg["end"])
        t = (b - a) / np.linalg.norm(b - a)
        return a, b, t, t
    c, r = np.array(seg["center"]), seg["radius"]
    a0, a1 = seg["start_deg"] * math.pi / 180, seg["end_deg"] * math.pi / 180
    assert a1 > a0  # counter-clockwise
    return (c + r * np.array([math.cos(a0), math.sin(a0)]), c + r * np.array([math.cos(a1), math.sin(a1)]),
            np.array([-math.sin(a0), math.cos(a0)]), np.array([-math.sin(a1), math.cos(a1)]))


def _points(seg: dict[str, Any]) -> np.ndarray:
    if seg["type"] == "line":
        return np.array([seg["start"]])
    a = np.linspace(seg["start_deg"], seg["end_deg"], 20_000, endpoint=False) * math.pi / 180
    return np.array(seg["center"]) + seg["radius"] * np.column_stack([np.cos(a), np.sin(a)])


@pytest.mark.parametrize(("n", "side", "r"), [(3, 30.0, 3.0), (4, 20.0, 5.0), (6, 15.0, 2.0)])
def test_rounded_regular_polygon_closes_tangentially(n: int, side: float, r: float) -> None:
    segs = bench._rounded_regular_polygon(n, side, r)["boundary"]
    assert [s["type"] for s in segs] == ["arc", "line"] * n
    for cur, nxt in zip(segs, segs[1:] + segs[:1]):
        _, end, _, t_end = _ends(cur)
        start, _, t_start, _ = _ends(nxt)
        assert np.abs(end - start).max() < JOIN_MM
        assert np.abs(t_end - t_start).max() < UNIT
    half = math.pi / n  # a corner's half exterior turn; the corner's tangent length is r·tan(π/n)
    for line in segs[1::2]:
        assert math.dist(line["start"], line["end"]) == pytest.approx(side - 2 * r * math.tan(half), rel=UNIT)
    for arc in segs[0::2]:
        assert arc["radius"] == r and arc["end_deg"] - arc["start_deg"] == pytest.approx(360 / n, rel=UNIT)
        apothem = side / (2 * math.tan(half))  # the sharp polygon's, about the origin
        normal = (arc["start_deg"] + arc["end_deg"]) / 2 * math.pi / 180  # the corner's direction
        for k in (-1, 1):  # each adjacent sharp side is r from the arc's centre
            u = (math.cos(normal + k * half), math.sin(normal + k * half))
            assert apothem - float(np.dot(arc["center"], u)) == pytest.approx(r, rel=UNIT)
    poly = np.vstack([_points(s) for s in segs])
    x, y = poly[:, 0], poly[:, 1]
    area = 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    sharp = n * side**2 / (4 * math.tan(half))
    corner = r * r * math.tan(half) - r * r * half  # kite of tangent length r·tan(π/n) less its sector
    assert area == pytest.approx(sharp - n * corner, rel=AREA_REL)
