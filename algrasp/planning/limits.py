"""Limits that answer the engineer's question (docs/conventions.md §8): for one part and
action, how far each physical range may reach with a plan still existing.

Each limit is found by bisection on one range end (or the profile tolerance) with the
others as given: the largest jaw friction, the smallest and largest support friction and
part mass, the largest profile tolerance. Each probe is one robust analysis on the part's
exact functions (computed once) and one plan, so a search costs about
``BISECTIONS`` × (analysis + plan); all six about 50 of them. Pure: no I/O.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

from algrasp.errors import NotOrientableError
from algrasp.planning.analysis import Analysis, plan_reads, robust_analysis, set_keys
from algrasp.planning.deadband import DeadBand, dead_band, profile_floor
from algrasp.planning.physics import Physics

BISECTIONS = 8
"""Halvings per search (in log scale): a limit to about 2 % of its value."""


@dataclass(frozen=True)
class Search:
    """One limit: ``key`` of Physics, which end (0 lo, 1 hi, None for a scalar), and the
    hard end of the search (the value least likely to allow a plan)."""

    name: str
    key: str
    end: int | None
    hard: Callable[[Physics, Analysis], float]
    easy: Callable[[Physics, Analysis], float]


SEARCHES: dict[str, Search] = {s.name: s for s in (
    Search("jaw_friction_max", "jaw_friction", 1, lambda p, a: 1.0, lambda p, a: 0.0),
    Search("support_friction_min", "support_friction", 0, lambda p, a: 0.0, lambda p, a: p.support_friction[1]),
    Search("support_friction_max", "support_friction", 1, lambda p, a: 1.5, lambda p, a: p.support_friction[0]),
    Search("part_mass_kg_min", "part_mass_kg", 0, lambda p, a: 0.0, lambda p, a: p.part_mass_kg[1]),
    Search("part_mass_kg_max", "part_mass_kg", 1, lambda p, a: 10.0 * max(p.part_mass_kg[1], 1e-3),
           lambda p, a: p.part_mass_kg[0]),
    Search("profile_tolerance_max", "profile_tolerance", None,
           lambda p, a: 20.0 * profile_floor(a.part, replace(p, profile_tolerance=None), _size(a)), lambda p, a: 0.0),
)}
LOG_OFFSET_REL = 1e-3
"""v0 of the log-scale bisection, relative to the searched span: limits below it resolve
to about v0."""
LOG_OFFSET_FLOOR = 1e-9
"""v0 when the span is empty."""
HEADLINE = ("jaw_friction_max",)
"""The limit reported with every plan; the rest on request and with every refusal."""


def _size(analysis: Analysis) -> float | None:
    """The part's nominal size as its dead-band terms hold it (None: measured again)."""
    terms = None if analysis.robust is None else analysis.robust.terms
    return None if terms is None else terms.nominal_size


def _with(physics: Physics, s: Search, v: float) -> Physics:
    if s.end is None:
        return physics.with_values(**{s.key: v})
    lo, hi = getattr(physics, s.key)
    span = (v, max(v, hi)) if s.end == 0 else (min(lo, v), v)
    return physics.with_range(s.key, span)


def _current(physics: Physics, s: Search, analysis: Analysis) -> float:
    if s.end is None:
        v = physics.profile_tolerance
        return profile_floor(analysis.part, physics, _size(analysis)) if v is None else v
    return float(getattr(physics, s.key)[s.end])


Planner = Callable[[Analysis, Any, float], Any]
"""One planning attempt (``algrasp.planning.plans.plan_once``): passed in, so this module
does not import the planner that reports its limits."""


class Known(dict[Physics, bool]):
    """Probes already made in one :func:`limits` call: the searches share their start (the
    given ranges, which a refused plan has already tried) and often their easy ends. (The
    set-valued functions the probes build are shared wider, by every probe on the
    analysis: :attr:`~algrasp.planning.analysis.RobustAnalysis.sets`.)"""


def plan_exists(analysis: Analysis, physics: Physics, action: str, planner: Planner, margin_deg: float,
                known: Known | None = None) -> bool:
    """Whether a robust plan of ``action`` exists for the part under ``physics``
    (looked up in, and added to, ``known``; then by what the plan reads in the analysis's
    :attr:`~algrasp.planning.analysis.SetMemo.plans`, shared by every probe and plan on it)."""
    if known is not None and physics in known:
        return known[physics]
    base = analysis.robust
    band = None if base is None or base.terms is None else dead_band(analysis.part, physics, analysis.tol, base.terms)
    key = _reads(analysis, physics, action, planner, margin_deg, band)
    plans = {} if key is None or base is None else base.sets.plans
    exists = plans.get(key) if key is not None else None
    if exists is None:
        exists = _plan_exists(analysis, physics, action, planner, margin_deg, band)
        if key is not None:
            plans[key] = exists
    if known is not None:
        known[physics] = exists
    return exists


