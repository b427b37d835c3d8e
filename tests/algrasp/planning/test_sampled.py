"""Drawing samples of an analysis (``?samples=N``): checked against closed forms."""

from __future__ import annotations

import math

import numpy as np

from algrasp import analyse
from algrasp.planning.sampled import sampled

W, H = 4.0, 2.0
RECT = {"polygon": [[0, 0], [W, 0], [W, H], [0, H]]}


def test_rectangle_width_and_radius_are_the_closed_forms() -> None:
    out = sampled(analyse(RECT, exact=True), 72)
    theta = np.radians(out["curves"]["theta_deg"])
    # width of a W×H rectangle along the closing axis: W|sin θ| + H|cos θ|
    d = W * np.abs(np.sin(theta)) + H * np.abs(np.cos(theta))
    assert np.allclose(out["curves"]["diameter"], d, rtol=1e-6)
    # centre of mass at the centre: r = d / 2
    assert np.allclose(out["curves"]["radius"], d / 2, rtol=1e-6)


def test_geometry_is_the_part_and_its_hull() -> None:
    pie = {"boundary": [{"type": "line", "start": [0, 0], "end": [5 * math.cos(math.radians(70)), 5 * math.sin(math.radians(70))]},
                        {"type": "arc", "center": [0, 0], "radius": 5, "start_deg": 70, "end_deg": 110},
                        {"type": "line", "start": [5 * math.cos(math.radians(110)), 5 * math.sin(math.radians(110))],
                         "end": [0, 0]}],
           "holes": [[{"type": "arc", "center": [0, 3.5], "radius": 0.5, "start_deg": 0, "end_deg": 360}]]}
    g = sampled(analyse(pie, exact=True), 8)["geometry"]
    outline, hull, hole = np.array(g["outline"]), np.array(g["hull"]), np.array(g["holes"][0])
    # every outline point within the radius, the arc's points on it; the hole on its circle
    assert np.all(np.hypot(*outline.T) <= 5 + 1e-6)
    assert np.sum(np.isclose(np.hypot(*outline.T), 5, atol=1e-6)) >= 10
    assert np.allclose(np.hypot(hole[:, 0], hole[:, 1] - 3.5), 0.5, atol=1e-6)
    # the pie is convex: hull and outline enclose the same area (shoelace), 25·(40° in rad)/2 minus chords
    def area(p: np.ndarray) -> float:
        return 0.5 * abs(float(np.dot(p[:, 0], np.roll(p[:, 1], -1)) - np.dot(p[:, 1], np.roll(p[:, 0], -1))))
    assert math.isclose(area(outline), area(hull), rel_tol=1e-3)
    assert math.isclose(area(outline), 25 * math.radians(40) / 2, rel_tol=2e-3)


def test_squeeze_samples_follow_the_steps() -> None:
    a = analyse(RECT, exact=True)
    c = sampled(a, 360)["curves"]
    # a rectangle squeezed ends with a side on a jaw: every θ maps to a multiple of 90° (lifted)
    after = np.array(c["squeeze_deg"])
    assert np.allclose(np.mod(after + 1e-6, 90.0), 0.0, atol=1e-5)
    # and never turns further than 90°
    assert np.all(np.abs(after - np.array(c["theta_deg"])) <= 90 + 1e-6)
