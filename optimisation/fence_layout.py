"""Fence layout (conventions §9): lengths, positions and the belt width of a fence design.

Each fence must be long enough for the part to finish its turn against it: the push
distance s_i (Peshkin's bound of :mod:`optimisation.push`, c = a the covering radius: the
slowest turn any support pressure allows, so every cell of the ranges is covered) from
the worst orientation the part can arrive in relative to fence i (the whole circle for
the first). In the belt's frame a fence at steepness β moves by s along its normal while
the part slides s·cot β along it, so fence i must reach laterally ``s_i cos β_i`` past
where the part can first touch it. A part leaves fence i−1 at its tip, within 2a of it,
so with every fence reaching h = W − 2a − c (c = a/2, the clearance beside a tip):

    h_{i−1} + h_i ≥ W + 2a + s_i cos β_i   ⇒   W ≥ 6a + 2c + s_i cos β_i,

and the first fence (parts enter along its side, within 2a of it) needs W ≥ 6a + c +
s_1 cos β_1. Fence i's root is at ``position`` along the belt, its tip h·cot β_i further;
the next root is 2a past that tip. With consecutive fences on one rail (``same_rail``)
the later one must catch the part where it comes off the earlier one's tip, within 2a of
it: h_i ≥ h_{i−1} + 2a + s_i cos β_i. So a fence followed by one on its own rail reaches
D_i less than h (D_i = D_{i+1} + 2a + s_{i+1} cos β_{i+1}, the last of a run reaching h),
and the bounds above read h_i = h − D_i: the belt widens by the D's. Each root lies
downstream of the tip before, every fence slanting downstream: no fence crosses another.
The last fence is followed by its exit guide
(:mod:`algrasp.planning.fence_exit`): s_e cot β_e long from its tip at β_e, rising
s_e cos β_e across the belt, by which the last fence is shortened and the belt widened.
Lengths in the part's unit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from algrasp.errors import ConfigError
from algrasp.geometry.angles import to_deg, to_rad
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.tolerances import ROUNDING
from algrasp.planning.analysis import Analysis
from algrasp.planning.deadband import mean_radius
from algrasp.planning.fence_exit import ExitGuide, exit_guide, exit_steepness
from algrasp.planning.fence_model import exit_turn
from algrasp.planning.fence_motion import fence_motion, follow
from algrasp.planning.fences import DEFAULT_MIN_MARGIN_DEG, DEFAULT_RULES, FenceDesign, FenceRules, design_fences
from algrasp.planning.motion import Motion
from optimisation.push import PushModel, push_distances, push_model

FOLLOW_STARTS_DEG = 360
"""Starts the document's ``follow_deg`` traces: every whole degree (the page's start slider's steps)."""

PUSH_TOLERANCE_DEG = 0.5
"""A turn is complete within this of the fixed point (as the gripper profile's default)."""
UNSTABLE_BAND_DEG = 2.0
"""Orientations this close to an unstable push equilibrium are left out of the worst case."""
CLEARANCE = 0.5
"""c: room beside a fence's tip, in covering radii a."""
SPACING = 2.0
"""Gap between a fence's tip and the next fence's root along the belt, in covering radii."""


@dataclass(frozen=True)
class Tail:
    """The curved tail of the last fence (Brokowski, Peshkin & Goldberg 1995): an arc of
    ``radius`` (part units) tangent to the fence at its tip, turning by ``sweep``
    (radians) towards the belt's direction, so that the part flush against it turns with
    it and leaves with its contact edge at ``sweep`` less to the belt (the default sweep,
    the fence's steepness β, leaves it parallel to the belt: no torque as it comes off)."""

    radius: float
    sweep: float