def remember(analysis: Analysis, action: str, planner: Planner, margin_deg: float, exists: bool) -> None:
    """Note whether ``planner`` found a plan of ``action`` on the analysis under its own
    physics (a plan or refusal already made): a later probe reading the same (the
    refusal's ``push_grasp_orients``, a search's start) is not planned again."""
    key = _reads(analysis, None, action, planner, margin_deg)
    if key is not None and analysis.robust is not None:
        analysis.robust.sets.plans[key] = exists


def _reads(analysis: Analysis, physics: Physics | None, action: str, planner: Planner,
           margin_deg: float, band: DeadBand | None = None) -> tuple[object, ...] | None:
    """What a plan of ``action`` under ``physics`` (None: the analysis's) reads
    (:func:`~algrasp.planning.analysis.plan_reads`), behind the planner and margin; None
    without the part's dead-band terms (the exact model). O(1): the dead band only."""
    base = analysis.robust
    if base is None or base.terms is None:
        return None
    # The analysis's own band was made from its physics as a probe's is (dead_band of the same terms).
    if band is None:
        band = base.band if physics is None else dead_band(analysis.part, physics, analysis.tol, base.terms)
    physics = base.physics if physics is None else physics
    keys = set_keys(analysis.diameter.kind, analysis.radius.kind, band, physics, analysis.tol.angle_rad)
    return (planner, margin_deg, *plan_reads(keys, band, physics, action))


def _plan_exists(analysis: Analysis, physics: Physics, action: str, planner: Planner, margin_deg: float,
                 band: DeadBand | None = None) -> bool:
    try:
        base = analysis.robust
        terms, sets = (None, None) if base is None else (base.terms, base.sets)
        robust = robust_analysis(analysis.part, analysis.diameter, analysis.radius, physics, analysis.tol, terms, action,
                                 sets, band)
        planner(replace(analysis, robust=robust), action, margin_deg)
    except NotOrientableError:
        return False
    return True


def search_limit(analysis: Analysis, physics: Physics, action: str, s: Search, planner: Planner,
                 margin_deg: float = 0.0, known: Known | None = None) -> dict[str, Any]:
    """``{"value": v, "bounded": bool}``: the last value toward the hard end at which a
    plan exists (``bounded`` False when even the hard end allows one); value None when
    not even the easy end does."""
    def ok(v: float) -> bool:
        return plan_exists(analysis, _with(physics, s, v), action, planner, margin_deg, known)

    cur, hard = _current(physics, s, analysis), s.hard(physics, analysis)
    good, bad = (cur, hard) if ok(cur) else (s.easy(physics, analysis), cur)
    if good == bad or (good != cur and not ok(good)):
        return {"value": None, "bounded": True}
    if bad == hard and ok(hard):
        return {"value": hard, "bounded": False}
    # Bisect in u = log(v + v0): small limits (a profile tolerance of microns) resolve as
    # well as large ones; v0 keeps 0 reachable.
    v0 = LOG_OFFSET_REL * abs(hard - s.easy(physics, analysis)) or LOG_OFFSET_FLOOR
    ug, ub = math.log(good + v0), math.log(bad + v0)
    for _ in range(BISECTIONS):
        mid = 0.5 * (ug + ub)
        ug, ub = (mid, ub) if ok(math.exp(mid) - v0) else (ug, mid)
    value = math.exp(ug) - v0
    return {"value": value if value > v0 else 0.0, "bounded": True}  # below v0: only the search's own resolution


def limits(analysis: Analysis, action: str, planner: Planner, names: tuple[str, ...] = tuple(SEARCHES),
           margin_deg: float = 0.0, refused: bool | None = None) -> dict[str, Any]:
    """The named limits for ``action`` under the analysis's physics (robust model only),
    with a sentence for the engineer under ``"advice"``. ``refused``: whether planning
    under the given ranges has already failed (True) or succeeded (False), so no probe
    repeats it."""
    assert analysis.robust is not None
    physics = analysis.robust.physics
    known = Known() if refused is None else Known({physics: not refused})
    hopeless = _hopeless(analysis, physics, action, planner, margin_deg, known, names) if refused else set()
    out: dict[str, Any] = {n: {"value": None, "bounded": True} if n in hopeless else
                           search_limit(analysis, physics, action, SEARCHES[n], planner, margin_deg, known) for n in names}
    stuck = all(out[n]["value"] is None for n in names)
    if physics.placement == "any" and action == "squeeze" and stuck:
        out["placement_centred"] = plan_exists(analysis, replace(physics, placement="centred"), action, planner, margin_deg,
                                               known)
    if stuck and not out.get("placement_centred"):
        out["ideal_cell"] = _in_ideal_cell(analysis, physics, action, planner, margin_deg, known)
    out["advice"] = advice(action, out, analysis.part.units)
    return out


