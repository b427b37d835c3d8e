"""What a drawing made for people holds beside the parts: frames and title blocks, other
views of the same part, engraving. Each rule looks at the loops' shapes and nesting and at
the drawing's marks (hatches, text), never at one layer name alone; layer names are a
hint, read in any language.

- **Frame**: a component whose outer boundary is an axis-aligned rectangle around other
  loops, with something that says "sheet": cells (a title block drawn onto it), text
  inside it, loops on other layers, parts that have holes of their own, parts that fill
  over half of it, or a frame-like layer name. Its cells holding text (or on its own
  layer, when the parts are on another) are the title block; other cells are parts cut
  along the border.
- **Views** of one part (plan, elevations, sections, pictorial) are recognised in
  `algrasp.io.cad.views`.
- **Engraving**: loops inside a part on a marking layer, filled by a hatch, or a row of
  small, different, non-circular loops (letters).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from algrasp.geometry.tolerances import ROUNDING
from algrasp.io.cad.chain import Segment

ENGRAVING_LAYER = re.compile(
    r"engrav|etch|mark|scor|scrib|label|text|letter|logo|raster|gravur|beschrift|schrift|grav|marqu|texte|grabad|"
    r"marcad|rotul|incisi|marcatur|testo|scritt|gravaç|marcaç|graveer|tekst|grawer|znakow|napis|gravyr|märk|popis|"
    r"гравир|маркир|текст|надпис|彫刻|刻印|マーキング|文字|テキスト|ロゴ|雕刻|刻字|打标|标记|标识|각인|조각|마킹|텍스트",
    re.IGNORECASE)
"""Layer names (English, German, French, Spanish, Italian, Portuguese, Dutch, Polish,
Swedish, Czech, Russian, Japanese, Chinese, Korean) of engraving, marking and text."""
FRAME_LAYER = re.compile(
    r"border|frame|title|rahmen|schriftfeld|cadre|cartouche|marco|cajet|cornice|cartiglio|moldura|kader|ramka|"
    r"рамк|штамп|枠|表題|图框|标题栏|도곽|표제", re.IGNORECASE)
"""Layer names of drawing frames and title blocks, in the same languages."""
COPY_AREA_REL = 1e-2
"""Loops whose areas agree to this share (and hole counts too) are copies of one part (a
nesting row), not views of it."""
NEARLY_BOX = 0.975
"""Axis-aligned outlines filling this share of their box count as rectangles (frames)."""
FILL_SHARE = 0.5
"""Parts filling over this share of a rectangle around them make it a sheet border."""
TABLE_MIN_CELLS = 3
"""A grid of at least this many cells with text in them is a table (hole table, title block)."""
GLYPH_AREA_REL = 5e-3
"""A letter engraved in a part has less than this share of the part's area."""
CAPITAL_HEIGHT = 1.5
"""A loop with counters beside a line of letters, up to this many times their (median)
height, is a letter too (a capital "O" or "D" before lower-case letters: cap height is
about 1.4 x-heights)."""
GLYPH_MIN = 4
"""At least this many small, different, non-circular loops make a line of text."""
GLYPH_VARIETY = 0.3
"""The least share of different shapes among the loops of a line of text."""
GLYPH_SPREAD = 4.0
"""A line (or a few lines) of text covers at most this many times its letters' boxes."""


@dataclass(frozen=True)
class Marks:
    """What a drawing says beside its geometry: one point inside each hatched region, the
    text (insertion point, content), whether it is annotated (dimensions), and the points
    its dimensions measure."""

    hatched: Sequence[tuple[float, float]] = ()
    texts: Sequence[tuple[float, float, str]] = ()
    annotated: bool = False
    measured: Sequence[tuple[float, float]] = ()


NO_MARKS = Marks()


@dataclass
class Loops:
    """The loops of a sheet with what the rules need: polygons, containment parent,
    component (of the arrangement) and layer of each."""

    loops: list[list[Segment]]
    polys: list[Any]
    parent: dict[int, int | None]
    component: list[int]
    outer: dict[int, list[Segment]]
    order: list[int] = field(default_factory=list)
    neighbours: dict[int, set[int]] = field(default_factory=dict)
    """The loops sharing an edge with each loop (faces of one arrangement component)."""

    def layer(self, i: int) -> str | None:
        return self.loops[i][0].get("_layer")

    def children(self, i: int) -> list[int]:
        return [j for j in self.order if self.parent[j] == i]


