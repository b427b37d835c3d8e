"""A real 20-tooth involute gear (koppi/involute-gear-collection, CC0; see
tests/data/real/SOURCES.md) as its DXF and as an STL of it: the period is the tooth pitch
(18°) and no plan rides on facets (issue 16)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import shapely

from algrasp.io.cad import import_bytes, import_file
from algrasp.planning.analysis import EXACT, IDEAL, analyse_document
from algrasp.planning.plans import make_plan
from tests.algrasp.meshes import extrude_stl

GEAR = Path(__file__).parents[1] / "data" / "real" / "koppi-involute-teeth-20.dxf"


def _stl_doc() -> dict:
    doc = import_file(str(GEAR))
    pts = np.array([s["start"] for s in doc["boundary"]])
    c, s = np.cos(0.1274), np.sin(0.1274)  # an odd pose: float32 rounding breaks exact symmetry
    pts = pts @ np.array([[c, s], [-s, c]]) + [3.3, -1.7]
    return import_bytes("gear.stl", extrude_stl(shapely.Polygon(pts), 5.0))


def test_gear_drawing_has_the_tooth_period() -> None:
    a = analyse_document(import_file(str(GEAR)), IDEAL).to_dict()
    assert a["robust"]["squeeze"]["symmetry_period_deg"] == 18.0


def test_tessellated_gear_stl_gets_18_degrees_and_no_facet_plan() -> None:
    doc = _stl_doc()
    exact = make_plan(analyse_document(doc, EXACT), "squeeze").to_dict()
    # The exact model sees the float32 facets: no symmetry, and margins of micro-degrees.
    assert exact["symmetry_period_deg"] == 180.0
    assert min(s["margin_deg"] for s in exact["steps"][1:]) < 1e-3
    robust = make_plan(analyse_document(doc, IDEAL), "squeeze").to_dict()
    assert robust["symmetry_period_deg"] == 18.0
    assert len(robust["final_orientations_deg"]) == 20
    margins = [s["margin_deg"] for s in robust["steps"][1:]]
    assert len(robust["steps"]) <= 3 and all(m > 0.5 for m in margins)
    assert robust["final_uncertainty_deg"] < 1.0


def test_crlf_and_lf_import_identically() -> None:
    """27 of 34 real DXFs are saved with Windows line endings (issue 17)."""
    from algrasp.io.cad import import_bytes

    lf = GEAR.read_bytes().replace(b"\r\n", b"\n")
    a = import_bytes("gear.dxf", lf)
    b = import_bytes("gear.dxf", lf.replace(b"\n", b"\r\n"))
    assert a == b and len(a["boundary"]) == 380 and len(a["holes"]) == 1


def test_damaged_dxf_is_repaired_or_refused_in_one_line(capsys) -> None:  # type: ignore[no-untyped-def]
    """No EOF marker: repaired by ezdxf's recover mode, and said; a bad number: one clear
    error; ezdxf prints nothing either way."""
    import pytest

    from algrasp.errors import PartDocumentError
    from algrasp.io.cad import import_bytes

    data = GEAR.read_bytes().replace(b"\r\n", b"\n")
    doc = import_bytes("gear.dxf", data.replace(b"  0\nEOF\n", b""))
    assert len(doc["boundary"]) == 380 and any("repaired" in w for w in doc["source"]["warnings"])
    with pytest.raises(PartDocumentError) as e:
        import_bytes("gear.dxf", data.replace(b" 10\n26.280794545155107\n", b" 10\nabc\n", 1))
    assert "not a readable DXF drawing" in str(e.value)
    out = capsys.readouterr()
    assert out.out == "" and out.err == ""
