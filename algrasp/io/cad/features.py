"""Drawn features that are not cuts of their own: a counterbore or thread drawn as a second
circle around a drilled hole, letters and hairlines beside the parts.

Rules on the loops of a sheet (:class:`~algrasp.io.cad.clutter.Loops`), by geometry:

- **Counterbores**: a round hole holding one concentric round loop with nothing inside it
  is a counterbore, spot face or thread drawn around the through hole: the hole is the
  inner circle (a slug is never drawn, so the inner disc is no part).
- **Drilled slugs**: a small round loop inside a hole (fixturing holes drilled in the
  cut-out's slug) is no part nested in it.
- **Pockets**: a loop on a pocket layer (``pcb_pocket``) is machined part-way: no hole;
  the holes inside it are the part's.
- **Letters with counters**: a small hole holding loops of its own is an engraved letter.
- **Loose letters**: loops outside every part (or in a part's window), each under
  GLYPH_AREA_REL of the largest part, forming a line of letters (:func:`~algrasp.io.cad.clutter.glyph_row`) or filled by
  a hatch, are text (an annotation written as outlines), not parts.
- **Not measured**: in a drawing with dimensions, a small loop outside the parts that no
  dimension measures and that copies no measured part (a logo, symbols, a title block's
  drawing) is not a part.
- **Notches and slivers**: a loop without holes that shares an edge with a part over
  1/NOTCH_AREA_REL times its area is no part: a cut-out drawn as a closed loop across the
  outline (a notch), the void between two plates drawn edge to edge where one has a notch
  on the common edge, a corner reference line closing a sliver against a fillet.
  Neighbouring parts of a common-line nesting sheet are of comparable sizes.
- **Hairlines**: a "part" over SLIVER_ASPECT times longer than wide is a line drawn as a
  closed outline (dimension and leader lines, a border stroke), not something to grasp.
"""

from __future__ import annotations

import math
import re
from typing import Any

from algrasp.io.cad.clutter import COPY_AREA_REL, GLYPH_AREA_REL, Loops, Marks, _round, glyph_row

CONCENTRIC_REL = 1e-3
"""Two circles are concentric when their centres are this share of the larger radius apart."""
BARE_AREA_REL = 0.05
"""An unmeasured loop under this share of the largest measured part is no part (copies of
a measured part, dimensioned once, stay parts)."""
NOTCH_AREA_REL = 0.03
"""A loop without holes sharing an edge with a part over 1/this times its area is a notch
or sliver of that part, not a part of its own."""
SLIVER_ASPECT = 200.0
"""A loop this many times longer than wide is a line drawn closed."""


def counterbore(lp: Loops, hole: int) -> int | None:
    """The through hole drawn inside the round ``hole`` (see module docs), or None."""
    kids = lp.children(hole)
    if len(kids) != 1 or lp.children(kids[0]):
        return None
    outer, inner = _disc(lp, hole), _disc(lp, kids[0])
    if outer is None or inner is None:
        return None
    (xa, ya), ra = outer
    (xb, yb), rb = inner
    return kids[0] if ((xa - xb) ** 2 + (ya - yb) ** 2) ** 0.5 <= CONCENTRIC_REL * max(ra, rb) else None


DISC_REL = 0.01
"""A loop whose box is square and whose area is that of the circle in it, both to this
share, is a circle drawn as a spline or polygon (its centre the box's)."""


def _disc(lp: Loops, i: int) -> tuple[tuple[float, float], float] | None:
    """Loop i's centre and radius when it is a circle: arcs of one circle, or a closed
    spline or tessellation as round as one (DISC_REL); else None."""
    if _round(lp.loops[i]):
        return _circle(lp.loops[i])
    x0, y0, x1, y1 = lp.polys[i].bounds
    r = (x1 - x0 + y1 - y0) / 4
    if r <= 0 or abs((x1 - x0) - (y1 - y0)) > DISC_REL * 2 * r or abs(lp.polys[i].area / (math.pi * r * r) - 1) > DISC_REL:
        return None
    return ((x0 + x1) / 2, (y0 + y1) / 2), r


SLUG_DRILL_REL = 0.01
"""A round loop without holes, inside a hole and under this share of its area, is drilled
into the hole's slug (fixturing, a pilot for the saw), not a part nested in the hole."""


def slug_drill(lp: Loops, loop: int, hole: int) -> bool:
    """Whether ``loop``, directly inside ``hole``, is a drilling in the hole's slug: a
    round loop with nothing inside it, far smaller than the hole (nobody nests a bare
    disc of 1 % of a cut-out in it to grasp)."""
    return (_disc(lp, loop) is not None and not lp.children(loop)
            and lp.polys[loop].area < SLUG_DRILL_REL * lp.polys[hole].area)


POCKET_LAYER = re.compile(r"pocket|tasche|poche|bolsillo|tasca|ポケット|cavity|recess|blind", re.IGNORECASE)
"""Layers of blind pockets (CAM: machined part-way, not through): the pocket is no hole;
the holes drawn inside it are the part's."""