def _is_rectangle(loop: list[Segment], size: float) -> bool:
    """Axis-aligned lines with four corners (collinear runs merged)."""
    if any(s["type"] != "line" for s in loop):
        return False
    tol = ROUNDING * max(size, 1.0) * 1e3
    dirs: list[tuple[int, int]] = []
    for s in loop:
        dx, dy = np.subtract(s["end"], s["start"])
        if abs(dx) > tol and abs(dy) > tol:
            return False
        d = (int(np.sign(dx)) if abs(dx) > tol else 0, int(np.sign(dy)) if abs(dy) > tol else 0)
        if d != (0, 0) and (not dirs or dirs[-1] != d):
            dirs.append(d)
    if len(dirs) > 1 and dirs[0] == dirs[-1]:
        dirs.pop()
    return len(dirs) == 4 or _nearly_box(loop)


def _nearly_box(loop: list[Segment]) -> bool:
    """Axis-aligned lines filling their box but for a nick: a border whose offset lines
    cross at a corner (a 2 mm square hanging off it)."""
    from shapely.geometry import Polygon

    poly = Polygon([s["start"] for s in loop]).buffer(0)
    return bool(poly.area >= NEARLY_BOX * poly.envelope.area) if poly.area > 0 else False


def _texts_in(poly: Any, marks: Marks) -> list[str]:
    from shapely.geometry import Point

    return [t for x, y, t in marks.texts if poly.covers(Point(x, y))]


def _components(lp: Loops) -> dict[int, list[int]]:
    """The faces of each connected component, largest first (``lp.order`` is by area)."""
    by_comp: dict[int, list[int]] = {}
    for i in lp.order:
        by_comp.setdefault(lp.component[i], []).append(i)
    return by_comp


def frames(lp: Loops, marks: Marks, size: float) -> tuple[set[int], list[str]]:
    """The loops that are frames or title-block cells, and what was said about them."""
    out: set[int] = set()
    said: list[str] = []
    by_comp = _components(lp)
    for c, faces in by_comp.items():
        main = faces[0]  # the largest face of the component (order is by decreasing area)
        if lp.parent[main] is not None or c not in lp.outer or not _is_rectangle(lp.outer[c], size):
            continue
        inside = lp.children(main)
        reason = _frame_reason(lp, main, faces, inside, marks)
        if reason is None:
            continue
        out.add(main)
        said.append(f"frame: the rectangle on layer {lp.layer(main)!r} around the parts ({reason})")
        other_layers = any(lp.layer(j) != lp.layer(main) and not ENGRAVING_LAYER.search(lp.layer(j) or "")
                           for j in inside)
        titled = any(_texts_in(lp.polys[j], marks) for j in faces[1:])  # a title block: all its cells are
        cells = [j for j in faces[1:] if titled or (other_layers and lp.layer(j) == lp.layer(main))]
        # title-block boxes drawn on their own, on the frame's layer
        boxes = [j for j in lp.order if other_layers and lp.parent.get(j) == main and lp.layer(j) == lp.layer(main)
                 and j not in cells]
        out |= set(cells) | set(boxes)
        said += _per_layer(lp, cells, "cell(s) of the frame") + _per_layer(lp, boxes, "loop(s) on the frame's layer")
    return out, said


def _per_layer(lp: Loops, loops: list[int], what: str) -> list[str]:
    """One line per layer: "title block: N <what> on layer L"."""
    count: dict[str | None, int] = {}
    for j in loops:
        count[lp.layer(j)] = count.get(lp.layer(j), 0) + 1
    return [f"title block: {n} {what} on layer {name!r}" for name, n in count.items()]


def tables(lp: Loops, marks: Marks, size: float) -> tuple[set[int], list[str]]:
    """The cells of tables drawn anywhere on the sheet (a hole table, a revision block, a
    title block inside its frame): a component of TABLE_MIN_CELLS or more faces holding no
    loops of their own, around which its outer boundary is a rectangle, with text in at
    least half of them. A part is never a grid of empty rectangles with writing in them."""
    out: set[int] = set()
    said: list[str] = []
    by_comp = _components(lp)
    for c, cells in by_comp.items():
        if len(cells) < TABLE_MIN_CELLS or c not in lp.outer or any(lp.children(j) for j in cells):
            continue
        written = sum(bool(_texts_in(lp.polys[j], marks)) for j in cells)
        if 2 * written >= len(cells) and _is_rectangle(lp.outer[c], size):
            out |= set(cells)
            said.append(f"table: {len(cells)} cells with text in {written} (a hole table or title block), not parts")
    return out, said