SCREENS = (("jaw_friction_max", "support_friction_min", "part_mass_kg_min"), ("support_friction_max", "part_mass_kg_max"))
"""Range searches screened together after a refusal: each group's easy ends applied at
once (with frictionless jaws) are at least as easy as any one of them with the others as
given, so if that combined cell has no plan (monotony, which the bisections assume too)
none of the group's searches can find one; two probes instead of five when no single
range helps, the common refusal under the default ranges."""


def _hopeless(analysis: Analysis, physics: Physics, action: str, planner: Planner, margin_deg: float, known: Known,
              names: tuple[str, ...]) -> set[str]:
    """The searches of :data:`SCREENS` that cannot succeed; the second group is probed
    only when the first fails (when it passes, single ranges tend to help: no saving)."""
    out: set[str] = set()
    for group in SCREENS:
        wanted = [n for n in group if n in names]
        if len(wanted) < 2:
            return out
        easy = physics.with_range("jaw_friction", (0.0, 0.0))
        for n in wanted:
            easy = _with(easy, SEARCHES[n], SEARCHES[n].easy(physics, analysis))
        if plan_exists(analysis, easy, action, planner, margin_deg, known):
            return out
        out.update(wanted)
    return out


IDEAL_SEARCHES = ("jaw_friction_max", "profile_tolerance_max")


def _in_ideal_cell(analysis: Analysis, physics: Physics, action: str, planner: Planner, margin_deg: float,
                   known: Known) -> dict[str, Any]:
    """When no single range helps: whether the part is orientable in the ideal cell at the
    middle of the ranges (centred, frictionless jaws, exact part, exact centre of mass),
    and there how much jaw friction and profile tolerance it tolerates."""
    mid = {k: (0.5 * sum(getattr(physics, k)),) * 2 for k in ("support_friction", "part_mass_kg", "grip_force_n")}
    ideal = physics.with_values(**mid, jaw_friction=(0.0, 0.0), profile_tolerance=0.0, com_tolerance=0.0,
                                placement="centred")
    if not plan_exists(analysis, ideal, action, planner, margin_deg, known):
        return {"orientable": False}
    return {"orientable": True, **{n: search_limit(analysis, ideal, action, SEARCHES[n], planner, margin_deg, known)
                                   for n in IDEAL_SEARCHES}}


WORDS = {"jaw_friction_max": ("jaw μ", "≤", ""), "support_friction_min": ("support μ", "≥", ""),
         "support_friction_max": ("support μ", "≤", ""), "part_mass_kg_min": ("part mass", "≥", " kg"),
         "part_mass_kg_max": ("part mass", "≤", " kg"), "profile_tolerance_max": ("profile tolerance", "≤", " {units}")}


ZERO_WORDS = {"jaw_friction_max": "frictionless jaws only (a linear bearing)",
              "profile_tolerance_max": "an exact part only (no profile tolerance)"}


def advice(action: str, found: dict[str, Any], units: str) -> str:
    """The limits in words, e.g. "orientable by squeeze with jaw μ ≤ 0.08 (mount PTFE pads
    or a linear bearing above that)"."""
    what = "squeeze" if action == "squeeze" else "push-grasp"
    within, blocked = [], []
    for name, (label, rel, unit) in WORDS.items():
        got = found.get(name)
        if not isinstance(got, dict):
            continue
        if got["value"] is None:
            blocked.append(label)
        elif got["bounded"] and got["value"] == 0.0 and name in ZERO_WORDS:
            within.append(ZERO_WORDS[name])
        elif got["bounded"]:
            tail = " (mount PTFE pads or a linear bearing above that)" if name == "jaw_friction_max" else ""
            within.append(f"{label} {rel} {got['value']:.3g}{unit.format(units=units)}{tail}")
    out = [f"orientable by {what} with {', '.join(within)}"] if within else []
    if blocked:
        out.append(f"no {' or '.join(dict.fromkeys(blocked))} alone makes it orientable by {what} with the other ranges as given")
    if found.get("placement_centred"):
        out.append(f"orientable by {what} with centred placement (both jaws touching together)")
    ideal = found.get("ideal_cell")
    if isinstance(ideal, dict):
        out.append(_ideal_words(what, ideal, units))
    return "; ".join(out) if out else f"orientable by {what} over the whole searched span"


def _ideal_words(what: str, ideal: dict[str, Any], units: str) -> str:
    if not ideal.get("orientable"):
        return f"not orientable by {what} even with centred placement, frictionless jaws and an exact part"
    there = []
    for name in IDEAL_SEARCHES:
        got = ideal.get(name) or {}
        if got.get("value") is not None and got.get("bounded"):
            label, rel, unit = WORDS[name]
            there.append(f"{label} {rel} {got['value']:.3g}{unit.format(units=units)}")
    return (f"orientable by {what} with centred placement, an exact part and frictionless jaws"
            + (f" (there: {', '.join(there)})" if there else ""))
