"""Plans a cell controller executes: gripper angles in execution order, margins, and
verification through the transfer functions (conventions §4).

Action j (execution order) uses interval I_j = Θ_{N−j+1}. The last action is at α = 0,
so the final world orientations are the value of Θ₁'s step plus multiples of T. Going
backwards, α_j = α_{j+1} + δ_j where δ_j centres the image F(I_j) in I_{j+1}; the
slack on each side is the margin of action j + 1: how far its gripper angle may be off,
relative to the previous action's, with the plan still orienting the part.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any, Literal, NamedTuple
from weakref import WeakKeyDictionary

import numpy as np

from algrasp.errors import ConfigError, NotOrientableError
from algrasp.geometry.angles import signed_diff, to_deg, to_rad
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.functions import wrap
from algrasp.geometry.hull import ConvexHull
from algrasp.geometry.tolerances import MAX_UNCERTAINTY_RAD, ROUNDING, SYMMETRY_TOL_RAD, UNCERTAINTY_FLOOR_RAD
from algrasp.planning import limits as lim
from algrasp.planning.actions import Action
from algrasp.planning.analysis import Analysis, uses_sets
from algrasp.planning.planner import GUARD_RAD, Lifted, algorithm_a_prime, first_choice, images, nearest, self_turn, set_a_prime
from algrasp.planning.setvalued import SetTransfer
from algrasp.planning.transfer import TransferFunction
from algrasp.planning.verification import run_steps, through, verify, verify_set


@dataclass(frozen=True)
class PlanStep:
    gripper_angle: float  # radians, world
    margin: float | None  # radians; None for the first action


@dataclass(frozen=True, eq=False)
class Plan:
    """A verified plan. Angles in radians; ``to_dict`` gives the JSON plan document (degrees).

    Attributes
    ----------
    action : {"squeeze", "push_grasp"}
        The action every step takes.
    transfer : TransferFunction
        The action's transfer function F the plan was built on.
    symmetry_period : float
        The symmetry period T of F (radians).
    intervals : tuple of (float, float)
        Θ₁ … Θ_N of Algorithm A′, lifted (radians).
    steps : tuple of PlanStep
        In execution order: ``gripper_angle`` (radians, world; the last is 0) and
        ``margin`` (radians; None for the first action).
    final_orientations : tuple of float
        Where the plan leaves the part (world, [0, 2π)).
    verified : bool
        Whether running the actions' functions from every start leaves the part exactly at
        ``final_orientations`` (within ``final_uncertainty``): :func:`verify`, :func:`verify_set`.
    timings_s : dict of str to float
        Seconds spent planning and verifying.
    bounds : SetTransfer or None
        The set-valued function the plan was built on (None: the exact model).
    final_uncertainty : float
        Half-width (radians) of the interval around each final orientation in which the
        part is guaranteed to end (conventions §7); 0 in the exact model.
    robust : dict or None
        Physics and dead band used (JSON-ready), None in the exact model.
    limits : dict or None
        How far the physics ranges may reach with a plan still existing
        (:func:`algrasp.planning.limits.limits`), when searched.
    analysis : Analysis or None
        The analysis the plan was made from (its part and model): what lets a plan be
        validated, optimised or re-planned without handing the part over again.
    execution : Execution or None
        The optimised execution (``optimisation.execution.Execution``: push distances, jaw
        timing, cycle time), None until optimised; its fields join :meth:`to_dict`.

    Examples
    --------
    >>> from algrasp import plan
    >>> p = plan({"name": "r", "boundary": [[0, 0], [4, 0], [4, 2], [0, 2]]}, exact=True)
    >>> p.action, p.verified, p.final_orientations, [s.gripper_angle for s in p.steps]
    ('squeeze', True, (0.0, 3.141592653589793), [0.7853981633974483, 0.0])
    >>> p.run(np.array([0.3, 2.0])).tolist(), p.to_dict()["final_orientations_deg"]
    ([0.0, 3.141592653589793], [0.0, 180.0])
    """

    action: Action
    transfer: TransferFunction
    symmetry_period: float
    intervals: tuple[tuple[float, float], ...]  # Θ₁ … Θ_N, lifted
    steps: tuple[PlanStep, ...]  # execution order
    final_orientations: tuple[float, ...]  # world, [0, 2π)
    verified: bool
    timings_s: dict[str, float] = field(default_factory=dict)
    bounds: SetTransfer | None = None
    final_uncertainty: float = 0.0
    robust: dict[str, object] | None = None
    limits: dict[str, object] | None = None
    analysis: Analysis | None = field(default=None, repr=False, compare=False)
    execution: Any = field(default=None, repr=False, compare=False)

    def run(self, phi: FloatArray) -> FloatArray:
        """World orientations after executing the plan from ``phi`` (radians), per the
        transfer function: φ′ = F(φ − α) + α for each action. A robust plan gives the
        claimed final orientation the part ends near (within ``final_uncertainty``)."""
        phi = np.asarray(phi, dtype=float)
        if self.bounds is not None:
            lo, hi = self.run_set(phi, phi)
            return self.nearest_final(0.5 * (lo + hi))
        return through(self.transfer, self.steps, phi)

    def run_set(self, lo: FloatArray, hi: FloatArray, steps: int | None = None) -> tuple[FloatArray, FloatArray]:
        """Hull of the world orientations after the plan (its first ``steps`` actions, or
        all) from [lo, hi] (set semantics)."""
        assert self.bounds is not None
        return run_steps(self.bounds, self.steps[:steps], lo, hi)

    def nearest_final(self, phi: FloatArray) -> FloatArray:
        """The claimed final orientation nearest to each φ (radians, [0, 2π))."""
        want = np.array(self.final_orientations)
        diff = signed_diff(np.asarray(phi, dtype=float)[..., None], want)
        return np.asarray(want[np.argmin(np.abs(diff), axis=-1)])

    def trace(self, phi0: float) -> list[float]:
        """World orientation before the plan and after each action (radians); for a
        robust plan the middle of the interval the part can be in after each action."""
        out = [phi0]
        for k, s in enumerate(self.steps, 1):
            if self.bounds is None:
                out.append(float(self.transfer(out[-1] - s.gripper_angle) + s.gripper_angle))
            else:
                lo, hi = self.run_set(np.array([phi0]), np.array([phi0]), k)
                out.append(float(0.5 * (lo[0] + hi[0])))
        return out

    def to_dict(self) -> dict[str, object]:
        """The plan document (degrees): :class:`~algrasp.planning.documents.PlanDocument`'s codec."""
        from algrasp.planning.documents import PlanDocument

        doc = PlanDocument.from_plan(self).to_json()
        return doc if self.execution is None else self.execution.apply_to(doc)


