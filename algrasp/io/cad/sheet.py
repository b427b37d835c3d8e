"""The parts on a drawing sheet: several outlines on one layer, nested sheets, shared cut
lines, clutter.

Zero-length lines are dropped; the rest become a planar arrangement
(`algrasp.io.cad.arrange`: shared stretches split, duplicates merged, small gaps closed,
open chains set aside) whose bounded faces are the loops. Loops are nested by containment:
a loop at even depth is a part's outline, the loops directly inside it are its holes, and
a loop inside a hole is a part of its own (a nested sheet). Frames and title blocks, other
views of a part and engraving are recognised and set aside (`algrasp.io.cad.clutter`).
Parts are numbered by decreasing area.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from algrasp.errors import PartDocumentError
from algrasp.geometry.tolerances import ROUNDING, TINY
from algrasp.io.cad.arrange import arrange
from algrasp.io.cad.centre_marks import drop_centre_marks
from algrasp.io.cad.chain import Piece, Segment, _polygon, point_at, ring
from algrasp.io.cad.clutter import NO_MARKS, Loops, Marks, engraving, frames, tables
from algrasp.io.cad.features import counterbore, letter, loose_marks, notches, pocket, slug_drill
from algrasp.io.cad.views import find_views


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


def drop_zero_length(pieces: Sequence[Piece], size: float) -> tuple[list[Piece], list[str]]:
    """Drop lines of no length (duplicates are found by the arrangement, by geometry)."""
    scale = max(size, TINY)
    out = [p for p in pieces if p.segment["type"] != "line"
           or np.linalg.norm(point_at(p.segment, True) - point_at(p.segment, False)) > ROUNDING * scale]
    zero = len(pieces) - len(out)
    return out, [f"{zero} zero-length entit{'y' if zero == 1 else 'ies'} dropped"] if zero else []


def find_parts(pieces: Sequence[Piece], size: float, tolerance: float | None = None, marks: Marks = NO_MARKS) -> Sheet:
    """The parts of a drawing (see module docs); ``size`` is the drawing's extent,
    ``tolerance`` (drawing units) overrides the join and gap tolerances. Raises
    PartDocumentError when no closed contour is left (naming the first open one)."""
    kept, warnings = drop_zero_length(pieces, size)
    kept, said = drop_centre_marks(kept)
    warnings += said
    arr = arrange(kept, size, tolerance)
    warnings += arr.notes
    ignored = list(arr.open_chains)
    if not arr.faces:
        raise PartDocumentError("drawing", ignored[0] if ignored else "no closed contour")
    if ignored:
        warnings.append(f"{len(ignored)} open chain(s) set aside (centre, construction or dimension lines?)")
    loops = [_untangle(lp, warnings) for lp in arr.faces]
    polys = [_polygon(lp) for lp in loops]
    order = sorted((i for i in range(len(loops)) if polys[i].area > 0.0), key=lambda i: -polys[i].area)
    if not order:
        raise PartDocumentError("drawing", "no closed contour with an area")
    parent = {i: _parent(i, order, polys) for i in order}
    lp = Loops(loops, polys, parent, arr.component, arr.outer, order, arr.neighbours)
    framed, said = frames(lp, marks, size)
    ignored += said
    tabled, said = tables(lp, marks, size)
    framed, ignored = framed | tabled, ignored + said
    for i in order:
        if parent[i] in framed:
            parent[i] = None
    order = [i for i in order if i not in framed]
    return _nest(lp, order, marks, ignored, warnings)


def _nest(lp: Loops, order: list[int], marks: Marks, ignored: list[str], warnings: list[str]) -> Sheet:
    """Parts at even depth, their holes the loops directly inside; engraving (and all it
    holds) is neither; other views of a part, loose marks and notches are set aside."""
    lp.order = order
    parts, dropped = _by_depth(lp, order, marks, ignored)
    holes = {i: [j for j in lp.children(i) if j not in dropped] for i in parts}
    found = find_views(lp, parts, {i: len(h) for i, h in holes.items()}, marks)
    ignored += found.said
    parts = [i for i in parts if i not in found.aside]
    for members in found.joined:
        parts = _join(lp, parts, holes, members, warnings)
    loose, said = loose_marks(lp, parts, marks)
    ignored += said
    notched, said = notches(lp, parts, holes)
    ignored += said
    parts = [i for i in parts if i not in loose | notched]
    kept = set(parts) | {j for i in parts for j in holes[i]}  # what was set aside crosses nothing cut
    warnings += _overlaps(sorted(kept, key=lambda i: -lp.polys[i].area), lp.parent, lp.polys)
    return Sheet([(_strip(lp.loops[i]), [_strip(lp.loops[j]) for j in holes[i]]) for i in parts], ignored, warnings,
                 [lp.layer(i) for i in parts])


def _join(lp: Loops, parts: list[int], holes: dict[int, list[int]], members: tuple[int, ...],
          warnings: list[str]) -> list[int]:
    """``parts`` with the faces ``members`` of one view (one arrangement component, split
    by visible edges) replaced by their outline, the component's outer boundary, which
    takes their holes; unchanged when that boundary does not bound their union."""
    c = lp.component[members[0]]
    outline = lp.outer.get(c)
    if outline is None:
        return parts
    poly = _polygon(outline)
    union = sum(lp.polys[i].area for i in members)
    if not poly.is_valid or abs(poly.area - union) > VIEW_JOIN_REL * union:
        return parts
    k = len(lp.loops)
    lp.loops.append(outline)
    lp.polys.append(poly)
    lp.component.append(c)
    lp.parent[k] = None
    holes[k] = [j for i in members for j in holes[i]]
    for j in holes[k]:
        lp.parent[j] = k
    warnings.append(f"plan view: {len(members)} faces split by visible edges joined into one outline")
    first = min(parts.index(i) for i in members)
    rest = [i for i in parts if i not in members]
    return rest[:first] + [k] + rest[first:]


VIEW_JOIN_REL = 1e-6
"""A view's outline bounds the union of its faces when their areas agree to this share."""


