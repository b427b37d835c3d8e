"""Re-reading a fence layout drawing (conventions §9): the DXF that ``algrasp fences --dxf``
writes, or a shop's re-save of it, read back as a fence layout, not mistaken for parts.

A DXF is a fence layout when its layer ``BELT`` holds two parallel LINEs (the rails) and
its layer ``FENCES`` LINEs (one per fence, from its root on a rail to its tip) and at most
one ARC (the last fence's curved tail); layer ``EXIT`` may hold the exit guide's LINE. The belt frame is the rails': x along them (the
direction the drawing gives them, as the writer draws them: the belt's motion), y across
from the lower rail (the right one looking downstream) to the other; positions along the
belt are x of the fences' roots, measured from where the belt frame's y axis crosses the
rails (the writer puts it at the first fence's root). Lengths in the file's unit
(``$INSUNITS``); angles as the fence document's (``angle_deg`` the wall's world direction
in [0, 180), ``steepness_deg`` its angle to the belt). O(entities) time.
"""

from __future__ import annotations

import math
from typing import Any

from algrasp.errors import PartDocumentError
from algrasp.geometry.angles import to_deg, to_rad
from algrasp.geometry.tolerances import DRAWING_SNAP_REL

KIND = "fence_layout"
"""``kind`` of a re-read fence layout document (a part document has none)."""
UNIT_NAMES = {1: "in", 2: "ft", 4: "mm", 5: "cm", 6: "m", 13: "um"}
"""$INSUNITS codes → unit names (those :mod:`algrasp.io.fence_drawing` writes)."""

Point = tuple[float, float]


def is_fence_layout(doc: object) -> bool:
    """Whether ``doc`` is a re-read fence layout document (not a part)."""
    return isinstance(doc, dict) and doc.get("kind") == KIND


def refuse_layout(doc: dict[str, Any], where: str) -> dict[str, Any]:
    """``doc`` unless it is a fence layout: then PartDocumentError naming ``where`` (a
    layout has no outline to plan)."""
    if is_fence_layout(doc):
        n = len(doc["fences"])
        raise PartDocumentError(where, f"{doc.get('name') or 'the drawing'} is a fence layout ({n} fence{'s' if n > 1 else ''} "
                                "on layer FENCES), not a part: `algrasp import` reads it as one")
    return doc


def fence_layout_of(data: bytes, name: str) -> dict[str, Any] | None:
    """The fence layout document of DXF ``data`` (see the module), None if it is not one.

    Raises PartDocumentError when it has the rails and fences but a fence is not rooted on
    a rail or the rails are not parallel."""
    if b"FENCES" not in data or b"BELT" not in data:  # most drawings: no parse
        return None
    from algrasp.io.cad.dxf import read_dxf

    drawing = read_dxf(data)
    msp = drawing.modelspace()
    rails = [_ends(e) for e in msp.query("LINE") if e.dxf.layer.upper() == "BELT"]
    walls = [_ends(e) for e in msp.query("LINE") if e.dxf.layer.upper() == "FENCES"]
    arcs = [e for e in msp.query("ARC") if e.dxf.layer.upper() == "FENCES"]
    guides = [_ends(e) for e in msp.query("LINE") if e.dxf.layer.upper() == "EXIT"]
    if len(rails) != 2 or not walls or len(arcs) > 1 or len(guides) > 1:
        return None
    frame = _belt_frame(rails)
    width = frame.width
    fences = sorted((_fence(frame, w, k) for k, w in enumerate(walls, 1)), key=lambda f: f["position"])
    units = UNIT_NAMES.get(int(drawing.header.get("$INSUNITS", 0)), "unitless")
    out: dict[str, Any] = {"kind": KIND, "name": name, "units": units, "belt_width": width,
                           "belt_direction_deg": 0.0, "fences": fences,
                           "total_length": math.fsum(f["length"] for f in fences),
                           "source": {"format": "dxf", "layer": "FENCES"}}
    if arcs:
        out["tail"] = _tail(frame, arcs[0], fences)
    if guides:
        out["exit"] = _exit(frame, guides[0])
    return out


def _exit(frame: _Frame, guide: tuple[Point, Point]) -> dict[str, Any]:
    """The exit guide (layer EXIT): from its upstream end, its angle and steepness to the
    belt (degrees), length and ends in the belt frame."""
    start, end = sorted((frame.to_belt(e) for e in guide), key=lambda p: p[0])
    return {**_wall(start, end), "start": list(start), "end": list(end)}


