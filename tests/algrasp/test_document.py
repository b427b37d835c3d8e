"""Part documents: every listed bad input gets a specific error naming the place."""

from __future__ import annotations

import math
from typing import Any

import pytest

from algrasp.errors import LimitExceededError, PartDocumentError
from algrasp.geometry.limits import Limits
from algrasp.geometry.part import load_part
from algrasp.testing import shapes

SQUARE = [[0, 0], [1, 0], [1, 1], [0, 1]]


def error_of(doc: Any, **kw: Any) -> PartDocumentError:
    with pytest.raises(PartDocumentError) as info:
        load_part(doc, **kw)
    return info.value


def test_open_loop_reports_gap_and_segment() -> None:
    doc = {"boundary": [
        {"type": "line", "start": [0, 0], "end": [1, 0]},
        {"type": "line", "start": [1, 0], "end": [1, 1]},
        {"type": "line", "start": [1, 1.5], "end": [0, 0]}]}
    err = error_of(doc)
    assert err.segment_index == 1 and "open loop" in err.message and "gap of 0.5" in err.message


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_coordinates(bad: float) -> None:
    err = error_of({"polygon": [[0, 0], [bad, 0], [1, 1]]})
    assert err.field == "polygon[1][0]" and "finite" in err.message


def test_zero_length_segment() -> None:
    err = error_of({"polygon": [[0, 0], [1, 0], [1, 0], [0, 1]]})
    assert err.segment_index == 1 and "zero-length" in err.message


def test_zero_area() -> None:
    err = error_of({"polygon": [[0, 0], [1, 0], [2, 0]]})
    assert "zero area" in err.message


def test_self_intersection_names_segments() -> None:
    err = error_of({"polygon": [[0, 0], [2, 2], [2, 0], [0, 1]]})
    assert "self-intersecting" in err.message and "segments 0 and 2" in err.message


def test_arc_sweep_over_360() -> None:
    err = error_of({"boundary": [{"type": "arc", "center": [0, 0], "radius": 1, "start_deg": 0, "end_deg": 400}]})
    assert err.field == "boundary[0].end_deg" and "more than 360" in err.message


@pytest.mark.parametrize("radius", [0, -1])
def test_non_positive_radius(radius: float) -> None:
    err = error_of({"boundary": [{"type": "arc", "center": [0, 0], "radius": radius, "start_deg": 0, "end_deg": 360}]})
    assert err.field == "boundary[0].radius" and "positive" in err.message


def test_non_positive_weight() -> None:
    doc = {"boundary": [
        {"type": "bezier", "points": [[0, 0], [1, 1], [2, 0]], "weights": [1, -0.5, 1]},
        {"type": "line", "start": [2, 0], "end": [0, 0]}]}
    err = error_of(doc)
    assert err.field == "boundary[0].weights[1]" and err.segment_index == 0


def test_bezier_degree_zero() -> None:
    err = error_of({"boundary": [{"type": "bezier", "points": [[0, 0]]}]})
    assert "degree 0" in err.message


def test_center_of_mass_outside_hull() -> None:
    err = error_of({"polygon": SQUARE, "center_of_mass": [2, 0.5]})
    assert err.field == "center_of_mass" and "outside the convex hull" in err.message


@pytest.mark.parametrize("doc", [{}, [], "x", {"boundary": []}])
def test_empty_documents(doc: Any) -> None:
    error_of(doc)


def test_document_limits() -> None:
    with pytest.raises(LimitExceededError):
        load_part(shapes.random_polygon(50), limits=Limits(max_segments=10))
    with pytest.raises(LimitExceededError):
        load_part({"polygon": [[0, 0], [1e12, 0], [0, 1]]})
    doc = {"boundary": [{"type": "bezier", "points": [[i, (i % 2)] for i in range(30)]}]}
    with pytest.raises(LimitExceededError):
        load_part(doc)


def test_unknown_segment_type_and_key() -> None:
    assert "unknown segment type" in error_of({"boundary": [{"type": "spline"}]}).message
    bad = {"type": "arc", "center": [0, 0], "raduis": 1, "radius": 1, "start_deg": 0, "end_deg": 360}
    assert error_of({"boundary": [bad]}).field == "boundary[0].raduis"


def test_hole_outside_boundary() -> None:
    err = error_of({"polygon": SQUARE, "holes": [[[2, 2], [3, 2], [3, 3]]]})
    assert err.field == "holes"


def test_valid_documents_load() -> None:
    for doc in (shapes.pie(), shapes.disk(), shapes.reuleaux(), shapes.bezier_blob(6), shapes.disk_with_flats()):
        load_part(doc)


def test_a_simple_polygon_whose_arc_reading_would_cross_is_analysed_as_drawn() -> None:
    # 10,000 jittered vertices: runs of them read as arcs, and two neighbouring arcs cross
    # (segments 8972/8973) where the drawn edges do not. Shapely, independently, finds the
    # drawn polygon simple; the robust reading must then keep the drawing, not refuse it.
    import shapely

    doc = shapes.random_polygon(10_000, 1)
    assert shapely.Polygon(doc["polygon"]).is_valid
    part = load_part(doc, snap=True)
    assert len(part.boundary) == 10_000 and part.recognised == ()