def _by_depth(lp: Loops, order: list[int], marks: Marks, ignored: list[str]) -> tuple[list[int], set[int]]:
    """The loops at even depth that are parts, and the loops dropped (with all they hold):
    engraving, counterbores' outer circles, pockets, letters, drillings in slugs."""
    depth: dict[int, int] = {}
    dropped: set[int] = set()
    parts: list[int] = []
    count = {"bores": 0, "slugs": 0}
    for i in order:  # by decreasing area: a loop's parent is placed before the loop
        p = lp.parent[i]
        if p in dropped:
            dropped.add(i)
            continue
        depth[i] = 0 if p is None else depth[p] + 1
        if p is not None and depth[i] % 2 == 1:
            _hole(lp, i, p, dropped, ignored, count)
        elif p is not None and slug_drill(lp, i, p):
            dropped.add(i)
            count["slugs"] += 1
        else:
            parts.append(i)
            marked, said = engraving(lp, i, marks)
            dropped |= marked
            ignored += said
    if count["slugs"]:
        ignored.append(f"slugs: {count['slugs']} small round loop(s) inside holes (drilled in the cut-out's slug): "
                       "not parts")
    if count["bores"]:
        ignored.append(f"counterbores: {count['bores']} round hole(s) drawn with a concentric circle around: "
                       "the inner circle is the hole")
    return parts, dropped


def _hole(lp: Loops, i: int, p: int, dropped: set[int], ignored: list[str], count: dict[str, int]) -> None:
    """Loop ``i`` at odd depth (in part ``p``): a hole, unless a counterbore's outer circle
    (the through hole inside takes its place), a pocket (its holes are the part's) or a
    letter with its counters."""
    if (through := counterbore(lp, i)) is not None:
        lp.parent[through] = p
        count["bores"] += 1
        dropped.add(i)
    elif pocket(lp, i):
        for kid in lp.children(i):
            lp.parent[kid] = p
        dropped.add(i)
        ignored.append(f"pocket: a loop on layer {lp.layer(i)!r} (machined part-way): not a hole")
    elif letter(lp, i, p):
        dropped.add(i)
        ignored.append("engraving: a small loop with a loop inside (a letter and its counter) inside a part: "
                       "not a hole")


KERF_AREA_REL = 0.01
"""A self-intersecting loop whose stray lobes (kerf loops, overshoots) hold less than this
share of its area is resolved to the region it bounds."""


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


def _strip(loop: list[Segment]) -> list[Segment]:
    return [{k: v for k, v in s.items() if k != "_layer"} for s in loop]
