"""Push distances against an independent quadrature of the push law on raw vertices."""

from __future__ import annotations

import math

import numpy as np
import pytest

from algrasp.geometry.part import load_part
from algrasp.planning.analysis import analyse_part
from algrasp.planning.deadband import mean_radius
from algrasp.testing import shapes
from optimisation.push import push_distances, push_model

TOL, BAND = math.radians(0.5), math.radians(2.0)


def _reference(vertices: np.ndarray, com: np.ndarray, c: float) -> float:
    """Worst distance over all starts more than BAND from a local maximum of r: the
    distance from θ₀ to within TOL of the fixed point is ∫ (c² + q²)/|q| dθ (the push law
    dθ/ds = q/(c² + q²) inverted), q = x of the lowest vertex by brute force."""
    n = 720_000
    th = np.linspace(0.0, 4 * math.pi, n, endpoint=False)
    rel = vertices - com
    ys = np.outer(np.sin(th), rel[:, 0]) + np.outer(np.cos(th), rel[:, 1])
    xs = np.outer(np.cos(th), rel[:, 0]) - np.outer(np.sin(th), rel[:, 1])
    low = np.argmin(ys, axis=1)
    q = xs[np.arange(n), low]
    r = -ys[np.arange(n), low]
    cost = np.concatenate([[0.0], np.cumsum((c * c + q[:-1] ** 2) / np.maximum(np.abs(q[:-1]), 1e-12) * np.diff(th))])
    d = th[1] - th[0]
    maxima = [i for i in range(1, n - 1) if r[i] >= r[i - 1] and r[i] > r[i + 1]]
    minima = [i for i in range(1, n - 1) if r[i] <= r[i - 1] and r[i] < r[i + 1]]
    worst = 0.0
    for i in minima:
        lo = max(m for m in maxima if m < i) if any(m < i for m in maxima) else None
        hi = min(m for m in maxima if m > i) if any(m > i for m in maxima) else None
        if lo is None or hi is None:
            continue
        a, b = lo + int(BAND / d), hi - int(BAND / d)
        left = cost[i - int(TOL / d)] - cost[a]
        right = cost[b] - cost[i + int(TOL / d)]
        worst = max(worst, left, right)
    return worst


@pytest.mark.parametrize("doc", [shapes.rectangle(10.0, 4.0), shapes.regular_polygon(3, 5.0),
                                 {"polygon": [[0, 0], [9, 0], [7, 5], [1, 3]]}])
def test_first_step_push_distance_matches_quadrature(doc: dict) -> None:
    part = load_part(doc)
    analysis = analyse_part(part)
    c = mean_radius(part)
    model = push_model(analysis, c)
    start = analysis.push.pieces[0].start
    (res,) = push_distances(model, analysis, [(start, start + 2 * math.pi)], TOL, BAND)
    verts = np.array([s.start for s in part.boundary])
    want = _reference(verts, np.asarray(part.center_of_mass), c)
    assert res.distance == pytest.approx(want, rel=5e-3)
    assert res.distance <= res.bound
    assert res.bound == pytest.approx(_reference(verts, np.asarray(part.center_of_mass), model.cover_radius), rel=5e-3)