def _frame_reason(lp: Loops, main: int, faces: list[int], inside: list[int], marks: Marks) -> str | None:
    if not inside and len(faces) < 2:
        return None
    name = lp.layer(main) or ""
    poly = lp.polys[main]
    from shapely.geometry import Point

    # letters drawn as outlines are no parts: the rules below look at the rest
    inside = [j for j in inside if j not in glyph_row(lp, [k for k in inside if lp.polys[k].area < 0.05 * poly.area])]
    spots = [Point(x, y) for x, y, _ in marks.texts]
    loose_text = [p for p in spots if poly.covers(p) and not any(lp.polys[j].covers(p) for j in inside)]
    checks = [
        (len(faces) > 1 and any(_texts_in(lp.polys[j], marks) for j in faces[1:]), "a title block"),
        (any(lp.layer(j) != lp.layer(main) and not ENGRAVING_LAYER.search(lp.layer(j) or "") for j in inside),
         "loops on other layers inside"),
        (bool(inside) and bool(loose_text) and len(inside) >= 2, "text beside the parts"),
        # (letters with counters inside a plate are no such parts: they are far smaller)
        (any(lp.children(j) and lp.polys[j].area >= GLYPH_AREA_REL * poly.area for j in inside),
         "parts with holes of their own inside"),
        (len(inside) >= 2 and sum(lp.polys[j].area for j in inside) > FILL_SHARE * poly.area
         and not _cutouts(lp, inside), "parts filling it"),
        (bool(inside) and bool(FRAME_LAYER.search(name)), f"layer {name!r}"),
        (len(faces) > 2 and bool(inside), "cells along it"),
    ]
    return next((why for ok, why in checks if ok), None)


def _cutouts(lp: Loops, inside: list[int]) -> bool:
    """Loops that look cut out of a plate, not parts nested on a sheet: no holes of their
    own, and nearly all of a few repeated shapes (switch cut-outs of a keyboard plate,
    a grille)."""
    if any(lp.children(j) for j in inside):
        return False
    shapes: dict[tuple[int, ...], int] = {}
    for j in inside:
        shapes[_shape(lp.polys[j])] = shapes.get(_shape(lp.polys[j]), 0) + 1
    return sum(n for n in shapes.values() if n >= 3) >= 0.6 * len(inside)


def engraving(lp: Loops, part: int, marks: Marks) -> tuple[set[int], list[str]]:
    """The loops directly inside ``part`` that are engraving, not holes."""
    from shapely.geometry import Point

    kids = lp.children(part)
    by_layer = {j for j in kids if (name := lp.layer(j)) and name != lp.layer(part) and ENGRAVING_LAYER.search(name)}
    filled = {j for j in kids if any(lp.polys[j].covers(Point(p)) for p in marks.hatched)}
    glyphs = _glyphs(lp, part, kids)
    out = by_layer | filled | glyphs
    said = []
    for found, why in ((by_layer, "on marking layers"), (filled, "filled by a hatch"), (glyphs, "a line of letters")):
        if found:
            said.append(f"engraving: {len(found)} loop(s) inside a part ({why}): not holes")
    return out, said


def _glyphs(lp: Loops, part: int, kids: list[int]) -> set[int]:
    """The loops of ``kids`` that are small against ``part`` and form a line of engraved
    letters (:func:`glyph_row`)."""
    area = lp.polys[part].area
    small = [j for j in kids if lp.polys[j].area < GLYPH_AREA_REL * area and not _round(lp.loops[j])]
    letters = glyph_row(lp, small)
    if not letters or _interlaced(lp, letters, [j for j in kids if j not in letters]):
        return set()
    # capitals with counters ("O", "D") beside the row, or beside such a capital: larger
    # than the small letters
    countered = [j for j in kids if lp.children(j) and not _round(lp.loops[j])]
    while more := _beside(lp, letters, [j for j in countered if j not in letters], CAPITAL_HEIGHT):
        letters |= more
    return letters


def _interlaced(lp: Loops, letters: set[int], others: list[int]) -> bool:
    """Whether larger cut-outs weave through ``letters``: a loop over INTERLACE_AREA times
    the largest of them with over INTERLACE_SHARE of its area within half a letter height
    of them. Fretwork (a Celtic knot's bands around its small pieces) is; text is not
    (a line of letters stands clear of the part's holes)."""
    from shapely.geometry import box
    from shapely.ops import unary_union

    h = float(np.median([lp.polys[j].bounds[3] - lp.polys[j].bounds[1] for j in letters]))
    largest = max(lp.polys[j].area for j in letters)
    zone = unary_union([box(*lp.polys[j].bounds).buffer(h / 2) for j in letters])
    return any(lp.polys[j].area > INTERLACE_AREA * largest
               and zone.intersection(lp.polys[j]).area > INTERLACE_SHARE * lp.polys[j].area for j in others)


INTERLACE_AREA = 2.0
INTERLACE_SHARE = 0.3
"""A cut-out over INTERLACE_AREA times the largest "letter" with over INTERLACE_SHARE of
its area within half a letter height of them makes them fretwork, not text (in the shop
corpus: the moodlamp knot's bands 48–69 %; beside real text at most 20 %, a capital "D"
of the hangprinter's "ODrive")."""