def transfer_for(analysis: Analysis, action: Action) -> TransferFunction:
    if action == "squeeze":
        if not analysis.squeeze.steps:
            raise NotOrientableError("constant_width", "the part has constant width: its squeeze function has no "
                                     "step, so no squeeze plan can orient it (try push_grasp)")
        return analysis.squeeze
    if not analysis.push_grasp.steps:
        raise NotOrientableError("no_step", "the push-grasp function has no step: no push-grasp plan can orient the part")
    return analysis.push_grasp


def gripper_steps(F: TransferFunction, intervals: list[tuple[float, float]], T: float,
                  upper: TransferFunction | None = None, first_images: list[tuple[float, float]] | None = None,
                  period: float | None = None, lifted: Lifted | None = None) -> tuple[list[PlanStep], tuple[float, float] | None]:
    """Execution-order gripper angles (last at 0) and margins from Θ₁ … Θ_N, and the arc
    the first action's image was placed as (None for a one-action plan).

    Each action's image is centred in the next action's interval (the paper's choice: the
    widest margin). The first action's input is the whole circle, so its image is any arc
    holding everything one action can leave the part in and leaving out one gap between
    those outcomes (``first_images``, by default :meth:`TransferFunction.circle_images`).
    Of the arcs whose margin is at least the plan's smallest (the gripper angle error the
    plan tolerates, which the choice leaves unchanged) the one needing the least turning
    is used. An action maps to itself under a turn by its period P, and by T where its
    margin is wide enough to absorb the symmetry tolerance, so each angle is taken nearest
    the next action's modulo that turn: no turn between actions exceeds T/2 (P/2).
    ``period``: the action's P (π for a squeeze, 2π for a push-grasp; default F's, which
    set-valued bounds store over T). ``lifted``: F's (and upper's) :class:`~algrasp.planning.planner.Lifted`, if made.
    """
    P = F.period if period is None else period
    order = intervals[::-1]  # I_1 … I_N
    n = len(order)
    if n == 1:
        return [PlanStep(0.0, None)], None
    alphas = [0.0] * n
    margins: list[float | None] = [None] * n
    later = images(F, order[1:-1], upper, lifted)  # of I_2 … I_{N−1}: the last action's is not needed
    for j in range(n - 2, 0, -1):
        (lo, hi), (a, b) = later[j - 1], order[j + 1]
        margin = max(0.0, 0.5 * ((b - a) - (hi - lo)))
        alphas[j] = nearest(alphas[j + 1] + 0.5 * (a + b - lo - hi), alphas[j + 1], self_turn(P, T, margin))
        margins[j + 1] = margin
    arcs = F.circle_images(T) if first_images is None else first_images
    a, b = order[1]
    fit = [0.5 * ((b - a) - (hi - lo)) for lo, hi in arcs]  # room on each side; < 0: does not fit
    # At least the plan's tolerance and the guard room every image keeps; the widest always.
    need = min(max(min([m for m in margins[2:] if m is not None], default=np.inf), GUARD_RAD), max(fit))
    k, alphas[0] = first_choice(arcs, fit, need, order[1], alphas[1], P, T)
    margins[1] = max(0.0, fit[k])
    return [PlanStep(float(al), m) for al, m in zip(alphas, margins)], arcs[k]


