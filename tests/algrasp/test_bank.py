"""Batched evaluation (algrasp.geometry.bank, algrasp.geometry.moments, loop_polyline) against independent
per-point evaluation and closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest

from algrasp.geometry.bank import POINT_ROWS, FeatureTable, coefficient_stack
from algrasp.geometry.curves import Piece, horner_rows
from algrasp.geometry.gauss import HullFeature
from algrasp.geometry.hull import unit
from algrasp.geometry.part import load_part
from algrasp.geometry.segments import loop_polyline
from algrasp.testing import shapes


def _de_casteljau_point(points: np.ndarray, weights: np.ndarray, t: float | np.ndarray) -> np.ndarray:
    """Rational Bezier point(s) by de Casteljau on homogeneous points (independent of the
    power-basis conversion the bank uses); t scalar → (2,), t (m,) → (m, 2)."""
    tt = np.asarray(t, dtype=float)[..., None, None]
    hom = np.column_stack([points * weights[:, None], weights]) + 0.0 * tt
    while hom.shape[-2] > 1:
        hom = (1 - tt) * hom[..., :-1, :] + tt * hom[..., 1:, :]
    return hom[..., 0, :2] / hom[..., 0, 2:]


def test_stacked_pieces_of_mixed_degree_evaluate_like_de_casteljau() -> None:
    rng = np.random.default_rng(3)
    pieces = [Piece(rng.normal(size=(k + 1, 2)), rng.uniform(0.5, 2.0, k + 1) if rational else np.ones(k + 1))
              for k, rational in [(1, False), (2, True), (3, False), (5, True), (3, True)]]
    coef = coefficient_stack(pieces)
    t = rng.uniform(0, 1, 40)
    idx = rng.integers(0, len(pieces), 40)
    x, y, w = horner_rows(coef[idx][:, POINT_ROWS], t)
    for i, k in enumerate(idx):
        p = pieces[k]
        expected = _de_casteljau_point(p.points, p.weights, t[i])
        assert (x[i] / w[i], y[i] / w[i]) == pytest.approx(tuple(expected), abs=1e-12)


def test_vectorised_support_points_are_the_maximisers() -> None:
    """h(ψ) from the batched Newton equals the maximum of ⟨p, u⟩ over a dense exact
    sampling of the boundary (to the sampling's resolution) and each point is on the part."""
    part = load_part(shapes.bezier_cam())
    psi = np.linspace(0.0, 2 * np.pi, 257)
    pts = part.hull.support_points(psi)
    u = np.linspace(0.0, 1.0, 20001)
    dense = np.concatenate([_de_casteljau_point(s.points, s.weights, u) if hasattr(s, "points")
                            else np.array([s.start, s.end]) for s in part.boundary])
    brute = np.max(dense @ unit(psi).T, axis=0)
    h = np.sum(pts * unit(psi), axis=1)
    assert np.all(h >= brute - 1e-12 * part.size)
    assert np.max(h - brute) < 1e-7 * part.size
    scalar = np.array([part.hull.support(float(p)) for p in psi])
    assert h == pytest.approx(scalar, abs=1e-12 * part.size)


def test_rational_quarter_disk_moments_are_exact() -> None:
    """A quarter disk bounded by a rational quadratic arc: area πr²/4, centroid 4r/3π,
    ∬x² = πr⁴/16 (closed forms)."""
    r = 2.0
    c = math.cos(math.pi / 4)
    doc = {"boundary": [
        {"type": "line", "start": [0, 0], "end": [r, 0]},
        {"type": "bezier", "points": [[r, 0], [r, r], [0, r]], "weights": [1, c, 1]},
        {"type": "line", "start": [0, r], "end": [0, 0]},
    ]}
    part = load_part(doc)
    assert part.area == pytest.approx(math.pi * r * r / 4, rel=1e-12)
    assert part.center_of_mass == pytest.approx((4 * r / (3 * math.pi),) * 2, rel=1e-12)
    com = np.asarray(part.center_of_mass)
    second = 2 * math.pi * r**4 / 16  # ∬x² + ∬y² about the origin
    assert part.polar_moment == pytest.approx(second - part.area * float(com @ com), rel=1e-12)


def test_loop_polyline_lies_on_the_curves() -> None:
    part = load_part(shapes.bezier_blob(7, 4))
    pts, parts = loop_polyline(part.boundary, 0.05)
    assert len(parts) == 7 and len(pts) == sum(len(p) for p in parts)
    for seg, chunk in zip(part.boundary, parts):
        u = np.linspace(0.0, 1.0, len(chunk) + 1)[:-1]
        expected = np.array([_de_casteljau_point(seg.points, seg.weights, t) for t in u])
        assert chunk == pytest.approx(expected, abs=1e-12)


def _vertices_only_arrays(t: FeatureTable) -> bool:
    """The polygon test in arrays, as first written."""
    return bool(not len(t.s0) and not t.radii.any() and not np.signbit(t.radii).any()
                and not np.signbit(t.centers[t.centers == 0.0]).any())


@pytest.mark.parametrize("radius", [0.0, -0.0, 1e-300, 0.5])
@pytest.mark.parametrize("centre", [(1.0, 2.0), (0.0, 0.0), (-0.0, 1.0), (1.0, -0.0), (-0.0, -0.0)])
def test_vertices_only_in_floats_is_the_array_test(radius: float, centre: tuple[float, float]) -> None:
    """Tables of points and arcs with ±0.0 radii and centre coordinates, and the hulls of
    polygons, arcs and curves: the plain-float test answers as the array one."""
    base = FeatureTable.build([HullFeature("point", 0.0, 2.0, (1.0, 1.0)), HullFeature("point", 2.0, 4.0, (-1.0, 0.5))])
    odd = HullFeature("circle" if radius else "point", 4.0, 2.0 * math.pi, centre, radius)
    t = FeatureTable.build([HullFeature("point", 0.0, 2.0, (1.0, 1.0)), HullFeature("point", 2.0, 4.0, (-1.0, 0.5)), odd])
    assert t.vertices_only == _vertices_only_arrays(t) and base.vertices_only is True
    for doc in (shapes.rectangle(3.0, 1.0), shapes.random_polygon(7, 3), shapes.pie(5.0, 20.0), shapes.bezier_cam()):
        table = load_part(doc).hull.table
        assert table.vertices_only == _vertices_only_arrays(table)