def _wall(root: Point, tip: Point) -> dict[str, float]:
    """A wall from ``root`` to ``tip`` (belt frame): its angle and steepness to the belt
    (degrees, the fence document's) and its length."""
    angle = to_deg(math.atan2(tip[1] - root[1], tip[0] - root[0])) % 180.0
    return {"angle_deg": angle, "steepness_deg": min(angle, 180.0 - angle),
            "length": math.hypot(tip[0] - root[0], tip[1] - root[1])}


def _ends(e: Any) -> tuple[Point, Point]:
    return (float(e.dxf.start.x), float(e.dxf.start.y)), (float(e.dxf.end.x), float(e.dxf.end.y))


class _Frame:
    """The belt frame of two rails: ``to_belt`` maps drawing points to (x along the rails,
    y across from the lower one); ``d`` the rails' unit direction, ``lo`` the lower rail's
    offset across, ``snap`` the distance under which points coincide."""

    def __init__(self, d: Point, lo: float, width: float, snap: float) -> None:
        self.d, self.lo, self.width, self.snap = d, lo, width, snap

    def to_belt(self, p: Point) -> Point:
        return p[0] * self.d[0] + p[1] * self.d[1], -p[0] * self.d[1] + p[1] * self.d[0] - self.lo


def _belt_frame(rails: list[tuple[Point, Point]]) -> _Frame:
    """x along the first rail as drawn, y across towards the other."""
    (a0, a1), _ = rails
    n = math.hypot(a1[0] - a0[0], a1[1] - a0[1])
    if n == 0.0:
        raise PartDocumentError("BELT", "a rail of zero length: not a belt")
    d = ((a1[0] - a0[0]) / n, (a1[1] - a0[1]) / n)
    snap = DRAWING_SNAP_REL * (max(abs(c) for r in rails for p in r for c in p) + n)
    across = [-p[0] * d[1] + p[1] * d[0] for r in rails for p in r]  # each end's offset across
    if abs(across[0] - across[1]) > snap or abs(across[2] - across[3]) > snap:
        raise PartDocumentError("BELT", "the two rails are not parallel lines: not a belt")
    lo, hi = sorted((across[0], across[2]))
    if hi - lo <= snap:
        raise PartDocumentError("BELT", "the two rails coincide: not a belt")
    return _Frame(d, lo, hi - lo, snap)


def _fence(frame: _Frame, wall: tuple[Point, Point], k: int) -> dict[str, Any]:
    """One fence's document entry: its root is the end on a rail."""
    p, q = (frame.to_belt(e) for e in wall)
    on = [min(abs(e[1]), abs(e[1] - frame.width)) <= frame.snap for e in (p, q)]
    if not any(on):
        raise PartDocumentError("FENCES", f"line {k} on layer FENCES touches neither rail: not a fence")
    root, tip = (p, q) if on[0] else (q, p)
    w = _wall(root, tip)
    return {"side": "right" if abs(root[1]) <= frame.snap else "left", "angle_deg": w["angle_deg"],
            "steepness_deg": w["steepness_deg"], "position": root[0], "length": w["length"], "tip": [tip[0], tip[1]]}


def _tail(frame: _Frame, arc: Any, fences: list[dict[str, Any]]) -> dict[str, Any]:
    """The curved tail: its radius, sweep (degrees) and the fence whose tip it starts at."""
    c = (float(arc.dxf.center.x), float(arc.dxf.center.y))
    R = float(arc.dxf.radius)
    ends = [frame.to_belt((c[0] + R * math.cos(to_rad(t)), c[1] + R * math.sin(to_rad(t))))
            for t in (arc.dxf.start_angle, arc.dxf.end_angle)]
    sweep = (float(arc.dxf.end_angle) - float(arc.dxf.start_angle)) % 360.0
    at = [i for i, f in enumerate(fences, 1) for e in ends
          if math.hypot(e[0] - f["tip"][0], e[1] - f["tip"][1]) <= frame.snap]
    if not at:
        raise PartDocumentError("FENCES", "the ARC on layer FENCES (a curved tail) starts at no fence's tip")
    return {"radius": R, "sweep_deg": sweep, "fence": at[0]}