@dataclass(frozen=True)
class FenceLayout:
    """A fence design laid out on a belt (lengths in ``units``).

    Attributes
    ----------
    design : FenceDesign
        The angles, margins and final orientations.
    belt_width : float
        W, between the side rails.
    reach : float
        h: every fence's extent across the belt.
    push_bounds : tuple of float
        s_i: Peshkin's push distance along each fence's normal.
    lengths, positions : tuple of float
        Each fence's length along the wall and its root's position along the belt.
    cover_radius : float
        a: the part's largest distance from its centre of mass.
    units : str
        The part's unit.
    """

    design: FenceDesign
    belt_width: float
    reach: float
    push_bounds: tuple[float, ...]
    lengths: tuple[float, ...]
    positions: tuple[float, ...]
    cover_radius: float
    units: str
    tail: Tail | None = None
    last_reach: float | None = None
    """The last fence's extent across the belt when an exit guide or a tail shortens it
    (else ``reach``)."""
    exit: ExitGuide | None = None
    """The exit guide on the last fence's rail (None: its push would not collapse the arc)."""
    exit_length: float = 0.0
    """The guide's length along its wall (part units): its push bound times cot β_e."""
    exit_push_bound: float = 0.0
    """s_e: Peshkin's push distance over the arc the part arrives at the guide in."""
    reaches: tuple[float, ...] | None = None
    """Each fence's extent across the belt when they differ: a fence followed by one on the
    same rail reaches less than h (None: every fence ``reach``, the last ``last_reach``)."""
    motion: Motion | None = None
    """The push's images and each fence's arcs after it (:mod:`algrasp.planning.fence_motion`):
    the document's ``images`` and fences' ``image_deg``, what a page animates."""
    follow: FloatArray | None = None
    """(360, N or N + 1, 2): the world arc each whole-degree start is in after each fence
    and past the exit guide (:func:`~algrasp.planning.fence_motion.follow`, radians), the
    document's ``follow_deg``: a page animates one start with it."""

    @property
    def steepness(self) -> tuple[float, ...]:
        """β_i: each fence's angle to the belt direction (radians)."""
        return tuple(a if a < 0.5 * np.pi else np.pi - a for a in self.design.angles)

    def tip(self, i: int) -> tuple[float, float]:
        """Fence i's free end (x, y) on the belt (y = 0 the right rail, y = W the left)."""
        beta = self.steepness[i]
        h = self.reach_of(i)
        x = self.positions[i] + h / math.tan(beta)
        return x, h if self.design.sides[i] == 0 else self.belt_width - h

    def reach_of(self, i: int) -> float:
        """Fence i's extent across the belt from its rail (part units)."""
        if self.last_reach is not None and i == len(self.lengths) - 1:
            return self.last_reach
        return self.reach if self.reaches is None else self.reaches[i]

    def root(self, i: int) -> tuple[float, float]:
        """Fence i's end on its rail (x, y)."""
        return self.positions[i], 0.0 if self.design.sides[i] == 0 else self.belt_width

    def tail_turn(self) -> float:
        """Signed turn (radians) the tail gives the part: −sweep on the right rail
        (clockwise, α = β towards 0), +sweep on the left (α = π − β towards π); 0 without."""
        if self.tail is None:
            return 0.0
        return -self.tail.sweep if self.design.sides[-1] == 0 else self.tail.sweep

    def tail_arc(self) -> tuple[tuple[float, float], float, float, float] | None:
        """(centre, radius, start, end): the tail's arc counter-clockwise from ``start`` to
        ``end`` (radians, the directions from the centre), as DXF draws arcs; None without.

        The centre is R behind the last fence's face: C = tip − R n, n = (−sin α, cos α)
        the face's normal (towards the part), so the arc leaves the tip along the fence
        (tangent) and bends away from the part, the part riding its convex side."""
        if self.tail is None:
            return None
        a = self.design.angles[-1]
        tx, ty = self.tip(len(self.lengths) - 1)
        R = self.tail.radius
        c = (tx + R * math.sin(a), ty - R * math.cos(a))
        at_tip = math.atan2(math.cos(a), -math.sin(a))  # the direction of n from the centre
        turn = self.tail_turn()
        lo, hi = (at_tip + turn, at_tip) if turn < 0 else (at_tip, at_tip + turn)
        return c, R, lo, hi

    def tail_points(self, n: int = 32) -> list[tuple[float, float]]:
        """The tail from the last fence's tip to its end, ``n`` + 1 points (part units)."""
        arc = self.tail_arc()
        if arc is None:
            return []
        (cx, cy), R, lo, hi = arc
        ts = np.linspace(hi, lo, n + 1) if self.tail_turn() < 0 else np.linspace(lo, hi, n + 1)
        return [(cx + R * math.cos(t), cy + R * math.sin(t)) for t in ts]

    def exit_points(self) -> list[tuple[float, float]]:
        """The exit guide's start (the tail's end, else the last fence's tip) and end."""
        if self.exit is None:
            return []
        pts = self.tail_points()
        x0, y0 = pts[-1] if pts else self.tip(len(self.lengths) - 1)
        b, n = self.exit.steepness, self.exit_length
        return [(x0, y0), (x0 + n * math.cos(b), y0 + (n if self.exit.side == 0 else -n) * math.sin(b))]

    def claim(self) -> tuple[tuple[float, ...], float]:
        """The final orientations (world, radians) and their half-width downstream of the
        layout: the exit guide's; without one, the last fence's widened by its exit turn."""
        if self.exit is not None:
            return self.exit.final_orientations, self.exit.final_uncertainty
        d = self.design
        finals = np.array(d.final_orientations)
        lo, hi = exit_turn(finals, finals, d.angles[-1])
        return (tuple(sorted(float(f) for f in np.mod(0.5 * (lo + hi), 2 * np.pi))),
                d.final_uncertainty + 0.5 * float(hi[0] - lo[0]))

    def to_dict(self, follow: bool = True) -> dict[str, object]:
        """The fence document (degrees; lengths in ``units``): ``FenceDocument``; without
        ``follow`` no ``follow_deg`` (a catalogue's results keep the layout, not the trace a
        page animates one start with: 360 × N arcs)."""
        d = self.design
        fences = [{"side": "right" if s == 0 else "left", "angle_deg": _deg(a),
                   "steepness_deg": _deg(b), "position": x, "length": n, "margin_deg": _deg(m),
                   "push_distance_bound": p}
                  for s, a, b, x, n, m, p in zip(d.sides, d.angles, self.steepness, self.positions, self.lengths,
                                                 d.margins, self.push_bounds)]
        for i, f in enumerate(fences):
            f["reach"] = self.reach_of(i)
        if self.motion is not None:
            for f, arcs in zip(fences, self.motion.after):
                f["image_deg"] = [[_deg(a), _deg(b)] for a, b in arcs]
        return {"units": self.units, "model": "exact" if d.exact else "robust", "belt_direction_deg": 0.0,
                "belt_width": self.belt_width, "reach": self.reach, "cover_radius": self.cover_radius,
                "fence_friction": list(d.rules.friction), "max_steepness_deg": _deg(d.rules.max_steepness),
                "min_steepness_deg": _deg(d.rules.min_steepness), "exit_turns": d.rules.exit_turns,
                "same_rail": d.rules.same_rail, "fences": fences,
                "total_length": float(sum(self.lengths)), "symmetry_period_deg": _deg(d.symmetry),
                "final_orientations_deg": [_deg(f) for f in self.claim()[0]],
                "final_uncertainty_deg": _deg(self.claim()[1]),
                "last_fence_orientations_deg": [_deg(f) for f in d.final_orientations],
                "last_fence_uncertainty_deg": _deg(d.final_uncertainty),
                "exit": None if self.exit is None else {
                    "side": "right" if self.exit.side == 0 else "left", "angle_deg": _deg(self.exit.angle),
                    "steepness_deg": _deg(self.exit.steepness), "length": self.exit_length,
                    "start": list(self.exit_points()[0]), "end": list(self.exit_points()[1]),
                    "push_distance_bound": self.exit_push_bound,
                    **({} if self.motion is None or len(self.motion.after) <= len(fences) else
                       {"image_deg": [[_deg(a), _deg(b)] for a, b in self.motion.after[len(fences)]]})},
                **({} if self.tail is None else {
                    "tail": {"radius": self.tail.radius, "sweep_deg": _deg(self.tail.sweep),
                             "turn_deg": _deg(self.tail_turn())}}),
                **({} if self.motion is None else {"images": _images(self.motion)}),
                **({} if self.follow is None or not follow else {"follow_deg": [[[_deg(a), _deg(b)] for a, b in row]
                                                                  for row in self.follow.tolist()]})}


