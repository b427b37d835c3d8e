"""Real drawings made by other projects (tests/data/real/SOURCES.md: 26 files), imported
as delivered, with no options: every part's box lies inside ezdxf's own bounding box of the
drawing, drawings that hold only outlines match it exactly, nothing is printed, nothing
takes over 10 s. The part counts of the cutting drawings were read off each drawing
(rendered) once; the boxes are checked against ezdxf every time. The larger corpus of
drawings as shops send them is tests/algrasp/io/cad/test_shop_corpus.py."""

from __future__ import annotations

import time
from pathlib import Path

import ezdxf
import ezdxf.bbox
import pytest
from ezdxf import recover

from algrasp.errors import PartDocumentError
from algrasp.io.cad import import_bytes, list_parts

REAL = Path(__file__).parents[3] / "data" / "real"
# file → (parts, holes of the largest part, the drawing holds only the outline): drawings
# for cutting, counted by looking at them
EXPECTED = {
    "koppi-involute-teeth-20.dxf": (1, 1, True),
    "koppi-involute-teeth-20-multiple.dxf": (10, 1, True),
    "ezdxf-R12_with_trash_beyond_EOF.dxf": (1, 0, True),
    "ezdxf-cc_dxflib.dxf": (1, 0, True),
    "ezdxf-forms.dxf": (23, 0, True),
    "ezdxf-issue_1359_1.dxf": (1, 1, True),
    "ezdxf-issue_1359_2.dxf": (2, 0, True),
    "ezdxf-multi_insert_with_attribs.dxf": (2, 0, False),  # a flag (its pole is an open chain) and a disc
    "landrs-battery-plate.dxf": (1, 12, False),
    **{p.name: (1, 1, True) for p in sorted(REAL.glob("koppi-involute-14.5-teeth-*.dxf"))},
}
# Drawings that are not for cutting (ezdxf's test drawings: overlapping and crossing
# squares drawn to be ambiguous, a colour chart, door plans, a map whose states share
# borders): what they "hold" is a matter of reading, so only robustness is checked —
# no traceback, boxes inside the drawing's, nothing printed, under 10 s.
CLUTTER = ["ezdxf-1_polylines.dxf", "ezdxf-2_polylines.dxf", "ezdxf-dimension_in_nested_blocks.dxf",
           "ezdxf-colors.dxf", "ezdxf-issue1106.dxf", "ezdxf-usa.dxf", "ezdxf-wipeout_door.dxf", "ezdxf-uncommon.dxf"]


def _extents(path: Path) -> tuple[float, float, float, float]:
    try:
        doc = ezdxf.readfile(str(path))
    except ezdxf.DXFError:  # a flawed file (issue1106.dxf): ezdxf's own repair, as the importer does
        doc, _ = recover.readfile(str(path))
    box = ezdxf.bbox.BoundingBox()
    for e in doc.modelspace():  # entity by entity: ezdxf fails on one odd entity of issue1106.dxf
        try:
            box.extend(ezdxf.bbox.extents([e]))
        except ezdxf.DXFError:
            continue
    return box.extmin.x, box.extmin.y, box.extmax.x, box.extmax.y


@pytest.mark.parametrize("name", sorted([*EXPECTED, *CLUTTER]))
def test_real_drawing_imports_as_delivered(name: str, capsys: pytest.CaptureFixture[str]) -> None:
    path = REAL / name
    t = time.perf_counter()
    out = list_parts(name, path.read_bytes())
    assert time.perf_counter() - t < 10.0
    parts, holes, outline_only = EXPECTED.get(name, (None, None, False))
    rows = out["parts"]
    if parts is not None:
        assert len(rows) == parts and rows[0]["holes"] == holes
    x0, y0, x1, y1 = _extents(path)
    slack = 1e-6 * max(x1 - x0, y1 - y0)
    for r in rows:
        a0, b0, a1, b1 = r["bbox"]
        assert x0 - slack <= a0 and b0 >= y0 - slack and a1 <= x1 + slack and b1 <= y1 + slack
    if outline_only:  # then the parts' boxes together are ezdxf's box
        union = [min(r["bbox"][0] for r in rows), min(r["bbox"][1] for r in rows),
                 max(r["bbox"][2] for r in rows), max(r["bbox"][3] for r in rows)]
        assert union == pytest.approx([x0, y0, x1, y1], abs=slack)
    doc = import_bytes(name, path.read_bytes(), part=0)
    assert doc["boundary"]
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err == ""  # ezdxf's log is kept, not printed


def test_binary_dxf_reads() -> None:
    """A binary R13 DXF is read (its lines happen to close no loop: said so, in one line)."""
    with pytest.raises(PartDocumentError, match="open contour"):
        import_bytes("bin.dxf", (REAL / "ezdxf-bin_dxf_r13.dxf").read_bytes())


GEARS = sorted(REAL.glob("koppi-involute-14.5-teeth-*.dxf"))


@pytest.mark.parametrize("path", GEARS, ids=lambda p: p.stem)
def test_real_gears_have_the_tooth_period(path: Path) -> None:
    """An N-tooth gear repeats every 360°/N; the diameter function also every 180°, so
    the squeeze period is 360°/N for even N and 180°/N for odd N (issue 16: symmetry to
    tolerance, on tessellated drawings with up to 800 segments)."""
    from algrasp.planning.analysis import IDEAL, analyse_document

    n = int(path.stem.rsplit("-", 1)[-1])
    doc = import_bytes(path.name, path.read_bytes())
    period = analyse_document(doc, IDEAL).to_dict()["robust"]["squeeze"]["symmetry_period_deg"]
    assert period == pytest.approx(360.0 / n if n % 2 == 0 else 180.0 / n, abs=1e-9)


@pytest.mark.parametrize("name", sorted([*EXPECTED, *CLUTTER]))
def test_crlf_and_lf_import_identically(name: str) -> None:
    """Issue 17: most DXFs are saved with Windows line endings. The corpus is stored with
    LF; each drawing written with CRLF lists the same parts and imports the same outline."""
    lf = (REAL / name).read_bytes().replace(b"\r\n", b"\n")
    crlf = lf.replace(b"\n", b"\r\n")
    assert list_parts(name, crlf) == list_parts(name, lf)
    assert import_bytes(name, crlf, part=0) == import_bytes(name, lf, part=0)
