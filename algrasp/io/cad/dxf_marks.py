"""What a DXF drawing says beside its geometry, for the clutter rules
(`algrasp.io.cad.clutter`): the points its dimensions measure, its texts, and a point inside
each hatched region."""

from __future__ import annotations

import math
from typing import Any

import numpy as np


def measured_points(entities: Any) -> list[tuple[float, float]]:
    """The points the drawing's DIMENSIONs measure (their definition points 13, 14 and 15):
    on the geometry of the part they describe."""
    out: list[tuple[float, float]] = []
    for e in entities:
        if e.dxftype() != "DIMENSION":
            continue
        for name in ("defpoint2", "defpoint3", "defpoint4"):
            if e.dxf.hasattr(name):
                v = e.dxf.get(name)
                if math.isfinite(float(v[0])) and math.isfinite(float(v[1])):
                    out.append((float(v[0]), float(v[1])))
        if len(out) >= MAX_TEXT_MARKS:
            break
    return out


MAX_TEXT_MARKS = 2000
"""Texts read for the frame and title-block rules (a drawing's first ones suffice)."""


def text_marks(entities: Any, depth: int = 0) -> list[tuple[float, float, str]]:
    """(x, y, content) of the drawing's TEXT, MTEXT and block attributes, blocks (title
    blocks are often blocks) read one level deep."""
    out: list[tuple[float, float, str]] = []
    for e in entities:
        if len(out) >= MAX_TEXT_MARKS:
            break
        t = e.dxftype()
        try:
            if t in ("TEXT", "MTEXT", "ATTRIB"):
                p = e.dxf.insert
                out.append((float(p[0]), float(p[1]), str(e.plain_text() if t == "MTEXT" else e.dxf.text)))
            elif t == "INSERT" and depth == 0:
                out += text_marks(e.attribs, 1) + text_marks(e.virtual_entities(), 1)
        except (ValueError, TypeError, AttributeError, LookupError, ArithmeticError):
            continue  # an unreadable text only ever weakens a clutter rule
    return out[:MAX_TEXT_MARKS]


def hatch_points(hatches: list[Any]) -> list[tuple[float, float]]:
    """One point inside each hatched region (section views are hatched; parts to cut are
    not): a hatch's boundary paths filled even-odd, as DXF hatches are, so a hatch of
    several islands (the letters of a logo) marks each of them. A hatch whose boundary
    cannot be read is skipped: it only ever sets a loop aside."""
    import ezdxf.path
    from shapely.errors import GEOSException

    out = []
    for h in hatches:
        try:
            rings = [np.asarray([(v.x, v.y) for v in p.flattening(0.01)]) for p in ezdxf.path.from_hatch(h)]
            for g in even_odd([r for r in rings if len(r) >= 3]):
                pt = g.representative_point()
                out.append((float(pt.x), float(pt.y)))
        except (ValueError, TypeError, AttributeError, IndexError, GEOSException):
            continue
    return out


def even_odd(rings: list[np.ndarray]) -> list[Any]:
    """The polygons of the region that ``rings`` fill under the even-odd rule."""
    from shapely.geometry import Polygon

    region: Any = None
    for r in rings:
        poly = Polygon(r).buffer(0)
        region = poly if region is None else region.symmetric_difference(poly)
    if region is None or region.is_empty:
        return []
    return [g for g in getattr(region, "geoms", [region]) if g.geom_type == "Polygon" and not g.is_empty]


SCALE_DIGITS = 9
"""DIMLFAC values equal to this many digits are one drawing scale."""
SCALE_MATCH_REL = 1e-6
"""A DIMLFAC within this fraction of a standard drawing scale is that scale."""
DRAWING_SCALES = (0.5, 0.2, 0.1, 0.05, 0.02, 2.0, 5.0, 20.0, 50.0)
"""DIMLFAC values read as the drawing's scale (ISO 5455: 2:1, 5:1, 10:1, 20:1, 50:1 and
1:2, 1:5, 1:20, 1:50). Others are taken for a unit change between the drawing and its
dimensions (10, 100, 1000: m or cm drawn, smaller units dimensioned; 25.4: inches
dimensioned in mm, as ezdxf's own styles do) and not applied."""


def drawing_scale(entities: Any) -> tuple[float, str | None]:
    """The scale a drawing is drawn at, from its DIMENSIONs' linear factor (DIMLFAC, from
    their style or its override): a part drawn at 2:1 is dimensioned with DIMLFAC 0.5, so
    its dimensions read true lengths. The factor that turns drawn lengths into true ones
    (1.0 when the dimensions say nothing, disagree — views at several scales — or change
    units rather than scale: DRAWING_SCALES), and what to say about it (None when all
    read 1:1). O(dimensions)."""
    factors: dict[float, int] = {}
    for e in entities:
        if e.dxftype() != "DIMENSION":
            continue
        try:
            f = float(e.override().get("dimlfac", 1.0))
        except (ValueError, TypeError, AttributeError, LookupError):
            continue
        if math.isfinite(f) and f > 0:
            factors[round(f, SCALE_DIGITS)] = factors.get(round(f, SCALE_DIGITS), 0) + 1
    if len(factors) != 1 or 1.0 in factors:
        if len(factors) > 1:
            return 1.0, (f"the dimensions read the drawing at {len(factors)} scales (DIMLFAC "
                         f"{', '.join(f'{f:g}' for f in sorted(factors))}): read as drawn")
        return 1.0, None
    (f, n), = factors.items()
    if not any(abs(f - s) <= SCALE_MATCH_REL * s for s in DRAWING_SCALES):
        return 1.0, (f"the dimensions read {f:g} × the drawn lengths (DIMLFAC), a unit change rather than a "
                     "drawing scale: read as drawn (in the header's unit)")
    return f, (f"the drawing is at {_ratio(f)}: its {n} dimension(s) read {f:g} × the drawn lengths (DIMLFAC): "
               f"read at full size")


def _ratio(f: float) -> str:
    """``f`` as a drawing scale: 0.5 → "2:1", 2 → "1:2"."""
    return f"{1 / f:g}:1" if f < 1 else f"1:{f:g}"