def _images(m: Motion) -> dict[str, object]:
    """The push's images in degrees, as a plan document writes them: ``period_deg`` and
    pieces ``[start, end, lower, upper]`` (None: θ itself)."""
    def opt(x: float | None) -> float | None:
        return None if x is None else _deg(x)

    return {"period_deg": _deg(m.period), "pieces": [[_deg(a), _deg(b), opt(lo), opt(hi)] for a, b, lo, hi in m.images]}


def _deg(rad: float) -> float:
    """Degrees, rounded to 1e-9 (grid angles carry rounding noise from radians)."""
    return round(float(to_deg(rad)), 9)


def _bounds(model: PushModel, analysis: Analysis, design: FenceDesign) -> list[float]:
    """s_i for each fence: Peshkin's bound over the arc the part arrives in (part units)."""
    found = push_distances(model, analysis, list(design.inputs), to_rad(PUSH_TOLERANCE_DEG), to_rad(UNSTABLE_BAND_DEG))
    return [r.bound for r in found]


def layout(analysis: Analysis, design: FenceDesign, belt_width: float | None = None,
           model: PushModel | None = None, exit_steepness_rad: float | None = None) -> FenceLayout:
    """Lengths, positions and belt width of ``design`` (see module docs) with its exit
    guide at steepness ``exit_steepness_rad`` (None: without a guide, as the search's
    tie-break measures designs); ``belt_width`` (part units) must be at least the least
    width, which is the default. The guide's push bound s_e gives its length s_e cot β_e
    and its rise s_e cos β_e across the belt, by which the last fence is shortened (the
    part must still pass between the guide's end and the far rail).

    Raises ConfigError (``belt_width``) when the given belt is too narrow."""
    model = model or push_model(analysis, mean_radius(analysis.part))
    a = model.cover_radius
    s = _bounds(model, analysis, design)
    beta = [x if x < 0.5 * np.pi else np.pi - x for x in design.angles]
    guide = None if exit_steepness_rad is None else exit_guide(analysis, design, exit_steepness_rad)
    s_e = 0.0 if guide is None else push_distances(model, analysis, [guide.input], to_rad(PUSH_TOLERANCE_DEG),
                                                   to_rad(UNSTABLE_BAND_DEG))[0].bound
    rise = s_e * math.cos(guide.steepness) if guide is not None else 0.0
    short = _shortfalls(design.sides, [si * math.cos(b) for si, b in zip(s, beta)], a, rise)
    need = [s[0] * math.cos(beta[0]) - CLEARANCE * a + short[0]]
    need += [si * math.cos(b) + d0 + d1 for si, b, d0, d1, s0, s1 in zip(s[1:], beta[1:], short, short[1:], design.sides,
                                                                           design.sides[1:]) if s0 != s1]
    least = (6.0 + 2.0 * CLEARANCE) * a + max(need)
    if belt_width is not None and not (np.isfinite(belt_width) and belt_width >= least):
        raise ConfigError("belt_width", f"this design needs a belt at least {least:.4g} {analysis.part.units} wide, "
                          f"got {belt_width!r}")
    W = least if belt_width is None else float(belt_width)
    h = W - (2.0 + CLEARANCE) * a
    reaches = [h - d for d in short]
    positions = [0.0]
    for hi, b in zip(reaches[:-1], beta[:-1]):
        positions.append(positions[-1] + hi / math.tan(b) + SPACING * a)
    lengths = tuple(hi / math.sin(b) for hi, b in zip(reaches, beta))
    same = any(s0 == s1 for s0, s1 in zip(design.sides, design.sides[1:]))
    return FenceLayout(design, W, h, tuple(s), lengths, tuple(positions), a, analysis.part.units,
                       last_reach=reaches[-1] if guide is not None or same else None, exit=guide,
                       exit_length=0.0 if guide is None else s_e / math.tan(guide.steepness), exit_push_bound=s_e,
                       reaches=tuple(reaches) if same else None)