def final_orientations(F: TransferFunction, intervals: list[tuple[float, float]], T: float) -> list[float]:
    value = F(intervals[0][0])
    k = int(round(2 * np.pi / T))
    return sorted(wrap(value + i * T, 2 * np.pi, ROUNDING) for i in range(k))


LimitsWanted = Literal["none", "refusal", "headline", "all"]
"""Which physics limits a plan searches (robust model; conventions §8): ``none`` not even
on a refusal (a catalogue screen: a refusal then costs one planning attempt, not the
~15 probes of its limit search); ``refusal`` every limit on a refusal only; ``headline``
also the largest jaw friction with a plan; ``all`` every limit either way."""
LIMITS_WANTED: tuple[str, ...] = ("none", "refusal", "headline", "all")


def make_plan(analysis: Analysis, action: Action, min_margin_deg: float = 0.0, limits: LimitsWanted = "refusal") -> Plan:
    """The shortest verified plan of ``action`` for the analysed part, with the physics
    limits asked for (robust model: ``headline`` is the largest jaw friction).

    Raises NotOrientableError (constant width, no step, margin too large, too uncertain);
    in the robust model a refusal carries every limit (``limits``) and says them, unless
    ``limits`` is ``none``. The refusal's limit search runs when its ``limits``,
    ``message``, ``str`` or ``to_dict`` is first read (every interface that shows a refusal
    reads them; a caller that only catches it pays one planning attempt).
    """
    if action not in ("squeeze", "push_grasp"):
        raise ConfigError("action", f"expected squeeze or push_grasp, got {action!r}")
    if analysis.robust is None:
        return plan_once(analysis, action, min_margin_deg)
    try:
        plan = plan_once(analysis, action, min_margin_deg)
    except NotOrientableError as e:
        lim.remember(analysis, action, plan_once, min_margin_deg, False)
        if limits == "none":
            raise NotOrientableError(e.reason, f"{e.message} (physics limits not searched: limits 'none')") from None
        raise NotOrientableError(e.reason, e.message, search=_refusal_limits(analysis, action, e.message, min_margin_deg)) from None
    lim.remember(analysis, action, plan_once, min_margin_deg, True)
    if limits in ("none", "refusal"):
        return plan
    wanted = lim.HEADLINE if limits == "headline" else tuple(lim.SEARCHES)
    return replace(plan, limits=lim.limits(analysis, action, plan_once, wanted, min_margin_deg, refused=False))


