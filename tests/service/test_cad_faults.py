"""CAD parser faults (issue 31): every file a reader library chokes on is a 422 naming the
file or the entity, fast, and the service goes on — an encrypted zip member, an SVG whose
root is not <svg>, an INSERT of a missing block, a coordinate of 1e300, an INSERT fan-out
of 2^15 and 2^16, a segment shorter than the chaining tolerance."""

from __future__ import annotations

import io
import zipfile
from collections.abc import Callable, Iterator
from typing import Any

import pytest

from tests.service.conftest import Server, dxf_bytes, start_server

SQUARE = {"name": "sq", "units": "mm", "boundary": [[0, 0], [4, 0], [4, 3], [0, 3]]}


@pytest.fixture(scope="module")
def srv(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    s = start_server(tmp_path_factory.mktemp("cad"))
    yield s
    s.kill()


def _missing_block(doc: Any) -> None:
    doc.modelspace().add_lwpolyline([(0, 0), (10, 0), (10, 5), (0, 5)], close=True)
    doc.modelspace().add_blockref("NOPE", (0, 0))


def _huge(doc: Any) -> None:
    doc.modelspace().add_lwpolyline([(0, 0), (1e300, 0), (1e300, 5), (0, 5)], close=True)


def _fanout(levels: int) -> Callable[[Any], None]:
    def build(doc: Any) -> None:
        doc.blocks.new("L0").add_lwpolyline([(0, 0), (1, 0), (1, 1), (0, 1)], close=True)
        for d in range(1, levels + 1):
            b = doc.blocks.new(f"L{d}")
            b.add_blockref(f"L{d - 1}", (0, 0))
            b.add_blockref(f"L{d - 1}", (2 ** d, 0))
        doc.modelspace().add_blockref(f"L{levels}", (0, 0))
    return build


CASES: dict[str, tuple[str, bytes, str]] = {
    "INSERT of a missing block": ("plate.dxf", dxf_bytes(_missing_block), "NOPE"),
    "coordinate 1e300": ("plate.dxf", dxf_bytes(_huge), "coordinate"),
    "fan-out 2^15": ("fan.dxf", dxf_bytes(_fanout(15)), "expands to more than"),
    "fan-out 2^16": ("fan.dxf", dxf_bytes(_fanout(16)), "nested deeper"),
    "root is <html>": ("a.svg", b'<?xml version="1.0"?><html xmlns="http://www.w3.org/1999/xhtml"><body/></html>', "root"),
    "root is a bare <g>": ("a.svg", b'<g xmlns="http://www.w3.org/2000/svg"><rect width="10" height="5"/></g>', "root"),
}


@pytest.mark.parametrize("case", sorted(CASES))
@pytest.mark.parametrize("listing", [False, True])
def test_parser_faults_are_422_naming_what(srv: Server, case: str, listing: bool) -> None:
    name, data, says = CASES[case]
    with srv.client() as c:
        r = c.post("/v1/imports", files={"file": (name, data)}, data={"list": "true"} if listing else {})
        assert r.status_code == 422, (r.status_code, r.text[:300])
        err = r.json()["error"]
        assert says in err["message"] and err.get("field"), err
        assert c.post("/v1/plans", json={"part": SQUARE}).status_code == 200  # the pools live


def test_a_segment_shorter_than_the_tolerance_is_set_aside(srv: Server) -> None:
    def build(doc: Any) -> None:
        doc.modelspace().add_lwpolyline([(0, 0), (10, 0), (10, 5), (0, 5)], close=True)
        doc.modelspace().add_line((20, 20), (20 + 1e-9, 20))
        doc.modelspace().add_lwpolyline([(30, 0), (30 + 1e-9, 0), (30, 1e-9)], close=True)  # a loop of no area

    with srv.client() as c:
        r = c.post("/v1/imports", files={"file": ("plate.dxf", dxf_bytes(build))})
        assert r.status_code == 200, r.text
        xs = [p[0] for s in r.json()["boundary"] for p in ([s["start"], s["end"]] if isinstance(s, dict) else [s])]
        assert max(xs) == pytest.approx(10.0) and min(xs) == pytest.approx(0.0)


def _encrypted_zip(inner: dict[str, bytes]) -> bytes:
    """A zip whose members carry the encryption flag (bit 0 of the general purpose flags,
    in the local and the central headers): what a password-protected archive looks like
    to a reader without the password."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as zf:
        for n, d in inner.items():
            zf.writestr(n, d)
    data = bytearray(buf.getvalue())
    for sig, offset in ((b"PK\x03\x04", 6), (b"PK\x01\x02", 8)):
        k = data.find(sig)
        while k >= 0:
            data[k + offset] |= 0x1
            k = data.find(sig, k + 4)
    return bytes(data)


def test_an_encrypted_archive_member_is_named(srv: Server) -> None:
    import json

    archive = _encrypted_zip({"sq.json": json.dumps(SQUARE).encode()})
    assert zipfile.ZipFile(io.BytesIO(archive)).infolist()[0].flag_bits & 0x1
    with srv.client() as c:
        r = c.post("/v1/jobs", files={"archive": ("parts.zip", archive)})
        assert r.status_code == 422, r.text
        assert "sq.json" in r.json()["error"]["message"] and "encrypted" in r.json()["error"]["message"]
