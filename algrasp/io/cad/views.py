"""Several views of one part on a drawing sheet (issue 32, class 9): a machined part or a
plate drawn in plan, elevations, sections and a pictorial view, with dimensions and a title
block. Only the plan view is the part; the others are set aside and said.

A **view** is a connected component of the arrangement among the top-level loops: visible
edges (tangent edges, steps, a flange seen from above) split a view into faces that share
edges, while views stand apart with empty space between them. In a drawing with dimensions:

- two views are **projections** of one part when they share an extent where they are
  placed (the same x-interval, one above the other; the same y-interval, side by side) and
  are not copies (same area and holes: a nesting row);
- a projection beside the plan is another view of it when it is hatched (a section),
  labelled as a view ("SECTION A-A", "DETAIL B", "SIDE VIEW", …, in several languages),
  shows no holes (through holes are hidden lines in an elevation), or when a third view
  closes the orthographic triple (plan w × d, front w × h, side d × h: the front shares the
  plan's x-interval, the side the front's y-interval, and the side's width is the plan's
  depth) — two plates of one width stacked, each with holes, stay two parts;
- the **plan** is the view showing the part's largest face (the largest silhouette, not
  hatched; then the most holes: an L-bracket lies on its long leg), and its faces join
  into one outline (the component's outer boundary);
- a hatched, thin (a section through a plate) or labelled view beside an unhatched plan
  with holes is a section view even where it is not placed in projection (a section drawn
  at another scale, broken off);
- once a part's views are recognised, a view no dimension measures whose straight edges
  run mostly off the axes (an isometric or dimetric view), or one labelled pictorial, is a
  pictorial view.

Each rule is O(v²) in the views v (components holding top-level loops, at most
MAX_VIEWS), after O(n) to group n loops.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from itertools import permutations

from algrasp.geometry.angles import to_deg
from algrasp.io.cad.clutter import COPY_AREA_REL, Loops, Marks, groups

VIEW_ALIGN_REL = 5e-3
"""Two views whose extents agree to this share (along one axis) are aligned."""
THIN_ASPECT = 4.0
"""A hatched view this many times longer than thick is a section through a plate."""
SKEW_SHARE = 0.5
"""A view whose straight edges run off the axes for over this share of their length is
pictorial (isometric edges run at 30° and 150°)."""
SKEW_DEG = 5.0
"""Edges within this angle of an axis run along it."""
MAX_VIEWS = 50
"""A drawing with more separate components than this among its parts is a nesting sheet:
no views are looked for (keeps the rules' O(v²) bounded)."""
LABEL_REACH = 0.5
"""A view label names the nearest view within this many times that view's larger side."""
SECTION_LABEL = re.compile(
    r"\bsection\b|\bdetail\b|\b([A-Z])\s*-\s*\1\b|schnitt|einzelheit|coupe|détail|detalle|secci[oó]n|sezione|"
    r"dettaglio|corte|разрез|сечение|вид\s|断面|詳細|剖面|详图|단면|상세", re.IGNORECASE)
"""View labels of sections and details (English, German, French, Spanish, Italian,
Portuguese, Russian, Japanese, Chinese, Korean): "SECTION A-A", "A-A (1:2)", "DETAIL B"."""
ELEVATION_LABEL = re.compile(
    r"\b(front|side|top|bottom|left|right|rear|back|end)\s+view\b|\belevation\b|ansicht|seitenansicht|vue\s+de|"
    r"vista\s+(frontal|lateral|superior)|正面図|側面図|平面図|主视图|侧视图|俯视图", re.IGNORECASE)
"""Labels of projected views."""
PICTORIAL_LABEL = re.compile(r"isometri|\biso\b|pictorial|trimetri|dimetri|axonometr|perspect|3d\s+view|等角|轴测",
                             re.IGNORECASE)
"""Labels of pictorial views."""


@dataclass(frozen=True)
class View:
    """A view: its top-level loops, box (x0, y0, x1, y1), hole count, whether it is
    hatched or measured by a dimension, the share of its straight edges running off the
    axes, and the view label next to it ("" if none)."""

    members: tuple[int, ...]
    box: tuple[float, float, float, float]
    area: float
    holes: int
    hatched: bool
    measured: bool
    skew: float
    label: str

    def side(self, axis: int) -> float:
        return self.box[axis + 2] - self.box[axis]

    @property
    def box_area(self) -> float:
        return self.side(0) * self.side(1)


@dataclass(frozen=True)
class Views:
    """What the views rule found: loops set aside, what was said, and each plan view of
    several faces (its loops, to join into one outline)."""

    aside: set[int]
    said: list[str]
    joined: list[tuple[int, ...]]


NO_VIEWS = Views(set(), [], [])


def find_views(lp: Loops, parts: list[int], holes: dict[int, int], marks: Marks) -> Views:
    """The other views of each part drawn in several views (see module docs). ``holes``:
    each part loop's hole count."""
    if not marks.annotated:  # views come with dimensions; a nesting sheet lines parts up too
        return NO_VIEWS
    tops = [i for i in parts if lp.parent[i] is None]
    if len({lp.component[i] for i in tops}) > MAX_VIEWS:  # a nesting sheet, not views of a part
        return NO_VIEWS
    vs = _views(lp, tops, holes, marks)
    if len(vs) < 2:
        return NO_VIEWS
    aside: dict[int, str] = {}
    plans: set[int] = set()
    for group in groups(list(range(len(vs))), lambda a, b: _aligned(vs[a], vs[b]) and not _copies(vs[a], vs[b])):
        if len(group) < 2:
            continue
        plan = max(group, key=lambda k: (not vs[k].hatched, vs[k].area, vs[k].holes))
        for k in group:
            if k != plan and (why := _projection(vs, plan, k, group)):
                aside[k] = why
                plans.add(plan)
    for k, v in enumerate(vs):
        if k not in aside and (why := _section(vs, k)):
            aside[k] = why
            plans.add(max((j for j in range(len(vs)) if j != k and _plan_like(vs[j], v)), key=lambda j: vs[j].area))
    _pictorial(vs, aside, plans)
    return _report(vs, aside, plans)


def _report(vs: list[View], aside: dict[int, str], plans: set[int]) -> Views:
    out = {i for k in aside for i in vs[k].members}
    said = [f"{why}: a view of the part drawn beside its plan view ({len(vs[k].members)} loop(s) at drawing coordinates "
            f"{_where(vs[k])}), set aside" for k, why in sorted(aside.items())]
    joined = [vs[k].members for k in sorted(plans - set(aside)) if len(vs[k].members) > 1]
    return Views(out, said, joined)


def _where(v: View) -> str:
    x0, y0, x1, y1 = v.box
    return f"({x0:.4g}, {y0:.4g})–({x1:.4g}, {y1:.4g})"


def _views(lp: Loops, tops: list[int], holes: dict[int, int], marks: Marks) -> list[View]:
    """The top-level loops grouped by arrangement component, as views."""
    from shapely.geometry import Point
    from shapely.ops import unary_union

    from algrasp.io.cad.features import _measured

    by_comp: dict[int, list[int]] = {}
    for i in tops:
        by_comp.setdefault(lp.component[i], []).append(i)
    out = []
    for members in by_comp.values():
        shape = unary_union([lp.polys[i] for i in members])
        hatched = sum(lp.polys[i].area for i in members if any(lp.polys[i].covers(Point(p)) for p in marks.hatched))
        out.append(View(tuple(members), tuple(shape.bounds), float(shape.area), sum(holes[i] for i in members),
                        hatched > 0.5 * shape.area, any(_measured(lp.polys[i], marks) for i in members),
                        _skew(lp, members), ""))
    return _labelled(out, marks)


def _labelled(vs: list[View], marks: Marks) -> list[View]:
    """Each view with the view label nearest it (within LABEL_REACH of its size)."""
    from dataclasses import replace

    labels: dict[int, str] = {}
    for x, y, text in marks.texts:
        if not (SECTION_LABEL.search(text) or ELEVATION_LABEL.search(text) or PICTORIAL_LABEL.search(text)):
            continue
        near = [(_gap(v, x, y), k) for k, v in enumerate(vs) if _gap(v, x, y) <= LABEL_REACH * max(v.side(0), v.side(1))]
        if near:
            k = min(near)[1]
            labels[k] = (labels.get(k, "") + " " + " ".join(text.split())).strip()
    return [replace(v, label=labels.get(k, "")) for k, v in enumerate(vs)]


def _gap(v: View, x: float, y: float) -> float:
    x0, y0, x1, y1 = v.box
    return math.hypot(max(x0 - x, 0.0, x - x1), max(y0 - y, 0.0, y - y1))


def _skew(lp: Loops, members: list[int]) -> float:
    """The share of the members' straight-edge length running off the axes."""
    off = total = 0.0
    for i in members:
        for s in lp.loops[i]:
            if s["type"] != "line":
                continue
            dx, dy = s["end"][0] - s["start"][0], s["end"][1] - s["start"][1]
            length = math.hypot(dx, dy)
            angle = to_deg(math.atan2(abs(dy), abs(dx)))
            total += length
            off += length if SKEW_DEG < angle < 90.0 - SKEW_DEG else 0.0
    return off / total if total > 0 else 0.0


def _axis(a: View, b: View) -> int | None:
    """The axis (0: x, 1: y) along which ``a`` and ``b`` share an interval, apart."""
    for axis in (0, 1):
        lo, hi = a.box[axis], a.box[axis + 2]
        span = max(a.side(axis), b.side(axis))
        if abs(lo - b.box[axis]) <= VIEW_ALIGN_REL * span and abs(hi - b.box[axis + 2]) <= VIEW_ALIGN_REL * span:
            return axis
    return None


def _aligned(a: View, b: View) -> bool:
    return _axis(a, b) is not None


def _copies(a: View, b: View) -> bool:
    return a.holes == b.holes and abs(a.area - b.area) <= COPY_AREA_REL * max(a.area, b.area)


def _same(x: float, y: float) -> bool:
    return abs(x - y) <= VIEW_ALIGN_REL * max(x, y)


def _projection(vs: list[View], plan: int, k: int, group: list[int]) -> str | None:
    """Why view ``k``, aligned in ``group`` with ``plan``, is another view of its part
    (None: another part)."""
    v = vs[k]
    if v.hatched:
        return "section view (hatched)"
    if v.label:
        return f"view labelled {v.label!r}"
    if v.holes == 0:
        return "side view (no holes of its own: they are hidden lines)"
    if any(_triple(vs, *order) for c in group if c not in (plan, k) for order in permutations((plan, k, c))):
        return "projected view (plan, front and side views agree on the part's width, depth and height)"
    return None


def _triple(vs: list[View], a: int, b: int, c: int) -> bool:
    """``a`` and ``b`` share one axis, ``b`` and ``c`` the other, and ``a``'s extent across
    the first equals ``c``'s across the second (plan depth = side width)."""
    ab, bc = _axis(vs[a], vs[b]), _axis(vs[b], vs[c])
    return ab is not None and bc is not None and ab != bc and _same(vs[a].side(1 - ab), vs[c].side(1 - bc))


def _plan_like(plan: View, view: View) -> bool:
    """An unhatched view with holes, larger than ``view``: the plan a section is cut from."""
    return not plan.hatched and plan.holes > 0 and plan.box_area > view.box_area


def _section(vs: list[View], k: int) -> str | None:
    """Why view ``k`` is a section or detail view beside a plan (None: it is not)."""
    v = vs[k]
    if not any(_plan_like(p, v) for j, p in enumerate(vs) if j != k):
        return None
    if SECTION_LABEL.search(v.label):
        return f"section or detail view labelled {v.label!r}"
    long, short = max(v.side(0), v.side(1)), min(v.side(0), v.side(1))
    if v.hatched and (short * THIN_ASPECT <= long or v.label):
        return "section view (hatched, a thin strip through the plate)"
    return None


def _pictorial(vs: list[View], aside: dict[int, str], plans: set[int]) -> None:
    """Once a part's views are recognised, the pictorial views among the rest (see module docs)."""
    if not aside:
        return
    for k, v in enumerate(vs):
        if k in aside or k in plans:
            continue
        if PICTORIAL_LABEL.search(v.label):
            aside[k] = f"pictorial view labelled {v.label!r}"
        elif not v.measured and v.skew > SKEW_SHARE:
            aside[k] = (f"pictorial view (no dimension measures it; {100 * v.skew:.0f} % of its straight edges run "
                        "off the axes, as in an isometric view)")
