"""SVG import (transforms, units, y flip, exact arcs and Beziers) and mesh import (stable
poses, projected convex hull), checked against closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh

from algrasp.errors import PartDocumentError
from algrasp.geometry.part import load_part
from algrasp.io.cad import import_bytes
from algrasp.planning.analysis import analyse_part

S, C = math.sin(math.radians(70)) * 5, math.cos(math.radians(70)) * 5
SVG = f"""<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="100mm" viewBox="0 0 50 50">
<g transform="translate(20,20) rotate(35)">
  <path id="pie" d="M 0 0 L {C / 2} {-S / 2} A 2.5 2.5 0 0 0 {-C / 2} {-S / 2} Z"/>
</g>
<ellipse id="oval" cx="10" cy="10" rx="4" ry="1.5" transform="rotate(20 10 10)"/>
<path id="cam" d="M 0 0 C 2 -3 6 -3 8 0 Q 4 3 0 0 Z"/>
<path id="open" d="M 0 0 L 10 0 L 10 10"/>
</svg>""".encode()


def test_svg_pie_keeps_the_papers_functions_in_mm() -> None:
    doc = import_bytes("d.svg", SVG, element_id="pie")  # drawn at half size in a 2 mm/unit viewBox
    assert [s["type"] for s in doc["boundary"]] == ["line", "arc", "line"]
    assert doc["boundary"][1]["radius"] == pytest.approx(5.0, rel=1e-12)
    part = load_part(doc)
    assert part.area == pytest.approx(25 * math.radians(40) / 2, rel=1e-9)
    sq = analyse_part(part).to_dict()["squeeze"]
    assert sorted(s["end_deg"] - s["start_deg"] for s in sq["steps"]) == pytest.approx([70, 70], abs=1e-6)
    assert [r["end_deg"] - r["start_deg"] for r in sq["ramps"]] == pytest.approx([40], abs=1e-6)


def test_svg_ellipse_is_exact() -> None:
    doc = import_bytes("d.svg", SVG, element_id="oval")
    assert {s["type"] for s in doc["boundary"]} == {"ellipse_arc"}
    part = load_part(doc)
    assert part.area == pytest.approx(math.pi * 8 * 3, rel=1e-12)
    d = [e["value"] for e in analyse_part(part).to_dict()["diameter"]["extrema"]]
    assert (min(d), max(d)) == pytest.approx((6.0, 16.0), rel=1e-12)


def test_svg_beziers_keep_their_degree_and_y_is_flipped() -> None:
    doc = import_bytes("d.svg", SVG, element_id="cam")
    degrees = sorted(len(s["points"]) - 1 for s in doc["boundary"])
    assert degrees == [2, 3]
    cubic = [s for s in doc["boundary"] if len(s["points"]) == 4][0]
    assert np.allclose(cubic["points"], [[0, 0], [4, 6], [12, 6], [16, 0]], atol=1e-9)  # ×2 mm, y up


def test_svg_errors_name_the_problem() -> None:
    with pytest.raises(PartDocumentError, match="open contour"):
        import_bytes("d.svg", SVG, element_id="open")
    with pytest.raises(PartDocumentError, match="no element with id 'nope'.*cam, open, oval, pie"):
        import_bytes("d.svg", SVG, element_id="nope")


def _prism(poly: list[tuple[float, float]], height: float) -> bytes:
    pts = np.array(poly, float)
    mesh = trimesh.convex.convex_hull(np.vstack([np.c_[pts, np.zeros(len(pts))], np.c_[pts, np.full(len(pts), height)]]))
    return bytes(mesh.export(file_type="stl"))


def _edges(poly: np.ndarray) -> list[float]:
    return sorted(np.hypot(*(np.roll(poly, -1, axis=0) - poly).T))


def test_mesh_of_a_prism_yields_its_polygon() -> None:
    poly = [(0, 0), (20, 0), (25, 8), (10, 14), (-3, 6)]
    doc = import_bytes("plate.stl", _prism(poly, 2.0))
    assert doc["approximate"] is True and doc["source"]["pose"] == 0
    got = np.array(doc["polygon"])
    assert len(got) == 5 and _edges(got) == pytest.approx(_edges(np.array(poly, float)), abs=1e-9)
    part = load_part(doc)
    assert part.area == pytest.approx(266.0, rel=1e-9)  # shoelace area of the pentagon
    assert sum(doc["source"]["pose_probabilities"][:2]) > 0.8  # a thin plate rests on a large face


def test_mesh_pose_out_of_range() -> None:
    with pytest.raises(PartDocumentError, match="pose 99 does not exist"):
        import_bytes("plate.stl", _prism([(0, 0), (4, 0), (0, 3)], 1.0), pose=99)
