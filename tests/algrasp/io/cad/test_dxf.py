"""DXF import: exact arcs, ellipses, bulges, splines and blocks, checked against
hand-written part documents, closed forms and an independent NURBS evaluation."""

from __future__ import annotations

import io
import math
from typing import Any

import ezdxf
import numpy as np
import pytest

from algrasp.errors import ConfigError, PartDocumentError
from algrasp.geometry.part import load_part
from algrasp.io.cad import import_bytes
from algrasp.planning.analysis import analyse_part

S, C = math.sin(math.radians(70)) * 5, math.cos(math.radians(70)) * 5


def _bytes(doc: Any) -> bytes:
    buf = io.StringIO()
    doc.write(buf)
    return buf.getvalue().encode()


def _functions(doc: dict[str, Any]) -> dict[str, Any]:
    a = analyse_part(load_part(doc)).to_dict()
    return {k: a[k] for k in ("squeeze", "push", "push_grasp", "diameter", "radius")}


def _close(a: Any, b: Any, tol: float = 1e-9) -> bool:
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_close(a[k], b[k], tol) for k in a)
    if isinstance(a, list):
        return len(a) == len(b) and all(_close(x, y, tol) for x, y in zip(a, b))
    if isinstance(a, float):
        return math.isclose(a, b, abs_tol=tol)
    return bool(a == b)


def test_pie_with_an_arc_has_the_papers_squeeze_function() -> None:
    d = ezdxf.new(units=4)
    m = d.modelspace()
    m.add_line((0, 0), (C, S), dxfattribs={"layer": "CUT"})
    m.add_arc((0, 0), 5, 70, 110, dxfattribs={"layer": "CUT"})
    m.add_line((-C, S), (0, 0), dxfattribs={"layer": "CUT"})
    m.add_text("part 20°", dxfattribs={"layer": "CUT"})  # annotation is skipped
    doc = import_bytes("pie.dxf", _bytes(d), layer="cut")
    assert doc["units"] == "mm" and [s["type"] for s in doc["boundary"]] == ["line", "arc", "line"]
    sq = _functions(doc)["squeeze"]
    steps = [v for s in sq["steps"] for v in (s["start_deg"], s["end_deg"], s["fixed_point_deg"])]
    assert steps == pytest.approx([20, 90, 70, 90, 160, 110], abs=1e-9)  # conventions §6
    assert [v for r in sq["ramps"] for v in (r["start_deg"], r["end_deg"])] == pytest.approx([160, 200], abs=1e-9)


def test_ellipse_and_arc_part_matches_its_part_document() -> None:
    d = ezdxf.new()
    m = d.modelspace()
    m.add_ellipse((0, 0), major_axis=(4, 0), ratio=0.5, start_param=0, end_param=math.pi)
    m.add_arc((-2, 0), 2, 180, 360)  # drawn the other way round: chaining reverses it
    m.add_arc((2, 0), 2, 180, 360)
    doc = import_bytes("cam.dxf", _bytes(d))
    assert sorted(s["type"] for s in doc["boundary"]) == ["arc", "arc", "ellipse_arc"]
    ref = {"boundary": [
        {"type": "ellipse_arc", "center": [0, 0], "rx": 4, "ry": 2, "rotation_deg": 0, "start_deg": 0, "end_deg": 180},
        {"type": "arc", "center": [-2, 0], "radius": 2, "start_deg": 180, "end_deg": 360},
        {"type": "arc", "center": [2, 0], "radius": 2, "start_deg": 180, "end_deg": 360}]}
    assert _close(_functions(doc), _functions(ref))


def test_bulged_polyline_is_an_exact_stadium() -> None:
    d = ezdxf.new()
    # stadium: centres 10 apart, radius 3; bulge 1 = a half circle
    d.modelspace().add_lwpolyline([(0, -3, 0, 0, 0), (10, -3, 0, 0, 1), (10, 3, 0, 0, 0), (0, 3, 0, 0, 1)],
                                  format="xyseb", close=True)
    doc = import_bytes("slot.dxf", _bytes(d))
    arcs = [s for s in doc["boundary"] if s["type"] == "arc"]
    assert [a["radius"] for a in arcs] == pytest.approx([3, 3], abs=1e-12)
    part = load_part(doc)
    assert part.area == pytest.approx(10 * 6 + math.pi * 9, rel=1e-12)
    values = [e["value"] for e in _functions(doc)["diameter"]["extrema"]]
    assert (min(values), max(values)) == pytest.approx((6.0, 16.0), rel=1e-12)


def _de_boor(p: int, U: np.ndarray, P: np.ndarray, w: np.ndarray, u: float) -> np.ndarray:
    """Independent NURBS evaluation (de Boor on homogeneous points)."""
    H = np.column_stack([P * w[:, None], w])
    k = min(int(np.searchsorted(U, u, "right")) - 1, len(P) - 1)
    d = [H[j + k - p].copy() for j in range(p + 1)]
    for r in range(1, p + 1):
        for j in range(p, r - 1, -1):
            a = (u - U[j + k - p]) / (U[j + 1 + k - r] - U[j + k - p])
            d[j] = (1 - a) * d[j - 1] + a * d[j]
    return d[p][:2] / d[p][2]


def _bezier(P: np.ndarray, w: np.ndarray, t: float) -> np.ndarray:
    k = len(P) - 1
    B = np.array([math.comb(k, i) * t**i * (1 - t) ** (k - i) for i in range(k + 1)]) * w
    return np.asarray(B @ P / B.sum())


