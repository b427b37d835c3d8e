"""One call from a validated part to everything the paper derives from it.

``analyse_part(part)`` → :class:`Analysis`: diameter and radius functions with their
extrema, and the squeeze Γ, push p and push-grasp Γ∘p transfer functions.
Pure: no I/O; ``to_dict`` gives the JSON object of ``algrasp analyze --json``.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.fft  # noqa: F401  (the symmetry screen's: at import, not inside a fresh process's first analysis)

from algrasp.errors import ConfigError, NotOrientableError
from algrasp.geometry.functions import SupportPairFunction, analyse, wrap
from algrasp.geometry.part import Part, load_part
from algrasp.geometry.tolerances import DEFAULT_TOLERANCES, SYMMETRY_TOL_RAD, Tolerances
from algrasp.planning.deadband import DEFAULT_PHYSICS, DeadBand, PartTerms, Physics, dead_band, part_terms
from algrasp.planning.documents import AnalysisDocument, FunctionDocument, SetTransferDocument, TransferDocument
from algrasp.planning.physics import IDEAL_CELL
from algrasp.planning.placement import off_centre_squeeze
from algrasp.planning.setvalued import SetTransfer, set_transfer
from algrasp.planning.transfer import TransferFunction, from_runs


@dataclass(frozen=True)
class Model:
    """Which model a request analyses and plans with: the robust model of conventions
    §7 (default: dead band from ``physics``, tessellated arcs recognised) or the paper's
    exact frictionless model (``exact``, the CLI's ``--exact``).

    Parameters
    ----------
    exact : bool, default False
        The paper's exact frictionless model.
    physics : Physics, default DEFAULT_PHYSICS
        The cell's physics ranges: what robust plans hold for, and what validation
        simulates (in either model).

    Examples
    --------
    >>> Model().exact, Model(exact=True).to_options()
    (False, {'exact': True})
    >>> Model.from_options({"physics": {"jaw_friction": 0.3}}).physics.jaw_friction
    (0.3, 0.3)
    """

    exact: bool = False
    physics: Physics = field(default_factory=lambda: DEFAULT_PHYSICS)

    @staticmethod
    def from_options(options: Mapping[str, Any], legacy_exact: bool = False, cell: Physics = DEFAULT_PHYSICS) -> Model:
        """From request options ``{"exact": bool, "physics": {...}}`` over the ``cell``'s
        physics (ranges as numbers or ``[lo, hi]``: :meth:`Physics.merged`). Records
        written before the robust model have neither key: ``legacy_exact`` reads them as exact."""
        exact = options.get("exact", legacy_exact)
        if not isinstance(exact, bool):
            raise ConfigError("exact", f"expected true or false, got {exact!r}")
        return Model(exact, cell.merged(options.get("physics") or {}))

    @staticmethod
    def from_record(options: Mapping[str, Any]) -> Model:
        """The model of a recorded request (a batch design run keeps it under "design").
        Records from before the robust model are exact; records from before physics
        ranges (their physics has no ``placement``) were made in the ideal cell."""
        design = options.get("design")
        opts = design if isinstance(design, Mapping) else options
        physics = opts.get("physics")
        legacy = not (isinstance(physics, Mapping) and "placement" in physics)
        return Model.from_options(opts, legacy_exact=True, cell=IDEAL_CELL if legacy else DEFAULT_PHYSICS)

    def to_options(self) -> dict[str, Any]:
        """What a run record keeps: the whole physics (the defaults may change)."""
        return {"exact": self.exact, **({} if self.exact else {"physics": self.physics.to_dict()})}


ROBUST = Model()
EXACT = Model(exact=True)
IDEAL = Model(physics=IDEAL_CELL)
"""The robust model in the ideal cell (:data:`~algrasp.planning.physics.IDEAL_CELL`)."""


@dataclass(frozen=True, eq=False)
class RobustAnalysis:
    """The set-valued functions of conventions §7 under one dead band. A function is
    None when the part may turn without end under it (``reasons`` says why)."""

    physics: Physics
    band: DeadBand
    squeeze: SetTransfer | None
    push: SetTransfer | None
    push_grasp: SetTransfer | None
    reasons: dict[str, str]
    terms: PartTerms | None = None
    """The part's own dead-band terms, for analyses of the same part under other physics."""
    sets: SetMemo = field(default_factory=lambda: SetMemo(), repr=False, compare=False)
    """The set-valued functions built for this part's d and r so far, under any physics:
    the probes of every limit search on the analysis (both actions') share them."""

    def to_dict(self) -> dict[str, object]:
        out: dict[str, object] = {"physics": self.physics.to_dict(), "dead_band": self.band.to_dict()}
        for name in ("squeeze", "push", "push_grasp"):
            S = getattr(self, name)
            out[name] = {"orientable": False, "reason": self.reasons[name]} if S is None else \
                SetTransferDocument.from_set(S).to_json()
        return out


@dataclass(frozen=True, eq=False)
class Analysis:
    """Everything the paper derives from one part, as :func:`algrasp.analyse` (or
    :func:`analyse_part`) makes it. Angles in radians; ``to_dict()`` is the ``algrasp
    analyze --json`` object, in degrees.

    Attributes
    ----------
    part : Part
        The part analysed.
    diameter, radius : SupportPairFunction
        d(θ) (period π) and r(θ) (period 2π, about the centre of mass), with their extrema
        and constant intervals (part units).
    squeeze, push, push_grasp : TransferFunction
        Γ, p and Γ∘p (conventions §3): steps and ramps over one period.
    tol : Tolerances
        The tolerances used.
    robust : RobustAnalysis or None
        Dead band and set-valued functions of the robust model (conventions §7); None: the
        paper's exact frictionless model (``--exact``).
    squeeze_orientable : bool
        False for parts of constant width: Γ has no step (paper §4, conventions §6).

    Examples
    --------
    >>> from algrasp import load_part
    >>> a = analyse_part(load_part({"name": "r", "boundary": [[0, 0], [4, 0], [4, 2], [0, 2]]}))
    >>> round(a.diameter(0.0), 9), a.squeeze_orientable, [e.kind for e in a.radius.extrema][:2]
    (2.0, True, ['min', 'max'])
    >>> [step["fixed_point_deg"] for step in a.to_dict()["squeeze"]["steps"]]
    [90.0, 0.0]
    """

    part: Part
    diameter: SupportPairFunction
    radius: SupportPairFunction
    squeeze: TransferFunction
    push: TransferFunction
    push_grasp: TransferFunction
    tol: Tolerances
    robust: RobustAnalysis | None = None

    @property
    def squeeze_orientable(self) -> bool:
        """False for parts of constant width: Γ has no step (paper §4, conventions §6)."""
        return bool(self.squeeze.steps)

    def to_dict(self) -> dict[str, object]:
        """The ``algrasp analyze --json`` object (degrees, lists sorted by start), through
        :class:`~algrasp.planning.documents.AnalysisDocument`'s codec."""
        return self.document().to_json()

    def document(self) -> AnalysisDocument:
        """This analysis as a typed document (radians)."""
        part = {"name": self.part.name, "units": self.part.units, "area": self.part.area,
                "hull_perimeter": self.part.hull.perimeter, "center_of_mass": list(self.part.center_of_mass),
                "center_of_mass_given": self.part.com_given}
        transfers = {name: _transfer_document(name, F) for name, F in
                     (("squeeze", self.squeeze), ("push", self.push), ("push_grasp", self.push_grasp))}
        return AnalysisDocument(part, _function_document(self.diameter), _function_document(self.radius),
                                transfers["squeeze"], transfers["push"], transfers["push_grasp"],
                                "exact" if self.robust is None else "robust",
                                None if self.robust is None else self.robust.to_dict())


def _function_document(f: SupportPairFunction) -> FunctionDocument:
    return FunctionDocument(tuple((e.theta, e.value, e.kind, e.equilibrium) for e in f.extrema),
                            tuple((a, b) for a, b in f.constant_intervals))


def _transfer_document(name: str, F: TransferFunction) -> TransferDocument:
    P = F.period
    steps = tuple((p.start, p.end, wrap(p.value, P, SYMMETRY_TOL_RAD)) for p in F.steps if p.value is not None)
    reason = None if F.steps else ("constant diameter: no step, so no squeeze plan can orient this part"
                                   if name == "squeeze" else "no step: the function is the identity everywhere")
    return TransferDocument(P, F.symmetry_period(SYMMETRY_TOL_RAD), steps, tuple((p.start, p.end) for p in F.ramps),
                            bool(F.steps), reason)


NOT_BUILT = "not built: a probe of one action builds only what that action's plan reads"


def analyse_part(part: Part, tol: Tolerances = DEFAULT_TOLERANCES, physics: Physics | None = None) -> Analysis:
    """Diameter/radius extrema and all three transfer functions. See module docs.

    With ``physics`` the set-valued functions of conventions §7 are added (the robust
    model every interface uses by default); None keeps the paper's exact model.
    """
    d = analyse("diameter", part.hull, part.center_of_mass, part.size, tol)
    r = analyse("radius", part.hull, part.center_of_mass, part.size, tol)
    squeeze = from_runs(list(d.runs), np.pi, tol.angle_rad)
    push = from_runs(list(r.runs), 2 * np.pi, tol.angle_rad)
    push_grasp = squeeze.compose_after(push, tol.angle_rad) if squeeze.steps else push
    robust = None if physics is None else robust_analysis(part, d, r, physics, tol)
    return Analysis(part, d, r, squeeze, push, push_grasp, tol, robust)


def analyse_document(doc: Mapping[str, Any], model: Model = ROBUST, tol: Tolerances = DEFAULT_TOLERANCES) -> Analysis:
    """Parse, validate and analyse a part document under ``model``: the one entry point
    of every interface (CLI, service, batch, replay, figures)."""
    part = load_part(doc, tol, snap=not model.exact)
    return analyse_part(part, tol, None if model.exact else model.physics)


def robust_analysis(part: Part, d: SupportPairFunction, r: SupportPairFunction, physics: Physics,
                    tol: Tolerances, terms: PartTerms | None = None, action: str | None = None,
                    memo: SetMemo | None = None, band: DeadBand | None = None) -> RobustAnalysis:
    """Dead band and set-valued squeeze, push and push-grasp functions over the physics
    ranges; with ``placement="any"`` the squeeze starts with a partial push by either jaw
    (push-grasps are unaffected: the pushing jaw meets the part first by design).
    ``terms``: the part's dead-band terms when already known (another analysis of it).
    ``action``: build only what a plan of that action reads (a limit search's probes;
    nothing once the squeeze, which every plan reads, is refused); the rest is None with
    the reason "not built". ``memo``: set-valued functions already built for this part's
    d and r (:attr:`RobustAnalysis.sets` of another analysis of it), kept by the result.
    ``band``: the dead band of ``physics`` on ``terms`` when already made (a limit probe's key)."""
    terms = part_terms(part, tol) if terms is None else terms
    memo = SetMemo() if memo is None else memo
    band = dead_band(part, physics, tol, terms) if band is None else band
    reasons: dict[str, str] = {}
    funcs: dict[str, SetTransfer | None] = {}
    keys = set_keys(d.kind, r.kind, band, physics, tol.angle_rad)
    needs_push = action != "squeeze" or physics.placement == "any"
    for name, f in (("squeeze", d), ("push", r)):
        if name == "push" and (not needs_push or (action is not None and funcs["squeeze"] is None)):
            funcs[name], reasons[name] = None, NOT_BUILT
            continue
        made = _set_transfer(memo, f, keys[name])
        if isinstance(made, SetTransfer):
            funcs[name] = made
        else:
            funcs[name], reasons[name] = None, made
    _compose(memo, funcs, reasons, keys, physics.placement == "any", action, tol.angle_rad)
    return RobustAnalysis(physics, band, funcs["squeeze"], funcs["push"], funcs["push_grasp"], reasons, terms, memo)


def set_keys(d_kind: str, r_kind: str, band: DeadBand, physics: Physics, tol_rad: float) -> dict[str, tuple[object, ...]]:
    """The arguments the squeeze's and the push's set-valued functions are built with
    (:func:`~algrasp.planning.setvalued.set_transfer`'s after f, behind f's kind): their
    :class:`SetMemo` keys. O(1)."""
    # Creep: the weakest holding case holds nothing, so motion is possible wherever f slopes.
    stall = (0.0 if physics.creep else band.stall_lo, band.stall_hi)
    # d has two contacts: its slope and value errors are twice one jaw's.
    # Shallow basins: the real part's f is within the profile tolerance per contact (and
    # r within ε_c more), so a basin less than twice that deep may not be one.
    return {"squeeze": (d_kind, stall, band.sigma_d, 2.0 * band.value_tol, tol_rad, band.jaw_friction,
                        2.0 * band.value_err, 4.0 * band.profile_floor),
            "push": (r_kind, stall, band.sigma_r, band.value_tol_r, tol_rad, 0.0, band.value_err + band.com_tolerance,
                     2.0 * (band.profile_floor + band.com_tolerance))}


def uses_sets(band: DeadBand, physics: Physics) -> bool:
    """Whether plans under this dead band are made on the set-valued functions: False
    only with no stall, slope error, jaw friction or centre-of-mass disk and centred
    placement, where they are the exact functions (conventions §7)."""
    return (band.kappa_d > 0.0 or band.kappa_r > 0.0 or band.jaw_friction > 0.0 or band.com_tolerance > 0.0
            or physics.placement == "any")


def plan_reads(keys: dict[str, tuple[object, ...]], band: DeadBand, physics: Physics, action: str) -> tuple[object, ...]:
    """Everything a plan of ``action`` reads of a robust analysis (given its :func:`set_keys`),
    so that two analyses of one part alike in it plan alike (the exact functions, the
    part's hull and the tolerances being the part's): the functions the plan is built on,
    whether it is made on them at all (:func:`uses_sets`), and the value error that tilts
    its final orientations. The physics itself and the rest of the band only word a
    refusal or fill the plan document. O(1)."""
    off_centre = action == "squeeze" and physics.placement == "any"
    built = (keys["squeeze"], keys["push"]) if off_centre or action != "squeeze" else (keys["squeeze"],)
    return action, off_centre, uses_sets(band, physics), band.value_err, built


def _compose(memo: SetMemo, funcs: dict[str, SetTransfer | None], reasons: dict[str, str],
             keys: dict[str, tuple[object, ...]], off_centre: bool, action: str | None, tol_rad: float) -> None:
    """The push-grasp Γ∘p and, with off-centre placement, the squeeze after a partial push,
    from the built squeeze and push (in place; each composition once per ``memo``)."""
    sq, pu = funcs["squeeze"], funcs["push"]
    if action == "squeeze":
        funcs["push_grasp"], reasons["push_grasp"] = None, NOT_BUILT
    elif sq is None or pu is None:
        funcs["push_grasp"] = None
        # The push's reason first (as a full analysis always gave); the squeeze's when the
        # push was not built because the squeeze was refused (a probe).
        reasons["push_grasp"] = reasons["push"] if pu is None and reasons["push"] != NOT_BUILT else reasons["squeeze"]
    else:
        funcs["push_grasp"] = _composed(memo, ("push_grasp", keys["squeeze"], keys["push"]),
                                        lambda: sq.compose_after(pu, tol_rad))
    if off_centre and sq is not None and action != "push_grasp":
        funcs["squeeze"] = None if pu is None else _composed(memo, ("off_centre", keys["squeeze"], keys["push"]),
                                                             lambda: off_centre_squeeze(sq, pu, tol_rad))
        if pu is None:
            reasons["squeeze"] = f"off-centre placement starts a squeeze with a push, and {reasons['push']}"


class SetMemo(dict[tuple[object, ...], "SetTransfer | str"]):
    """Set-valued functions of one part's d and r by their arguments (or the refusal's
    message), and their compositions by their parts' keys: what the probes of limit
    searches on one analysis share (probes that move only a range one function does not
    read, the jaw friction for the push; both actions' searches, which probe the same
    ranges first). A cache: it pickles and copies empty.

    ``plans``: whether a plan exists, by what the plan reads (:func:`plan_reads`, behind the
    planner and margin): the limit probes and plans of one analysis whose physics differ
    only where no plan looks (a range end no dead-band term reads, a profile tolerance
    given as the floor it defaults to) are answered once."""

    def __init__(self) -> None:
        super().__init__()
        self.plans: dict[tuple[object, ...], bool] = {}

    def __reduce__(self) -> tuple[type[SetMemo], tuple[()]]:
        return SetMemo, ()


def _set_transfer(memo: SetMemo, f: SupportPairFunction, key: tuple[Any, ...]) -> SetTransfer | str:
    """:func:`~algrasp.planning.setvalued.set_transfer` of ``f`` with the arguments after
    ``key``'s first (looked up in, and added to, ``memo``), or the message of its refusal."""
    if key in memo:
        return memo[key]
    try:
        made: SetTransfer | str = set_transfer(f, *key[1:])
    except NotOrientableError as e:
        made = str(e)
    memo[key] = made
    return made


def _composed(memo: SetMemo, key: tuple[object, ...], make: Callable[[], SetTransfer]) -> SetTransfer:
    """``make()`` (a composition of memoised functions; deterministic), once per ``key``."""
    got = memo.get(key)
    if not isinstance(got, SetTransfer):
        got = memo[key] = make()
    return got