def pocket(lp: Loops, hole: int) -> bool:
    """Whether ``hole`` is a blind pocket (on a pocket layer, the part on another)."""
    name = lp.layer(hole) or ""
    parent = lp.parent[hole]
    return bool(POCKET_LAYER.search(name)) and parent is not None and lp.layer(parent) != name


def letter(lp: Loops, hole: int, part: int) -> bool:
    """Whether ``hole`` is a letter engraved in ``part``: small against the part (under
    GLYPH_AREA_REL of it) with loops of its own inside (its counters) — nobody nests a part
    in a hole that small."""
    return bool(lp.children(hole)) and lp.polys[hole].area < GLYPH_AREA_REL * lp.polys[part].area


def _circle(loop: list[Any]) -> tuple[tuple[float, float], float]:
    return (float(loop[0]["center"][0]), float(loop[0]["center"][1])), float(loop[0]["radius"])


def loose_marks(lp: Loops, parts: list[int], marks: Marks) -> tuple[set[int], list[str]]:
    """The top-level ``parts`` that are letters or hairlines (see module docs), and what
    was set aside, said."""
    from shapely.geometry import Point

    if not parts:
        return set(), []
    largest = max(lp.polys[i].area for i in parts)
    small = [i for i in parts if lp.polys[i].area < GLYPH_AREA_REL * largest]
    letters = glyph_row(lp, [i for i in small if not _round(lp.loops[i])])
    filled = {i for i in small if any(lp.polys[i].covers(Point(p)) for p in marks.hatched)}
    hairlines = {i for i in parts if _aspect(lp.polys[i]) > SLIVER_ASPECT}
    measured = {i for i in parts if lp.parent[i] is None and _measured(lp.polys[i], marks)}
    top = max((lp.polys[i].area for i in measured), default=0.0)
    bare = {i for i in parts if lp.parent[i] is None and i not in measured and lp.polys[i].area < BARE_AREA_REL * top
            and not any(abs(lp.polys[i].area - lp.polys[j].area) <= COPY_AREA_REL * lp.polys[j].area for j in measured)}
    said = []
    for found, why in ((letters, "a line of letters"), (filled - letters, "filled by a hatch"),
                       (hairlines, "hairlines: lines drawn as closed outlines"),
                       (bare - letters - filled - hairlines, "no dimension measures them, in a dimensioned "
                        "drawing: logo, symbols or title-block drawing")):
        if found:
            said.append(f"text and marks: {len(found)} loop(s) outside the parts ({why}): not parts")
    return letters | filled | hairlines | bare, said


def _measured(poly: Any, marks: Marks) -> bool:
    """Whether a dimension measures a point of ``poly`` (within 1 % of its size)."""
    from shapely.geometry import Point

    if not marks.measured:
        return False
    x0, y0, x1, y1 = poly.bounds
    pad = 0.01 * max(x1 - x0, y1 - y0)
    return any(x0 - pad <= x <= x1 + pad and y0 - pad <= y <= y1 + pad and poly.distance(Point(x, y)) <= pad
               for x, y in marks.measured)


def _aspect(poly: Any) -> float:
    x0, y0, x1, y1 = poly.bounds
    short = min(x1 - x0, y1 - y0)
    return float("inf") if short <= 0 else max(x1 - x0, y1 - y0) / short


def notches(lp: Loops, parts: list[int], holes: dict[int, list[int]]) -> tuple[set[int], list[str]]:
    """The ``parts`` that are notches or slivers of a neighbouring part, or cut-outs drawn
    across its outline (see module docs)."""
    chosen = set(parts)
    out = {i for i in parts if not holes[i] and any(
        j in chosen and lp.polys[i].area < NOTCH_AREA_REL * lp.polys[j].area for j in lp.neighbours.get(i, ()))}
    out |= _across(lp, [i for i in parts if i not in out])
    if not out:
        return out, []
    return out, [f"notches: {len(out)} loop(s) sharing an edge with a part over {1 / NOTCH_AREA_REL:.0f} times larger, "
                 "or drawn across its outline (a cut-out, a void or sliver beside it): not parts"]


def _across(lp: Loops, parts: list[int]) -> set[int]:
    """The ``parts`` lying mostly (over half their area) inside a part over
    1/NOTCH_AREA_REL times larger, crossing its outline: a hole drawn breaking through the
    edge (into a finger joint's notch), which the arrangement does not split."""
    from shapely.strtree import STRtree

    if len(parts) < 2:
        return set()
    tree = STRtree([lp.polys[i] for i in parts])
    out = set()
    for a, b in zip(*(v.tolist() for v in tree.query([lp.polys[i] for i in parts], predicate="intersects"))):
        small, big = lp.polys[parts[a]], lp.polys[parts[b]]
        if small.area < NOTCH_AREA_REL * big.area and not big.contains(small) \
                and small.intersection(big).area > 0.5 * small.area:
            out.add(parts[a])
    return out