def test_rational_spline_round_trips_within_1e9() -> None:
    P = np.array([[0, 0], [3, 4], [7, 5], [10, 2], [12, -1], [8, -4], [4, -3]], float)
    w = np.array([1.0, 0.7, 1.6, 1.1, 0.9, 1.3, 1.0])
    U = np.array([0, 0, 0, 0, 0.2, 0.45, 0.7, 1, 1, 1, 1])
    d = ezdxf.new()
    d.modelspace().add_rational_spline([(*p, 0) for p in P], w, degree=3, knots=U)
    d.modelspace().add_line(tuple(P[-1]), tuple(P[0]))
    doc = import_bytes("spline.dxf", _bytes(d))
    beziers = [s for s in doc["boundary"] if s["type"] == "bezier"]
    assert len(beziers) == 4 and all(len(b["points"]) == 4 for b in beziers)  # one cubic per knot span
    spans = [0, 0.2, 0.45, 0.7, 1]
    forward = np.allclose(beziers[0]["points"][0], P[0])
    segs = beziers if forward else [{"points": b["points"][::-1], "weights": b["weights"][::-1]} for b in beziers[::-1]]
    err = max(float(np.linalg.norm(_bezier(np.array(b["points"]), np.array(b["weights"]), t)
                                   - _de_boor(3, U, P, w, spans[j] + t * (spans[j + 1] - spans[j]))))
              for j, b in enumerate(segs) for t in np.linspace(0, 1, 21))
    assert err < 1e-9


def test_blocks_are_expanded_with_their_transformation() -> None:
    d = ezdxf.new()
    blk = d.blocks.new("PLATE")
    blk.add_lwpolyline([(0, 0), (4, 0), (4, 1), (0, 1)], close=True)
    blk.add_circle((3, 0.5), 0.25)
    d.modelspace().add_blockref("PLATE", (10, 5), dxfattribs={"xscale": 2, "yscale": 2, "rotation": 30})
    doc = import_bytes("plate.dxf", _bytes(d))
    assert len(doc["holes"]) == 1 and doc["holes"][0][0]["type"] == "arc"
    assert load_part(doc).area == pytest.approx(4 * 4 - math.pi * 0.25, rel=1e-12)  # scaled ×2, minus the hole


@pytest.mark.parametrize(("code", "units", "scale"), [(1, "in", 1.0), (2, "mm", 304.8), (6, "m", 1.0)])
def test_units_come_from_the_header(code: int, units: str, scale: float) -> None:
    d = ezdxf.new(units=code)
    d.modelspace().add_lwpolyline([(0, 0), (2, 0), (2, 1)], close=True)
    doc = import_bytes("u.dxf", _bytes(d))
    assert doc["units"] == units and load_part(doc).area == pytest.approx(scale**2, rel=1e-12)


def test_clear_errors() -> None:
    d = ezdxf.new()
    m = d.modelspace()
    m.add_line((0, 0), (5, 0), dxfattribs={"layer": "OPEN"})
    m.add_line((5, 0), (5, 5), dxfattribs={"layer": "OPEN"})
    m.add_line((5, 5.25), (0, 0), dxfattribs={"layer": "OPEN"})
    m.add_solid([(0, 0), (1, 0), (0, 1)], dxfattribs={"layer": "SOLID"})
    m.add_lwpolyline([(0, 0), (1, 0), (1, 1)], close=True, dxfattribs={"layer": "TWO"})
    m.add_lwpolyline([(5, 0), (6, 0), (6, 1)], close=True, dxfattribs={"layer": "TWO"})
    data = _bytes(d)
    with pytest.raises(PartDocumentError, match=r"open contour.*0\.25"):
        import_bytes("x.dxf", data, layer="OPEN")
    with pytest.raises(PartDocumentError, match="layer 'SOLID' has no outline geometry"):  # fills are set aside
        import_bytes("x.dxf", data, layer="SOLID")
    with pytest.raises(PartDocumentError, match="holds 2 parts.*--part K"):  # two parts on one layer (issue 17)
        import_bytes("x.dxf", data, layer="TWO")
    second = import_bytes("x.dxf", data, layer="TWO", part=1)
    assert second["name"] == "x#1" and second["source"]["part"] == 1 and len(second["boundary"]) == 3
    with pytest.raises(PartDocumentError, match="layer 'EMPTY' has no outline.*OPEN, SOLID, TWO"):
        import_bytes("x.dxf", data, layer="EMPTY")
    with pytest.raises(ConfigError, match="element_id"):
        import_bytes("x.dxf", data, element_id="a")
    with pytest.raises(PartDocumentError, match="not a readable DXF"):
        import_bytes("x.dxf", b"\x00garbage")


@pytest.mark.parametrize(("p", "n", "seed"), [(2, 5, 1), (3, 8, 2), (3, 6, 3)])
def test_unclamped_nurbs_split_matches_de_boor(p: int, n: int, seed: int) -> None:
    from algrasp.io.cad.nurbs import nurbs_to_beziers

    rng = np.random.default_rng(seed)
    P, w, U = rng.uniform(-5, 5, (n, 2)), rng.uniform(0.5, 2.0, n), np.sort(rng.uniform(0, 3, n + p + 1))
    spans = [u for u in np.unique(U) if U[p] <= u <= U[n]]
    segs = nurbs_to_beziers(p, P, w, U)
    assert len(segs) == len(spans) - 1
    err = max(float(np.linalg.norm(_bezier(B, W, t) - _de_boor(p, U, P, w, spans[j] + t * (spans[j + 1] - spans[j]))))
              for j, (B, W) in enumerate(segs) for t in np.linspace(0, 1, 11)[:-1])
    assert err < 1e-9
