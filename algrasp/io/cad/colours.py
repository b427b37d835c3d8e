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
and stays a part. The decision is said in the warnings.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable, Sequence
from typing import Any

from algrasp.errors import PartDocumentError
from algrasp.io.cad.arrange import GAP_MAX_REL
from algrasp.io.cad.chain import Piece, ring, samples

FindParts = Callable[[Sequence[Piece]], Any]


def by_colour(pieces: Sequence[Piece], size: float, find_parts: FindParts) -> Any:
    """The sheet ``find_parts`` finds in ``pieces``, or, when a second stroke colour is
    engraving (module docs), the sheet of the other colour's pieces with that said in its
    warnings. Two imports of the drawing when it has exactly two colours, else one."""
    sheet = find_parts(pieces)
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
