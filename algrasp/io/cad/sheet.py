"""The parts on a drawing sheet (issue 17): several outlines on one layer, nested sheets,
clutter.

Pieces are cleaned (zero-length and duplicated entities dropped, with a warning), chained
into closed loops (open chains — centre lines, construction lines, dimension leftovers —
are set aside and reported), and the loops are nested by containment: a loop at even depth
is a part's outline, the loops directly inside it are its holes, and a loop inside a hole
is a part of its own (a nested sheet). Parts are numbered by decreasing area.

Drawings made for people hold more than the part: a frame with its title block (a
rectangle around everything, on a layer of its own) is set aside; so are section views
(hatched regions, when some parts are hatched and some are not) and engraving (loops on an
engraving/marking layer inside a part are not holes).
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from algrasp.errors import PartDocumentError
from algrasp.geometry.tolerances import ROUNDING, TINY
from algrasp.io.cad.chain import Piece, Segment, _polygon, chain, point_at, ring

_DUPLICATE_DIGITS = 9
"""End points rounded to this many significant digits of the drawing size when looking
for duplicated entities."""


@dataclass
class Sheet:
    """What a drawing holds: its parts (outline, holes) and what was set aside."""

    parts: list[tuple[list[Segment], list[list[Segment]]]]
    ignored: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    layers: list[str | None] = field(default_factory=list)

    def summary(self, units: str) -> dict[str, Any]:
        """``{"parts": [{"index", "layer", "bbox", "area", "holes", "segments"}], "ignored",
        "warnings"}``."""
        rows = []
        for k, (outline, holes) in enumerate(self.parts):
            poly = _polygon(outline)
            x0, y0, x1, y1 = poly.bounds
            area = poly.area - sum(_polygon(h).area for h in holes)
            layer = self.layers[k] if k < len(self.layers) else None
            rows.append({"index": k, "layer": layer, "bbox": [x0, y0, x1, y1], "area": float(area), "holes": len(holes),
                         "segments": len(outline), "units": units})
        return {"parts": rows, "ignored": list(self.ignored), "warnings": list(self.warnings)}


def clean(pieces: Sequence[Piece], size: float) -> tuple[list[Piece], list[str]]:
    """Drop zero-length and duplicated entities (the same end points, type and shape)."""
    out: list[Piece] = []
    seen: set[tuple[Any, ...]] = set()
    zero, dup = 0, 0
    scale = max(size, TINY)
    for p in pieces:
        a, b = point_at(p.segment, False), point_at(p.segment, True)
        if np.linalg.norm(b - a) <= ROUNDING * scale and p.segment["type"] == "line":
            zero += 1
            continue
        key = _key(p.segment, a, b, scale)
        if key in seen:
            dup += 1
            continue
        seen.add(key)
        out.append(p)
    notes = []
    if zero:
        notes.append(f"{zero} zero-length entit{'y' if zero == 1 else 'ies'} dropped")
    if dup:
        notes.append(f"{dup} duplicated entit{'y' if dup == 1 else 'ies'} dropped")
    return out, notes


def _key(seg: Segment, a: np.ndarray, b: np.ndarray, scale: float) -> tuple[Any, ...]:
    """Direction-free identity of a segment: its type, end points and shape parameters."""
    def r(v: Any) -> tuple[float, ...]:
        return tuple(np.round(np.ravel(np.asarray(v, dtype=float)) / scale, _DUPLICATE_DIGITS).tolist())

    ends = tuple(sorted([r(a), r(b)]))
    shape: tuple[Any, ...] = ()
    if seg["type"] == "bezier":
        shape = tuple(sorted(r(p) for p in seg["points"])) + tuple(sorted(seg.get("weights", [])))
    elif seg["type"] in ("arc", "ellipse_arc"):
        shape = r(seg["center"]) + r([seg.get("radius", 0.0), seg.get("rx", 0.0), seg.get("ry", 0.0)])
        shape += (round(abs(seg["end_deg"] - seg["start_deg"]), 9),)
    return (seg["type"], ends, shape)


ENGRAVING_LAYER = re.compile(r"engrav|etch|mark|scor|scrib|label|text|letter|logo|raster", re.IGNORECASE)
"""Layer names whose loops inside a part are engraving or marking, not holes."""


def find_parts(pieces: Sequence[Piece], tol: float, size: float,
               hatched: Sequence[tuple[float, float]] = ()) -> Sheet:
    """The parts of a drawing (see module docs); ``hatched`` holds one point inside each
    hatched region. Raises PartDocumentError when no closed contour is left (naming the
    first open one)."""
    kept, warnings = clean(pieces, size)
    ignored: list[str] = []
    loops = chain([Piece({**p.segment, "_layer": p.layer}, p.origin) for p in kept], tol, ignored)
    if not loops:
        if ignored:
            raise PartDocumentError("drawing", ignored[0])
        raise PartDocumentError("drawing", "no closed contour")
    if ignored:
        warnings.append(f"{len(ignored)} open chain(s) set aside (centre, construction or dimension lines?)")
    loops = _with_area(loops, ignored)
    loops = [_untangle(lp, warnings) for lp in loops]
    polys = [_polygon(lp) for lp in loops]
    order = sorted(range(len(loops)), key=lambda i: -polys[i].area)
    parent = {i: _parent(i, order, polys) for i in order}
    warnings += _overlaps(order, parent, polys)
    frames = [i for i in order if parent[i] is None and _is_frame(loops, i, parent)]
    ignored += [f"frame: the rectangle on layer {_layer(loops[f])!r} around the parts" for f in frames]
    for i in order:  # by decreasing area: a cell's parent is decided before the cell
        if parent[i] in frames and i not in frames and _layer(loops[i]) == _layer(loops[parent[i]]):  # type: ignore[index]
            frames.append(i)  # title block cells, however nested
            ignored.append(f"title block: a loop on the frame's layer {_layer(loops[i])!r}")
    for i in order:
        if parent[i] in frames:
            parent[i] = None
    depth: dict[int, int] = {}
    for i in order:
        depth[i] = 0 if parent[i] is None else depth[parent[i]] + 1  # type: ignore[index]
    outer = [i for i in order if i not in frames and depth[i] % 2 == 0]
    outer = _without_sections(outer, polys, hatched, ignored)
    engraved = _engraving(outer, order, parent, loops, ignored)
    parts = [(_strip(loops[i]), [_strip(loops[j]) for j in order if parent[j] == i and j not in engraved])
             for i in outer]
    return Sheet(parts, ignored, warnings, [_layer(loops[i]) for i in outer])


def _without_sections(outer: list[int], polys: list[Any], hatched: Sequence[tuple[float, float]],
                      ignored: list[str]) -> list[int]:
    """Set aside hatched parts (section views) when some parts are not hatched: a part to
    cut is drawn as an outline, a section through it is filled."""
    from shapely.geometry import Point

    marks = [Point(p) for p in hatched]
    filled = {i for i in outer if any(polys[i].covers(m) for m in marks)}
    if not filled or len(filled) == len(outer):
        return outer
    ignored += [f"section view: a hatched region of {len(polys[i].exterior.coords) - 1} vertices" for i in sorted(filled)]
    return [i for i in outer if i not in filled]


def _engraving(outer: list[int], order: list[int], parent: dict[int, int | None], loops: list[list[Segment]],
               ignored: list[str]) -> set[int]:
    """Loops directly inside a part, on an engraving or marking layer other than the part's:
    not holes."""
    out = set()
    for i in outer:
        for j in order:
            name = _layer(loops[j])
            if parent[j] == i and name != _layer(loops[i]) and name and ENGRAVING_LAYER.search(name):
                out.add(j)
    if out:
        ignored.append(f"engraving: {len(out)} loop(s) on marking layers inside parts (not holes)")
    return out


KERF_AREA_REL = 0.01
"""A self-intersecting loop whose stray lobes (kerf loops, overshoots) hold less than this
share of its area is resolved to the region it bounds."""


def _with_area(loops: list[list[Segment]], ignored: list[str]) -> list[list[Segment]]:
    """The loops that bound an area; a loop of fewer than 3 distinct points (a segment
    shorter than the chaining tolerance closes on itself) or of no area is set aside, said.
    Raises PartDocumentError when none is left."""
    from shapely.geometry import Polygon

    kept = [lp for lp in loops if len(np.unique(pts := ring(lp), axis=0)) >= 3 and Polygon(pts).buffer(0).area > 0]
    if len(kept) < len(loops):
        ignored.append(f"{len(loops) - len(kept)} degenerate loop(s) set aside (no area: a segment shorter than the "
                       "chaining tolerance, or a loop that folds back on itself)")
    if not kept:
        raise PartDocumentError("drawing", "no closed contour with an area")
    return kept


def _untangle(loop: list[Segment], warnings: list[str]) -> list[Segment]:
    """A loop with tiny self-intersections becomes the outline of the region it bounds (as
    a polyline through its points: the exact curves of that one loop are given up, and
    said); any other loop is returned as it is (the part's validation names the crossing)."""
    import shapely
    from shapely.geometry import Polygon

    pts = ring(loop)
    raw = Polygon(pts)
    if raw.is_valid or len(pts) < 4:
        return loop
    region = shapely.make_valid(raw)
    pieces = [g for g in getattr(region, "geoms", [region]) if g.geom_type == "Polygon"]
    if not pieces:
        return loop
    main = max(pieces, key=lambda g: g.area)
    stray = sum(g.area for g in pieces) - main.area + abs(abs(raw.area) - main.area)
    if stray > KERF_AREA_REL * main.area:
        return loop
    edge_pts = np.asarray(main.exterior.coords)
    warnings.append(f"a loop of {len(loop)} segments crossed itself (kerf loop or overshoot): resolved to the "
                    f"region it bounds, as a {len(edge_pts) - 1}-edge polyline")
    layer = loop[0].get("_layer")
    return [{"type": "line", "start": [float(a[0]), float(a[1])], "end": [float(b[0]), float(b[1])], "_layer": layer}
            for a, b in zip(edge_pts[:-1], edge_pts[1:]) if np.hypot(*(b - a)) > 0.0]


def _parent(i: int, order: list[int], polys: list[Any]) -> int | None:
    """The smallest loop that wholly contains loop i."""
    inside = [j for j in order if j != i and polys[j].area > polys[i].area and polys[j].contains(polys[i])]
    return inside[-1] if inside else None


def _overlaps(order: list[int], parent: dict[int, int | None], polys: list[Any]) -> list[str]:
    """Sibling loops whose areas cross (neither contains the other)."""
    out = []
    for n, i in enumerate(order):
        for j in order[n + 1:]:
            if parent[i] == parent[j] and polys[i].intersects(polys[j]) and polys[i].intersection(polys[j]).area > 0.0:
                out.append(f"overlapping loops: loops {i} and {j} cross (several parts drawn over each other?)")
    return out[:10]


def _layer(loop: list[Segment]) -> str | None:
    return loop[0].get("_layer")


def _is_frame(loops: list[list[Segment]], i: int, parent: dict[int, int | None]) -> bool:
    """A drawing frame: an axis-aligned rectangle around other loops on other layers (a
    plate with holes has its holes on its own layer); loops inside it on its own layer
    are its title block."""
    loop = loops[i]
    children = [j for j, p in parent.items() if p == i]
    if len(loop) != 4 or not children or any(s["type"] != "line" for s in loop):
        return False
    if not all(s["start"][0] == s["end"][0] or s["start"][1] == s["end"][1] for s in loop):
        return False
    return _layer(loop) is not None and any(_layer(loops[j]) != _layer(loop) for j in children)


def _strip(loop: list[Segment]) -> list[Segment]:
    return [{k: v for k, v in s.items() if k != "_layer"} for s in loop]