def _shortfalls(sides: tuple[int, ...], lateral: list[float], a: float, rise: float) -> list[float]:
    """D_i: how much less than the full reach h each fence reaches across the belt (part
    units). The last fence falls short by the exit guide's ``rise``; a fence followed by
    one on the same rail by that one's D plus 2a + s cos β of it (``lateral``: s_i cos β_i),
    so the later fence reaches past the earlier one's tip by all a part leaving it can
    occupy (2a) and its own turn; a fence followed by one on the other rail reaches h. O(N)."""
    out = [rise]
    for i in range(len(sides) - 2, -1, -1):
        out.insert(0, out[0] + 2.0 * a + lateral[i + 1] if sides[i] == sides[i + 1] else 0.0)
    return out


def with_tail(out: FenceLayout, radius: float, sweep_deg: float | None = None) -> FenceLayout:
    """``out`` with a curved tail of ``radius`` (part units) on its last fence, turning
    by ``sweep_deg`` (default the fence's steepness: the tail ends parallel to the belt).

    The last fence is shortened so that its tail reaches across the belt no further than
    its tip did plus c (the room beside a tip): the part still passes the far rail.

    Raises ConfigError (``tail``) unless 0 < radius, 0 < sweep ≤ β and the shortened
    fence still lets the part finish its turn (a wider belt gives it room)."""

    beta = out.steepness[-1]
    top = beta - (out.exit.steepness if out.exit is not None else 0.0)  # the tail ends tangent to the guide
    sweep = top if sweep_deg is None else to_rad(float(sweep_deg))
    if not (math.isfinite(radius) and radius > 0.0):
        raise ConfigError("tail", f"expected a radius > 0, got {radius!r}")
    if not (math.isfinite(sweep) and 0.0 < sweep <= top + ROUNDING):
        raise ConfigError("tail", f"expected 0 < sweep_deg ≤ {to_deg(top):.4g} (the last fence's angle to the belt less "
                          f"the exit guide's: a larger sweep turns the tail back against the guide), got {sweep_deg!r}")
    # The straight part is shortened so that the tail rises no further across the belt
    # than the fence's tip did plus c: by Δ = R(1 − cos sweep) − c across the belt. The
    # last fence must still let the part finish its turn: W − Δ ≥ 6a + 2c + s_N cos β_N
    # (the layout's own bound, c less for a single fence), which a wider belt makes room for.
    a = out.cover_radius
    c = CLEARANCE * a
    delta = max(radius * (1.0 - math.cos(sweep)) - c, 0.0)
    need = out.push_bounds[-1] * math.cos(beta) - (c if len(out.lengths) == 1 else 0.0)
    h_now = out.reach_of(len(out.lengths) - 1)
    sides = out.design.sides
    same = len(sides) > 1 and sides[-1] == sides[-2]
    # on the rail of the fence before, it must still reach 2a + s_N cos β_N past it, whatever the belt's width
    floor = out.reach_of(len(sides) - 2) + 2.0 * a if same else (4.0 + CLEARANCE) * a
    slack = h_now - (floor + need)
    if delta > slack + ROUNDING:
        wider = ("" if same else f", or a belt {delta - slack:.4g} {out.units} wider (belt_width)")
        raise ConfigError("tail", f"a tail of radius {radius:g} {out.units} shortens the last fence by {delta:.4g} {out.units} "
                          f"across the belt, more than the {max(slack, 0.0):.4g} {out.units} it can spare: use a smaller "
                          f"radius or sweep{wider}")
    h = h_now - delta
    lengths = out.lengths[:-1] + (h / math.sin(beta),)
    return replace(out, tail=Tail(float(radius), float(sweep)), last_reach=h, lengths=lengths)


