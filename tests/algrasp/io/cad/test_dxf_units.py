"""DXF units (issue 17): every $INSUNITS code, $MEASUREMENT when it is missing, and a
unitless drawing reported with the assumption made — never silently."""

from __future__ import annotations

import pytest

from algrasp.io.cad import import_bytes


def _dxf(header: dict[str, int], newline: str = "\n") -> bytes:
    lines = ["0", "SECTION", "2", "HEADER"]
    for name, value in header.items():
        lines += ["9", name, "70", str(value)]
    lines += ["0", "ENDSEC", "0", "SECTION", "2", "ENTITIES"]
    square = [(0, 0), (2, 0), (2, 1), (0, 1)]
    for (x0, y0), (x1, y1) in zip(square, square[1:] + square[:1]):
        lines += ["0", "LINE", "8", "0", "10", str(x0), "20", str(y0), "11", str(x1), "21", str(y1)]
    lines += ["0", "ENDSEC", "0", "EOF"]
    return (newline.join(lines) + newline).encode()


def _width(doc: dict) -> float:
    xs = [p for s in doc["boundary"] for p in (s["start"][0], s["end"][0])]
    return max(xs) - min(xs)


@pytest.mark.parametrize("code,unit,width", [(1, "in", 2.0), (4, "mm", 2.0), (6, "m", 2.0), (9, "um", 50.8),
                                             (2, "mm", 609.6), (14, "mm", 200.0), (21, "mm", 609.6012192)])
def test_insunits_codes(code: int, unit: str, width: float) -> None:
    doc = import_bytes("sq.dxf", _dxf({"$INSUNITS": code}))
    assert doc["units"] == unit and _width(doc) == pytest.approx(width, rel=1e-12)
    assert "warnings" not in doc["source"]


def test_measurement_zero_is_inches_and_said() -> None:
    doc = import_bytes("sq.dxf", _dxf({"$MEASUREMENT": 0}))
    assert doc["units"] == "in" and _width(doc) == 2.0
    assert any("$MEASUREMENT" in w for w in doc["source"]["warnings"])


def test_unitless_drawing_is_reported() -> None:
    doc = import_bytes("sq.dxf", _dxf({}, newline="\r\n"))
    assert doc["units"] == "mm" and any("unitless" in w for w in doc["source"]["warnings"])
    assert "warnings" not in import_bytes("sq.dxf", _dxf({}), units="in")["source"]
