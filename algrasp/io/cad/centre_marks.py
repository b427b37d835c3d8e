"""Centre marks drawn as plain lines: the cross a drawing program puts on a hole (SolidWorks'
SW_CENTERMARKSYMBOL: four radii from the centre to the circle and four extensions beyond
it, in a continuous linetype). Reaching the circle, the radii would cut the hole into
quarters; they are found by geometry, not by block or layer name: lines that run through
a circle's centre and stay within CENTRE_MARK_REACH radii of it, in at least two
directions (a cross). A single line through a circle's centre may be a cut (a disc cut in
halves) and is kept. O(n log n) in the entities (a KD-tree of the circles' centres).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from algrasp.io.cad.chain import Piece
from algrasp.io.cad.split import is_closed_curve

CENTRE_MARK_REACH = 2.5
"""A centre mark's lines stay within this many radii of the circle's centre (SolidWorks
extends them to 2 radii)."""
CENTRE_ON_LINE_REL = 1e-3
"""A line runs through a circle's centre when it passes within this share of the radius."""
CROSS_SIN = 0.5
"""Two lines of a mark are a cross when their directions' sine is at least this (30°)."""


def _through_centre(a: np.ndarray, b: np.ndarray, c: np.ndarray, r: float) -> bool:
    """Whether the line a–b runs through centre c and stays within the mark's reach."""
    v = b - a
    span = float(np.linalg.norm(v))
    if span == 0.0 or max(float(np.linalg.norm(a - c)), float(np.linalg.norm(b - c))) > CENTRE_MARK_REACH * r:
        return False
    off = abs(float(v[0] * (c - a)[1] - v[1] * (c - a)[0])) / span
    return off <= CENTRE_ON_LINE_REL * r


def _crossed(directions: list[np.ndarray]) -> bool:
    """Whether two of the unit directions cross (are not parallel)."""
    return any(abs(float(u[0] * w[1] - u[1] * w[0])) >= CROSS_SIN for n, u in enumerate(directions)
               for w in directions[n + 1:])


def drop_centre_marks(pieces: Sequence[Piece]) -> tuple[list[Piece], list[str]]:
    """The pieces without the lines of centre marks (see module docs), and what was said."""
    from scipy.spatial import cKDTree

    lines = [k for k, p in enumerate(pieces) if p.segment["type"] == "line"]
    circles = [p.segment for p in pieces if p.segment["type"] == "arc" and is_closed_curve(p.segment)]
    if not circles or not lines:
        return list(pieces), []
    ends = np.array([[pieces[k].segment["start"], pieces[k].segment["end"]] for k in lines], dtype=float)
    tree = cKDTree(ends.mean(axis=1))  # a mark's line has its middle within the reach too
    drop: set[int] = set()
    holes = 0
    for c in circles:
        centre, r = np.asarray(c["center"], float), float(c["radius"])
        near = [n for n in tree.query_ball_point(centre, CENTRE_MARK_REACH * r)
                if _through_centre(ends[n, 0], ends[n, 1], centre, r)]
        directions = [(ends[n, 1] - ends[n, 0]) / np.linalg.norm(ends[n, 1] - ends[n, 0]) for n in near]
        if _crossed(directions):
            drop |= {lines[n] for n in near}
            holes += 1
    if not drop:
        return list(pieces), []
    return [p for k, p in enumerate(pieces) if k not in drop], [
        f"centre marks: {len(drop)} line(s) crossing at the centres of {holes} circle(s) set aside (not cuts)"]