def plan_fences(analysis: Analysis, rules: FenceRules = DEFAULT_RULES, min_margin_deg: float = DEFAULT_MIN_MARGIN_DEG,
                belt_width: float | None = None, exit_steepness_deg: float | None = None,
                exit_turns: bool = True, same_rail: bool = False) -> FenceLayout:
    """The fence design of :func:`~algrasp.planning.fences.design_fences`, ties broken by
    the total fence length of its layout, laid out on the belt with its exit guide at
    ``exit_steepness_deg`` (default 2°; the guide is not part of the tie-break); with
    ``exit_turns`` False in Berretty et al.'s model (no turn over the fences' tips); with
    ``same_rail`` consecutive fences may stand on one rail.

    Raises ConfigError (``exit_steepness_deg``) unless 0 < β_e ≤ 10°."""

    beta_e = exit_steepness(exit_steepness_deg)
    rules = replace(rules, exit_steepness=beta_e, exit_turns=bool(exit_turns), same_rail=bool(same_rail))
    model = push_model(analysis, mean_radius(analysis.part))

    def total(design: FenceDesign) -> float:
        return float(sum(layout(analysis, design, None, model).lengths))

    design = design_fences(analysis, rules, min_margin_deg, total)
    out = layout(analysis, design, belt_width, model, beta_e)
    exit_angle = None if out.exit is None else out.exit.angle
    starts = to_rad(np.arange(FOLLOW_STARTS_DEG, dtype=float))
    return replace(out, motion=fence_motion(analysis, design, exit_angle),
                   follow=follow(analysis, design, starts, exit_angle))