def _refusal_limits(analysis: Analysis, action: Action, message: str,
                    min_margin_deg: float) -> Callable[[], tuple[str, dict[str, Any]]]:
    """The limit search of a refusal, left for the refusal to run when its limits or
    message are first read (:class:`~algrasp.errors.NotOrientableError`): a caller that
    only needs to know that no plan exists does not pay the ~5–25 probes."""
    def search() -> tuple[str, dict[str, Any]]:
        assert analysis.robust is not None
        found = lim.limits(analysis, action, plan_once, margin_deg=min_margin_deg, refused=True)
        if action == "squeeze":
            found["push_grasp_orients"] = lim.plan_exists(analysis, analysis.robust.physics, "push_grasp", plan_once,
                                                          min_margin_deg)
        other = "; a push-grasp plan exists under these ranges" if found.get("push_grasp_orients") else ""
        return f"{message}. Under the given ranges: {found['advice']}{other}", found
    return search


def plan_once(analysis: Analysis, action: Action, min_margin_deg: float = 0.0) -> Plan:
    """:func:`make_plan` without limits: one planning attempt (the plan holds ``analysis``)."""
    if not (np.isfinite(min_margin_deg) and 0.0 <= min_margin_deg < 180.0):
        raise ConfigError("min_margin_deg", f"must be in [0, 180), got {min_margin_deg}")
    band = None if analysis.robust is None else analysis.robust.band
    robust = analysis.robust
    if band is not None and robust is not None and uses_sets(band, robust.physics):
        return _robust_plan_verified(analysis, action, to_rad(min_margin_deg))
    # κ = 0 (no friction, exact drawing): the paper's exact model, conventions §7.
    F = transfer_for(analysis, action)
    t0 = time.perf_counter()
    T = F.symmetry_period(SYMMETRY_TOL_RAD)
    intervals = algorithm_a_prime(F, T, to_rad(min_margin_deg))
    steps, _ = gripper_steps(F, intervals, T)
    finals = final_orientations(F, intervals, T)
    t1 = time.perf_counter()
    plan = Plan(action, F, T, tuple(intervals), tuple(steps), tuple(finals), False)
    ok = verify(plan)
    t2 = time.perf_counter()
    if not ok:
        raise NotOrientableError("verification_failed", "the plan did not verify: please report this part")
    return Plan(action, F, T, tuple(intervals), tuple(steps), tuple(finals), True,
                {"planning": t1 - t0, "verification": t2 - t1}, analysis=analysis)


def _set_for(analysis: Analysis, action: Action) -> SetTransfer:
    assert analysis.robust is not None
    transfer_for(analysis, action)  # no step even without the dead band: say why (constant width, …)
    S: SetTransfer | None = getattr(analysis.robust, action)
    if S is None:
        raise NotOrientableError("dead_band", analysis.robust.reasons[action])
    if not S.orientable:
        what = "squeeze" if action == "squeeze" else "push-grasp"
        raise NotOrientableError("constant_width" if action == "squeeze" else "no_step",
                                 f"with the dead band every orientation may stay where it is: no {what} plan can orient "
                                 "the part (its diameter/radius slopes never beat the support friction and shape tolerance)")
    return S


RETRY_MARGINS_RAD = (0.0, 0.008726646259971648, 0.03490658503988659)  # +0°, +0.5°, +2°
"""Extra margins a robust plan is made with again when it does not verify: Algorithm A′
places intervals from interval images, and a single orientation whose image is wide (a
shallow basin that may go either way) can fall just outside; verification is the truth,
so a plan is only returned once it verifies."""


def _robust_plan_verified(analysis: Analysis, action: Action, margin: float) -> Plan:
    """:func:`_robust_plan`, again with more margin while it does not verify."""
    for extra in RETRY_MARGINS_RAD:
        try:
            return _robust_plan(analysis, action, margin + extra)
        except NotOrientableError as e:
            if e.reason != "verification_failed" or extra == RETRY_MARGINS_RAD[-1]:
                raise
    raise AssertionError("unreachable")


