"""Exact dead-zone edges (algrasp.planning.edges) checked against brute force: slopes from
finite differences of f itself at 200,000 orientations, not the closed forms under test."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from algrasp.geometry.functions import SupportPairFunction, analyse
from algrasp.geometry.part import load_part
from algrasp.geometry.tolerances import DEFAULT_TOLERANCES as TOL
from algrasp.planning.edges import crossings
from algrasp.planning.setvalued import EDGE_RAD, GRID_RAD, set_transfer
from algrasp.testing import shapes

H = 1e-7


def _slope(f: SupportPairFunction, theta: np.ndarray) -> np.ndarray:
    return (f.values(theta + H) - f.values(theta - H)) / (2 * H)


def _function(doc: dict, kind: str) -> SupportPairFunction:
    part = load_part(doc)
    return analyse(kind, part.hull, part.center_of_mass, part.size, TOL)  # type: ignore[arg-type]


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 10_000), n=st.integers(3, 12), kind=st.sampled_from(["diameter", "radius"]),
       mu=st.floats(0.0, 0.5))
def test_every_crossing_is_on_a_threshold(seed: int, n: int, kind: str, mu: float) -> None:
    f = _function(shapes.random_polygon(n, seed), kind)
    scale = float(np.max(f.values(np.linspace(0, np.pi, 64))))
    slopes = (0.05 * scale, 0.2 * scale)
    theta, grid = crossings(f, slopes, (mu, 0.1 * scale), TOL, GRID_RAD)
    assert len(grid) == 0  # polygons: every cell is closed-form
    g, v = np.abs(_slope(f, theta)), f.values(theta)
    off = np.min(np.abs(np.stack([g - slopes[0], g - slopes[1], g - (mu * v + 0.1 * scale)])), axis=0)
    assert np.all(off <= 1e-5 * scale)


def _brute_rest(f: SupportPairFunction, s_hi: float, sigma: float, mu: float, m: int = 200_000) -> tuple[np.ndarray, np.ndarray]:
    """Rest where |f′| ≤ μ·f + s_hi + σ on either side (one-sided differences: at a kink
    the central one would average the two slopes)."""
    theta = np.linspace(0.0, f.period, m, endpoint=False)
    v = f.values(theta)
    bound = mu * v + s_hi + sigma
    forward, backward = (f.values(theta + H) - v) / H, (v - f.values(theta - H)) / H
    return theta, (np.abs(forward) <= bound) | (np.abs(backward) <= bound)


def _in_zones(theta: np.ndarray, zones: tuple[tuple[float, float], ...], P: float, pad: float) -> np.ndarray:
    inside = np.zeros(len(theta), dtype=bool)
    for a, b in zones:
        inside |= np.mod(theta - a + pad, P) <= (b - a) + 2 * pad
    return inside


def test_rest_zones_are_the_brute_force_zones_to_the_guard() -> None:
    """Pie (arcs and lines), a rectangle, a random polygon and two Bezier parts (edges
    bracketed and bisected), squeeze and push: every
    brute-force rest orientation is in a zone, and every orientation more than the guard
    (EDGE_RAD) and two samples inside a zone rests by brute force: no grid rounding."""
    for doc in (shapes.pie(), shapes.rectangle(3.0, 1.0), shapes.random_polygon(7, 4), shapes.bezier_cam(),
                shapes.bezier_blob(12, 2)):
        for kind, mu in (("diameter", 0.2), ("radius", 0.0)):
            f = _function(doc, kind)
            scale = float(np.max(f.values(np.linspace(0, np.pi, 64))))
            s, sigma = 0.08 * scale, 0.01 * scale
            F = set_transfer(f, (s, s), sigma, 1e-9, 1e-9, mu, 0.0)
            theta, rest = _brute_rest(f, s, sigma, mu)
            step = f.period / len(theta)
            assert np.all(_in_zones(theta[rest], F.rest_zones, f.period, step))
            assert not np.any(~rest & _in_zones(theta, F.rest_zones, f.period, -(EDGE_RAD + 2 * step)))


def test_curve_crossings_are_placed_on_their_thresholds() -> None:
    """Bezier cam and blob: crossings bracketed on the curve grid and placed by regula
    falsi sit on a threshold to far below the edges' guard."""
    for doc in (shapes.bezier_cam(), shapes.bezier_blob(12, 2)):
        f = _function(doc, "diameter")
        scale = float(np.max(f.values(np.linspace(0, np.pi, 64))))
        slopes = (0.05 * scale, 0.2 * scale)
        theta, grid = crossings(f, slopes, (0.1, 0.1 * scale), TOL, GRID_RAD)
        assert len(grid) > 0 and len(theta) > 0
        g, v = np.abs(_slope(f, theta)), f.values(theta)
        off = np.min(np.abs(np.stack([g - slopes[0], g - slopes[1], g - (0.1 * v + 0.1 * scale)])), axis=0)
        # |f′| changes by at most ~f per radian of θ: an error of 1e-6·scale is ~1e-6 rad.
        assert np.all(off <= 1e-6 * scale)


def test_the_grid_kept_between_calls_gives_the_crossings_of_a_fresh_one() -> None:
    """The curve grid and f′ on it are kept per function (a limit search asks again with
    other thresholds): each call equals the same call on an empty cache."""
    from algrasp.planning import edges

    f = _function(shapes.bezier_blob(8, 3), "diameter")
    calls = [((0.05, 0.2), (0.1, 0.02), ()), ((0.3,), None, ()), ((), None, (float(f.values(np.array([0.3]))[0]),))]
    warm = [edges.crossings(f, s, j, TOL, edges.CURVE_GRID_RAD, levels=lv) for s, j, lv in calls]
    for (s, j, lv), (theta, grid) in zip(calls, warm):
        edges._grid.cache_clear()
        fresh_theta, fresh_grid = edges.crossings(f, s, j, TOL, edges.CURVE_GRID_RAD, levels=lv)
        assert np.array_equal(theta, fresh_theta) and np.array_equal(grid, fresh_grid) and len(theta) > 0