def glyph_row(lp: Loops, small: list[int]) -> set[int]:
    """Non-circular loops of similar heights with varied shapes: a line of letters. A row
    of mostly equal shapes (a grille of slots, switch cut-outs, a bolt pattern, copies on a
    sheet) is machined features: a line of text has at least three different shapes, and
    at least GLYPH_VARIETY of its loops differ ("100x100mm": 4 shapes in 9 letters)."""
    out: set[int] = set()
    for band in _by_height(lp, small):
        for row in _words(lp, band):
            shapes = {_shape(lp.polys[j]) for j in row}
            if len(row) >= GLYPH_MIN and len(shapes) >= 3 and len(shapes) >= GLYPH_VARIETY * len(row) \
                    and _compact(lp, row):
                out |= set(row)
    return out | _beside(lp, out, small, 1.0) if out else out


def _beside(lp: Loops, letters: set[int], small: list[int], tallest: float) -> set[int]:
    """The loops of ``small`` at most ``tallest`` times the letters' height that reach
    within half a letter height of them: punctuation, dots and dashes (an "=" before a
    word), or capitals beside lower-case letters, are text too."""
    from shapely.geometry import box
    from shapely.ops import unary_union

    def height(j: int) -> float:
        return float(lp.polys[j].bounds[3] - lp.polys[j].bounds[1])

    h = float(np.median([height(j) for j in letters]))
    area = unary_union([box(*lp.polys[j].bounds).buffer(h / 2) for j in letters])
    return {j for j in small if height(j) <= tallest * h and area.intersects(box(*lp.polys[j].bounds))}


def _words(lp: Loops, band: list[int]) -> list[list[int]]:
    """``band`` in groups of loops standing within one letter height of each other."""
    from shapely.geometry import box

    if len(band) < GLYPH_MIN:
        return []
    h = float(np.median([lp.polys[j].bounds[3] - lp.polys[j].bounds[1] for j in band]))
    boxes = {j: box(*lp.polys[j].bounds) for j in band}
    return groups(band, lambda a, b: boxes[a].distance(boxes[b]) <= h)


def groups(items: list[int], linked: Callable[[int, int], bool]) -> list[list[int]]:
    """``items`` in the groups that ``linked`` pairs join (transitively: union-find), each
    in the order of ``items``, the groups in the order of their first member. O(n²) calls."""
    group = {i: i for i in items}

    def root(i: int) -> int:
        while group[i] != i:
            i = group[i]
        return i

    for n, a in enumerate(items):
        for b in items[n + 1:]:
            if linked(a, b):
                group[root(b)] = root(a)
    out: dict[int, list[int]] = {}
    for i in items:
        out.setdefault(root(i), []).append(i)
    return list(out.values())


def _compact(lp: Loops, row: list[int]) -> bool:
    """Letters stand close together: the hull of the row is at most GLYPH_SPREAD times the
    area of their boxes (slots spread over a part are not a word)."""
    from shapely.geometry import box
    from shapely.ops import unary_union

    boxes = [box(*lp.polys[j].bounds) for j in row]
    return bool(unary_union(boxes).convex_hull.area <= GLYPH_SPREAD * sum(b.area for b in boxes))


def _by_height(lp: Loops, loops: list[int]) -> list[list[int]]:
    """``loops`` in bands of similar height (a gap of 1.5× between bands): letters of one
    size apart from a grille of taller slots."""
    ranked = sorted(loops, key=lambda j: lp.polys[j].bounds[3] - lp.polys[j].bounds[1])
    bands: list[list[int]] = []
    last = 0.0
    for j in ranked:
        h = lp.polys[j].bounds[3] - lp.polys[j].bounds[1]
        if not bands or h > 1.5 * last:
            bands.append([])
        bands[-1].append(j)
        last = h
    return bands


def _shape(poly: Any) -> tuple[int, int, int, int]:
    """A loop's shape and size up to position, to about 1 %: drawn copies whose joints
    miss by a hair (a keyboard plate's switch cut-outs) are one shape."""
    x0, y0, x1, y1 = poly.bounds
    size = max(x1 - x0, y1 - y0, ROUNDING)
    unit = size / 100.0
    return (round(50.0 * math.log(size)), round((x1 - x0) / unit), round((y1 - y0) / unit),
            round(poly.area / (unit * unit * 100.0)))


def _round(loop: list[Segment]) -> bool:
    """A drilled hole: one full circle, or arcs of one circle."""
    if not all(s["type"] == "arc" for s in loop):
        return False
    scale = max(float(loop[0]["radius"]), ROUNDING)
    circles = {(round(s["radius"] / scale, 6), round(s["center"][0] / scale, 6), round(s["center"][1] / scale, 6))
               for s in loop}
    return len(circles) == 1
