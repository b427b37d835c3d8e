"""DXF import time for a large sheet (issue 17: a 10,000-entity sheet in ≤ 5 s).

Writes (ezdxf) a drawing of 10,000 LINE entities — a 9,000-edge serrated outline with
25 forty-edge holes — in shuffled order with CRLF line endings, then times
``algrasp.io.cad.import_bytes`` (read, chain, classify loops).
"""

from __future__ import annotations

import io
import math
import random
import time

import ezdxf


def sheet(n_outline: int = 9000, holes: int = 25, hole_edges: int = 40) -> bytes:
    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = 4
    msp = doc.modelspace()
    lines = []
    pts = [((100 + (2 if k % 2 else 0)) * math.cos(2 * math.pi * k / n_outline),
            (100 + (2 if k % 2 else 0)) * math.sin(2 * math.pi * k / n_outline)) for k in range(n_outline)]
    lines += list(zip(pts, pts[1:] + pts[:1]))
    for h in range(holes):
        cx, cy = -50 + 25 * (h % 5), -50 + 25 * (h // 5)
        ring = [(cx + 5 * math.cos(2 * math.pi * k / hole_edges), cy + 5 * math.sin(2 * math.pi * k / hole_edges))
                for k in range(hole_edges)]
        lines += list(zip(ring, ring[1:] + ring[:1]))
    random.Random(1).shuffle(lines)
    for a, b in lines:
        msp.add_line(a, b)
    out = io.StringIO()
    doc.write(out)
    return out.getvalue().replace("\n", "\r\n").encode()


def main() -> None:
    from algrasp.io.cad import import_bytes

    data = sheet()
    t = time.perf_counter()
    doc = import_bytes("sheet.dxf", data)
    dt = time.perf_counter() - t
    print(f"10,000-entity DXF sheet ({len(data) / 1e6:.1f} MB, CRLF): {dt:.2f} s "
          f"({len(doc['boundary'])} outline segments, {len(doc['holes'])} holes; target ≤ 5 s)")


if __name__ == "__main__":
    main()
