"""Area, centre of mass and hull perimeter against closed forms; Cauchy's formula."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from algrasp.geometry.part import load_part
from algrasp.planning.analysis import analyse_part
from algrasp.testing import shapes


def test_pie_area_centroid_perimeter() -> None:
    r, half = 5.0, math.radians(20)
    part = load_part(shapes.pie(r, 20))
    assert part.area == pytest.approx(r * r * half, rel=1e-9)
    assert part.center_of_mass[0] == pytest.approx(0.0, abs=1e-9)
    assert part.center_of_mass[1] == pytest.approx(2 * r * math.sin(half) / (3 * half), rel=1e-9)
    assert part.hull.perimeter == pytest.approx(2 * r + r * 2 * half, rel=1e-9)


def test_ellipse_area_and_perimeter() -> None:
    rx, ry = 3.0, 1.0
    doc = {"boundary": [{"type": "ellipse_arc", "center": [1, 2], "rx": rx, "ry": ry, "rotation_deg": 30,
                         "start_deg": 0, "end_deg": 360}]}
    part = load_part(doc)
    assert part.area == pytest.approx(math.pi * rx * ry, rel=1e-12)
    assert part.center_of_mass == pytest.approx((1, 2), abs=1e-12)
    # Complete elliptic integral: perimeter = 4 a E(e²).
    from scipy.special import ellipe
    assert part.hull.perimeter == pytest.approx(4 * rx * ellipe(1 - (ry / rx) ** 2), rel=1e-9)


def test_rectangle_with_hole_centre_of_mass() -> None:
    doc = {"polygon": [[0, 0], [4, 0], [4, 2], [0, 2]], "holes": [[[2.5, 0.5], [3.5, 0.5], [3.5, 1.5], [2.5, 1.5]]]}
    part = load_part(doc)
    assert part.area == pytest.approx(7.0)
    assert part.center_of_mass == pytest.approx(((8 * 2 - 1 * 3) / 7, 1.0))


def test_cubic_bezier_area_is_exact() -> None:
    # x(t) = 3t, y(t) = 9t(1 − t): the region over the chord has area ∫ y dx = 27/6 = 4.5,
    # centroid x = 1.5 and y = (∫ y²/2 dx)/A = (81·3/2 · 1/30)/4.5 = 0.9.
    pts = [[0, 0], [1, 3], [2, 3], [3, 0]]
    part = load_part({"boundary": [{"type": "bezier", "points": pts}, {"type": "line", "start": [3, 0], "end": [0, 0]}]})
    assert part.area == pytest.approx(4.5, rel=1e-13)
    assert part.center_of_mass == pytest.approx((1.5, 0.9), rel=1e-13)


@pytest.mark.parametrize("doc", [shapes.pie(), shapes.disk_with_flats(1.0, 15), shapes.bezier_blob(7, 3),
                                 shapes.reuleaux(), shapes.random_polygon(30, 4),
                                 {"boundary": [{"type": "ellipse_arc", "center": [0, 0], "rx": 2, "ry": 1,
                                                "rotation_deg": 10, "start_deg": -90, "end_deg": 90},
                                               {"type": "line", "start": [-0.17364817766693, 0.98480775301221],
                                                "end": [0.17364817766693, -0.98480775301221]}]}])
def test_cauchy_formula(doc: dict) -> None:
    """∫₀^π d(θ) dθ equals the hull perimeter (paper §2.1.1)."""
    a = analyse_part(load_part(doc))
    theta = np.linspace(0.0, np.pi, 40001)
    d = a.diameter.values(theta)
    assert d[::4000] == pytest.approx([a.diameter(t) for t in theta[::4000]], rel=1e-12)
    assert float(np.trapezoid(d, theta)) == pytest.approx(a.part.hull.perimeter, rel=2e-7)


def test_polar_moments_closed_forms() -> None:
    # Rectangle w×h: (w² + h²)·wh/12. Disk: πR⁴/2. Pie (sector, half-angle a) about the apex:
    # R⁴a/2, moved to the centroid by the parallel-axis theorem.
    rect = load_part(shapes.rectangle(3.0, 1.0))
    assert rect.polar_moment == pytest.approx((9 + 1) * 3 / 12, rel=1e-12)
    disk = load_part(shapes.disk(2.0))
    assert disk.polar_moment == pytest.approx(math.pi * 16 / 2, rel=1e-12)
    r, a = 5.0, math.radians(20)
    pie = load_part(shapes.pie(r, 20))
    apex = r**4 * a / 2
    assert pie.polar_moment == pytest.approx(apex - pie.area * pie.center_of_mass[1] ** 2, rel=1e-12)
    blob = shapes.bezier_blob(6, 1)
    from shapely.geometry import Polygon
    part = load_part(blob)
    dense = np.concatenate([s.piece().point(np.linspace(0, 1, 20001))[:-1] for s in part.boundary])
    poly = Polygon(dense)
    # Polygon second moment of a dense tessellation (independent formula) about the centroid.
    x, y = dense[:, 0], dense[:, 1]
    x1, y1 = np.roll(x, -1), np.roll(y, -1)
    cross = x * y1 - x1 * y
    j = float(np.sum(cross * (x * x + x * x1 + x1 * x1 + y * y + y * y1 + y1 * y1))) / 12
    cx, cy = poly.centroid.x, poly.centroid.y
    assert part.polar_moment == pytest.approx(j - poly.area * (cx * cx + cy * cy), rel=1e-6)


@pytest.mark.parametrize("form", ["arc", "bezier"])
@pytest.mark.parametrize("center", [(0.0, 0.0), (100.0, 50.0), (-3000.0, 2000.0)])
def test_thin_segment_far_from_the_origin_has_its_closed_form_centroid(center: tuple[float, float], form: str) -> None:
    """A circular segment of radius r and half-angle a (a 5° sliver, 0.044 × 0.0005 for
    r = 0.5): area r²(2a − sin 2a)/2, centroid 4r sin³a / 3(2a − sin 2a) from the centre
    (closed forms). Far from the origin the moments about the world origin kept only a
    few digits of it (the centroid moved by 1e-6 at (100, 50)); given as an arc or as the
    rational quadratic Bezier of the same arc, it stays within 1e-9 of the part's size
    (the coordinates themselves are rounded to 2e-13 at 2000)."""
    r, a = 0.5, math.radians(2.5)
    cx, cy = center
    p0, p2 = (cx + r * math.cos(a), cy - r * math.sin(a)), (cx + r * math.cos(a), cy + r * math.sin(a))
    arc = {"type": "arc", "center": [cx, cy], "radius": r, "start_deg": -2.5, "end_deg": 2.5}
    bez = {"type": "bezier", "points": [list(p0), [cx + r / math.cos(a), cy], list(p2)], "weights": [1.0, math.cos(a), 1.0]}
    part = load_part({"boundary": [arc if form == "arc" else bez, {"type": "line", "start": list(p2), "end": list(p0)}]})
    area = r * r * (2 * a - math.sin(2 * a)) / 2
    offset = 4 * r * math.sin(a) ** 3 / (3 * (2 * a - math.sin(2 * a)))
    chord = 2 * r * math.sin(a)
    assert part.area == pytest.approx(area, rel=1e-9)
    assert abs(part.center_of_mass[0] - (cx + offset)) <= 1e-9 * chord
    assert abs(part.center_of_mass[1] - cy) <= 1e-9 * chord


def test_polar_moment_about_a_given_center_of_mass() -> None:
    """∬|p − c|² dA = ∬|p − g|² dA + A|c − g|² for a centre of mass c given away from the
    centroid g (parallel axes); a w × h rectangle far from the origin."""
    w, h, x0, y0 = 3.0, 1.0, 250.0, -75.0
    doc = shapes.rectangle(w, h)
    moved = {**doc, "polygon": [[x + x0, y + y0] for x, y in doc["polygon"]]}
    c = (x0 + w / 2 + 0.4, y0 + h / 2 - 0.2)
    part = load_part({**moved, "center_of_mass": list(c)})
    assert part.center_of_mass == c
    assert part.polar_moment == pytest.approx((w * w + h * h) * w * h / 12 + w * h * (0.4**2 + 0.2**2), rel=1e-12)
    assert load_part(moved).polar_moment == pytest.approx((w * w + h * h) * w * h / 12, rel=1e-12)


def test_a_cusp_in_a_bezier_is_a_hull_corner() -> None:
    """x = 6t(1−t)² + 2t³, y = 6t(1−t) stops at t = ½ (x′ = 6(1−2t)², y′ = 6(1−2t)):
    a tent with concave sides whose hull is the triangle (0,0), (2,0), (1, 1.5). It was
    refused (the hull saw only two points); by hand: perimeter 2 + 2·√3.25, area 6/5."""
    from algrasp import analyse

    tent = {"boundary": [{"type": "bezier", "points": [[0, 0], [2, 2], [0, 2], [2, 0]]},
                         {"type": "line", "start": [2, 0], "end": [0, 0]}]}
    a = analyse(tent, exact=True)
    assert a.part.hull.perimeter == pytest.approx(2.0 + 2.0 * math.sqrt(3.25), rel=1e-12)
    assert a.part.area == pytest.approx(1.2, rel=1e-12)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.integers(-1000, 1000), st.integers(-1000, 1000)), min_size=3, max_size=60, unique=True))
def test_hull_order_matches_qhull(points: list[tuple[int, int]]) -> None:
    """The monotone chain that locates the hull, against qhull (scipy: an independent
    implementation) on grid points (exact arithmetic, many collinear triples): the same
    corners, strictly convex and counter-clockwise."""
    from scipy.spatial import ConvexHull as Qhull
    from scipy.spatial import QhullError

    from algrasp.geometry.hull import hull_order

    pts = np.array(points, dtype=float) / 100.0
    order = hull_order(pts)
    try:
        expected = set(Qhull(pts).vertices.tolist())
    except QhullError:  # all points on one line: no 2-D hull
        assert len(order) < 3
        return
    assert set(order) == expected
    ring = pts[order]
    e1 = np.roll(ring, -1, axis=0) - ring
    e2 = np.roll(e1, -1, axis=0)
    assert np.all(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0] > 0)
