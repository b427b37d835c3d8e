"""Cut and engrave told apart by stroke colour, where geometry cannot tell them.

Laser shops mark what to cut and what to engrave (etch, score) by stroke colour, and the
conventions differ (red is cut in one shop, etch in another), so no colour means "engrave"
by itself. What the drawing itself says: when its strokes fall in exactly two colours and
the rarer colour's lines, taken as cuts, would carve parts out of the other colour's parts
— every one of its lines lying on or within the material (outline less holes) of the parts
the commoner colour cuts — the rarer colour is engraving. A red rectangle drawn on a panel's
corner is then an etched area, not a part nested in an L-shaped one; red loops that are
only holes (a shop cutting inner contours first in their own colour) change no part and
stay cuts; a red part nested in a blue part's cutout lies in the cutout, not the material,
and stays a part. The decision is said in the warnings; ``--engrave-colours`` (HTTP:
``engrave_colours``, the workbench's "engrave colours") names the engraving colours
instead, or says none is.
"""

from __future__ import annotations

import re
from collections import Counter
from collections.abc import Callable, Sequence
from typing import Any

from algrasp.errors import ConfigError, PartDocumentError
from algrasp.io.cad.arrange import GAP_MAX_REL
from algrasp.io.cad.chain import Piece, ring, samples

FindParts = Callable[[Sequence[Piece]], Any]
HEX = re.compile(r"#(?:[0-9a-f]{3}|[0-9a-f]{6})")


def parse_colours(text: str | None) -> frozenset[str] | None:
    """``"#ff0000, #00F"`` → ``{"#ff0000", "#0000ff"}``; ``"none"`` → the empty set (every
    colour is cut); None → None (judged from the drawing). ConfigError naming
    ``engrave_colours`` for anything else."""
    if text is None:
        return None
    if text.strip().lower() == "none":
        return frozenset()
    out = set()
    for item in (t.strip().lower() for t in text.split(",")):
        if not HEX.fullmatch(item):
            raise ConfigError("engrave_colours", f"{item!r} is not a colour: give #rrggbb or #rgb values separated by "
                              "commas (the drawing's stroke colours), or none")
        out.add(item if len(item) == 7 else "#" + "".join(c * 2 for c in item[1:]))
    return frozenset(out)


def by_colour(pieces: Sequence[Piece], size: float, find_parts: FindParts,
              engrave: frozenset[str] | None = None) -> Any:
    """The sheet ``find_parts`` finds in ``pieces`` less those stroked in an ``engrave``
    colour; with ``engrave`` None, when a second stroke colour is engraving (module docs),
    the sheet of the other colour's pieces. Either is said in the warnings. Two imports of
    the drawing when it has exactly two colours and ``engrave`` is None, else one."""
    if engrave:
        return _named(pieces, find_parts, engrave)
    sheet = find_parts(pieces)
    if engrave is not None:
        return sheet
    counts = Counter(p.colour for p in pieces)
    if len(counts) != 2 or None in counts:
        return sheet
    (major, _), (minor, n_minor) = counts.most_common()
    cut = [p for p in pieces if p.colour == major]
    try:
        alone = find_parts(cut)
    except PartDocumentError:
        return sheet
    if len(sheet.parts) <= len(alone.parts) or not _on_material(alone, [p for p in pieces if p.colour == minor], size):
        return sheet
    alone.warnings.insert(0, f"{n_minor} entit{'y' if n_minor == 1 else 'ies'} stroked {minor} set aside as engraving: "
                             f"they lie on the parts cut in {major} and would carve {len(sheet.parts) - len(alone.parts)} "
                             f"more part(s) out of them (colour conventions differ between shops)")
    return alone


def _named(pieces: Sequence[Piece], find_parts: FindParts, engrave: frozenset[str]) -> Any:
    cut = [p for p in pieces if p.colour not in engrave]
    n = len(pieces) - len(cut)
    if not cut:
        raise PartDocumentError("engrave_colours", f"every entity is stroked in {', '.join(sorted(engrave))}: "
                                "nothing left to cut")
    sheet = find_parts(cut)
    shown = ", ".join(sorted({p.colour or "none" for p in pieces}))
    sheet.warnings.insert(0, f"{n} entit{'y' if n == 1 else 'ies'} stroked {', '.join(sorted(engrave))} set aside as "
                             f"engraving (engrave colours; the drawing's colours: {shown})")
    return sheet


def _on_material(sheet: Any, pieces: Sequence[Piece], size: float) -> bool:
    """Whether every sample point of ``pieces`` lies on or within the material of a part
    of ``sheet`` (outline less holes, widened by the gap tolerance). O(n log n)."""
    import shapely
    from shapely.geometry import Polygon

    if not sheet.parts:
        return False
    material = shapely.union_all([Polygon(ring(outline), [ring(h) for h in holes]).buffer(0)
                                  for outline, holes in sheet.parts]).buffer(GAP_MAX_REL * size)
    shapely.prepare(material)
    pts = [pt for p in pieces for pt in samples(p.segment)]
    return bool(pts) and bool(shapely.contains_xy(material, [x for x, _ in pts], [y for _, y in pts]).all())


def dxf_colour(e: Any) -> str | None:
    """The entity's colour as ``#rrggbb``: its true colour, else its ACI colour, BYLAYER
    looked up on its layer; None for BYBLOCK or an unknown layer."""
    from ezdxf.colors import aci2rgb, int2rgb

    if e.dxf.hasattr("true_color"):
        return _hex(int2rgb(e.dxf.true_color))
    aci = e.dxf.color
    if aci == 256 and e.doc is not None and e.doc.layers.has_entry(e.dxf.layer):
        layer = e.doc.layers.get(e.dxf.layer)
        if layer.dxf.hasattr("true_color"):
            return _hex(int2rgb(layer.dxf.true_color))
        aci = abs(layer.dxf.color)
    return _hex(aci2rgb(aci)) if 1 <= aci <= 255 else None


def _hex(rgb: Any) -> str:
    return "#" + "".join(f"{int(c):02x}" for c in rgb)