def _robust_plan(analysis: Analysis, action: Action, margin: float) -> Plan:
    """The shortest plan on the set-valued function (conventions §7), verified on it."""
    S = _set_for(analysis, action)
    assert analysis.robust is not None
    F = analysis.squeeze if action == "squeeze" else analysis.push_grasp
    t0, T = time.perf_counter(), S.symmetry
    lifted = Lifted.of(S.lower, S.upper)  # read by the search, the first image and the gripper angles
    try:
        intervals = set_a_prime(S.lower, S.upper, T, S.circle_width, margin, 2.0 * MAX_UNCERTAINTY_RAD, lifted=lifted)
    except NotOrientableError as e:
        if e.reason != "margin_too_large" or margin > 0.0:
            raise
        band = analysis.robust.band
        raise NotOrientableError("dead_band", f"{e.message.split(': with that margin ')[-1]}: the support friction and "
                                 f"shape tolerance (κ_d = {band.kappa_d:.3g}, κ_r = {band.kappa_r:.3g} {analysis.part.units}/rad) "
                                 "leave no sequence of actions that collapses every orientation; a larger grip force, "
                                 "less friction, or --exact (the frictionless model) may") from None
    lo, hi = images(S.lower, intervals[:1], S.upper, lifted)[0]
    uncertainty = max(0.5 * (hi - lo) + GUARD_RAD + _edge_tilt(analysis, lo, hi), UNCERTAINTY_FLOOR_RAD)
    if uncertainty > MAX_UNCERTAINTY_RAD:  # before the gripper angles: they cannot change it
        raise NotOrientableError("uncertain", f"the part ends within ±{to_deg(uncertainty):.3g}° at best, more "
                                 f"than the ±{to_deg(MAX_UNCERTAINTY_RAD):g}° a plan may claim")
    steps, first = gripper_steps(S.lower, intervals, T, S.upper, S.circle_images(), F.period, lifted)
    k = int(round(2 * np.pi / T))
    finals = sorted(wrap(0.5 * (lo + hi) + i * T, 2 * np.pi, ROUNDING) for i in range(k))
    t1 = time.perf_counter()
    ok = verify_set(_Draft(F, steps, finals, uncertainty, S), S.circle_images()[0] if first is None else first)
    t2 = time.perf_counter()
    if not ok:
        raise NotOrientableError("verification_failed", "the plan did not verify: please report this part")
    return Plan(action, F, T, tuple(intervals), tuple(steps), tuple(finals), True,
                {"planning": t1 - t0, "verification": t2 - t1}, S, uncertainty,
                {**analysis.robust.physics.to_dict(), **analysis.robust.band.to_dict()}, analysis=analysis)


class _Draft(NamedTuple):
    """What :func:`verify_set` reads of a plan not yet made (the plan is made once, verified)."""

    transfer: TransferFunction
    steps: list[PlanStep]
    final_orientations: list[float]
    final_uncertainty: float
    bounds: SetTransfer


EDGE_NORMAL_RAD = 1e-6
"""A hull edge whose normal is this close to the jaws' normal lies flat on a jaw."""
_EDGES: WeakKeyDictionary[ConvexHull, tuple[FloatArray, FloatArray]] = WeakKeyDictionary()
"""Each hull's edge lengths and flat angles (:func:`_edge_tilt`; every plan and limit probe of a part reads them)."""


def _edge_tilt(analysis: Analysis, lo: float, hi: float) -> float:
    """How far (radians) the final orientations may move because the drawing is only
    within ε of the part: an edge of length L that can lie flat on a jaw anywhere in the
    final interval [lo, hi] (relative, radians) can be tilted by up to 2ε/L in the real
    part (its end points move by ε), and it may then come to rest that much beyond the
    interval. 0 when no edge can lie flat there."""
    assert analysis.robust is not None
    eps = analysis.robust.band.value_err  # the drawing's error or the profile tolerance, the larger
    got = _EDGES.get(analysis.part.hull)
    if got is None:  # the part's edges (lengths, the angles they lie flat at), once per hull
        e = np.array(analysis.part.hull.edges, dtype=float).reshape(-1, 2, 2)  # (m, 2, 2): each value as edge by edge
        dx, dy = e[:, 1, 0] - e[:, 0, 0], e[:, 1, 1] - e[:, 0, 1]
        # the edge is flat on a jaw at θ with π/2 − θ ≡ its normal (mod π)
        got = _EDGES[analysis.part.hull] = np.hypot(dx, dy), np.pi / 2 - np.arctan2(-dx, dy)
        got[0].flags.writeable = got[1].flags.writeable = False
    length, flat = got
    t = 2.0 * eps / length
    rel = (flat - lo + t + EDGE_NORMAL_RAD) % np.pi
    tilts: list[float] = t[rel <= (hi - lo) + 2.0 * (t + EDGE_NORMAL_RAD)].tolist()
    return max([0.0, *tilts])  # the first largest, as edge by edge
