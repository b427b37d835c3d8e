"""The plan document (conventions §6) as a typed value with one codec.

:class:`PlanDocument` holds a plan in radians; :meth:`PlanDocument.to_json` writes the
JSON document (degrees) and :meth:`PlanDocument.from_json` reads one back — from a
record, a ``plan --json`` file or an HTTP response — checking every field it needs and
keeping the optional execution fields (push distances, jaw trajectories, cycle time) as
written. This is the one place where a plan's angles cross between radians and degrees.

>>> doc = {"action": "squeeze", "symmetry_period_deg": 180.0, "intervals_deg": [[0.0, 70.0]],
...        "steps": [{"gripper_angle_deg": 45.0, "margin_deg": None}], "final_orientations_deg": [90.0],
...        "final_uncertainty_deg": 0.0, "model": "exact", "verified": True, "timings_s": {}}
>>> plan = PlanDocument.from_json(doc)
>>> round(plan.steps[0].gripper_angle, 6), plan.to_json() == doc
(0.785398, True)
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from algrasp.errors import PartDocumentError
from algrasp.geometry.angles import TWO_PI, to_deg, to_rad
from algrasp.geometry.functions import wrap
from algrasp.geometry.tolerances import ROUNDING


@dataclass(frozen=True)
class StepDocument:
    """One action: the gripper angle (radians, [0, 2π)), its margin (radians; None for
    the first action), the execution fields as written (``push_distance``, …) and
    ``image``: the world arcs the part can be in after it from any start
    (:func:`~algrasp.planning.motion.motion`; None when not written)."""

    gripper_angle: float
    margin: float | None
    execution: Mapping[str, Any] = field(default_factory=dict)
    image: tuple[tuple[float, float], ...] | None = None


@dataclass(frozen=True)
class PlanDocument:
    """A plan document in radians. ``execution``: the optimised execution's plan-level
    fields (``cycle_time_s``, ``units``, ``gripper_profile``, …), empty without."""

    action: str
    symmetry_period: float
    intervals: tuple[tuple[float, float], ...]
    steps: tuple[StepDocument, ...]
    final_orientations: tuple[float, ...]
    final_uncertainty: float
    model: str
    verified: bool
    dead_band: Mapping[str, Any] | None = None
    timings_s: Mapping[str, float] = field(default_factory=dict)
    execution: Mapping[str, Any] = field(default_factory=dict)
    limits: Mapping[str, Any] | None = None
    images: Mapping[str, Any] | None = None
    """The action's own images (degrees, as written): ``period_deg`` and ``pieces``
    ``[start, end, lower, upper]`` (None: θ itself), so a page follows a start through the
    plan without a planner of its own."""

    @staticmethod
    def from_plan(plan: Any) -> PlanDocument:
        """The document of a :class:`~algrasp.planning.plans.Plan` (angles wrapped as
        conventions §6 writes them)."""
        from algrasp.planning.motion import motion

        P = plan.transfer.period
        m = motion(plan)
        intervals = tuple((wrap(a, P, ROUNDING), wrap(a, P, ROUNDING) + b - a) for a, b in plan.intervals)
        steps = tuple(StepDocument(wrap(s.gripper_angle, TWO_PI, ROUNDING), None if s.margin is None else float(s.margin),
                                   image=arcs) for s, arcs in zip(plan.steps, m.after))

        def opt(x: float | None) -> float | None:
            return None if x is None else to_deg(x)

        images = {"period_deg": to_deg(m.period), "pieces": [[to_deg(a), to_deg(b), opt(lo), opt(hi)] for a, b, lo, hi in m.images]}
        return PlanDocument(plan.action, float(plan.symmetry_period), intervals, steps,
                            tuple(float(f) for f in plan.final_orientations), float(plan.final_uncertainty),
                            "exact" if plan.bounds is None else "robust", bool(plan.verified), plan.robust,
                            dict(plan.timings_s), limits=plan.limits, images=images)

    def to_json(self) -> dict[str, Any]:
        """The JSON document (degrees), key order as conventions §6."""
        out: dict[str, Any] = {
            "action": self.action,
            "symmetry_period_deg": to_deg(self.symmetry_period),
            "intervals_deg": [[to_deg(a), to_deg(b)] for a, b in self.intervals],
            "steps": [{"gripper_angle_deg": to_deg(s.gripper_angle),
                       "margin_deg": None if s.margin is None else to_deg(s.margin), **s.execution,
                       **({} if s.image is None else {"image_deg": [[to_deg(a), to_deg(b)] for a, b in s.image]})}
                      for s in self.steps],
            "final_orientations_deg": [to_deg(f) for f in self.final_orientations],
            "final_uncertainty_deg": to_deg(self.final_uncertainty),
            "model": self.model,
            **({} if self.dead_band is None else {"dead_band": dict(self.dead_band)}),
            **({} if self.limits is None else {"limits": dict(self.limits)}),
            **({} if self.images is None else {"images": dict(self.images)}),
            "verified": self.verified,
            "timings_s": dict(self.timings_s),
        }
        return {**out, **self.execution}

    @staticmethod
    def from_json(doc: Any, field_name: str = "plan") -> PlanDocument:
        """Read a plan document; PartDocumentError names the first missing or malformed field."""
        if not isinstance(doc, Mapping):
            raise PartDocumentError(field_name, "a plan document must be an object")
        steps_raw = _get(doc, "steps", list, field_name)
        steps = tuple(_step(s, f"{field_name}.steps[{i}]") for i, s in enumerate(steps_raw))
        known = {"action", "symmetry_period_deg", "intervals_deg", "steps", "final_orientations_deg",
                 "final_uncertainty_deg", "model", "dead_band", "limits", "images", "verified", "timings_s"}
        return PlanDocument(
            action=_get(doc, "action", str, field_name),
            symmetry_period=to_rad(_number(doc.get("symmetry_period_deg"), f"{field_name}.symmetry_period_deg")),
            intervals=tuple((to_rad(_number(p[0], f"{field_name}.intervals_deg[{i}]")),
                             to_rad(_number(p[1], f"{field_name}.intervals_deg[{i}]")))
                            for i, p in enumerate(_pairs(doc.get("intervals_deg"), f"{field_name}.intervals_deg"))),
            steps=steps,
            final_orientations=tuple(to_rad(_number(f, f"{field_name}.final_orientations_deg"))
                                     for f in _get(doc, "final_orientations_deg", list, field_name)),
            final_uncertainty=to_rad(_number(doc.get("final_uncertainty_deg", 0.0), f"{field_name}.final_uncertainty_deg")),
            model=str(doc.get("model", "exact")),
            verified=bool(doc.get("verified", False)),
            dead_band=doc.get("dead_band"),
            timings_s=dict(doc.get("timings_s") or {}),
            execution={k: v for k, v in doc.items() if k not in known},
            limits=doc["limits"] if isinstance(doc.get("limits"), Mapping) else None,
            images=doc["images"] if isinstance(doc.get("images"), Mapping) else None,
        )


def _step(raw: Any, where: str) -> StepDocument:
    if not isinstance(raw, Mapping):
        raise PartDocumentError(where, "a step must be an object")
    margin = raw.get("margin_deg")
    image = raw.get("image_deg")
    arcs = None if image is None else tuple((to_rad(_number(a, f"{where}.image_deg")), to_rad(_number(b, f"{where}.image_deg")))
                                            for a, b in _pairs(image, f"{where}.image_deg"))
    return StepDocument(to_rad(_number(raw.get("gripper_angle_deg"), f"{where}.gripper_angle_deg")),
                        None if margin is None else to_rad(_number(margin, f"{where}.margin_deg")),
                        {k: v for k, v in raw.items() if k not in ("gripper_angle_deg", "margin_deg", "image_deg")}, arcs)


def _get(doc: Mapping[str, Any], key: str, kind: type, where: str) -> Any:
    value = doc.get(key)
    if not isinstance(value, kind):
        raise PartDocumentError(f"{where}.{key}", f"expected {kind.__name__}, got {type(value).__name__}")
    return value


def _number(value: Any, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise PartDocumentError(where, f"expected a finite number, got {value!r}")
    return float(value)


def _pairs(value: Any, where: str) -> list[Any]:
    if not isinstance(value, list) or not all(isinstance(p, list) and len(p) == 2 for p in value):
        raise PartDocumentError(where, "expected a list of [start, end] pairs")
    return value


@dataclass(frozen=True)
class FunctionDocument:
    """d(θ) or r(θ) in a document: extrema ``(θ rad, value, "min"|"max", equilibrium)``
    and the intervals (radians) where the function is constant."""

    extrema: tuple[tuple[float, float, str, Any], ...]
    constant_intervals: tuple[tuple[float, float], ...]

    def to_json(self) -> dict[str, Any]:
        return {"extrema": [{"theta_deg": to_deg(t), "value": v, "kind": k, "equilibrium": e} for t, v, k, e in self.extrema],
                "constant_intervals_deg": [[to_deg(a), to_deg(b)] for a, b in self.constant_intervals]}

    @staticmethod
    def from_json(doc: Any, where: str) -> FunctionDocument:
        if not isinstance(doc, Mapping):
            raise PartDocumentError(where, "expected an object")
        extrema = tuple((to_rad(_number(e.get("theta_deg"), f"{where}.extrema[{i}].theta_deg")),
                         _number(e.get("value"), f"{where}.extrema[{i}].value"), str(e.get("kind")), e.get("equilibrium"))
                        for i, e in enumerate(_get(doc, "extrema", list, where)))
        spans = tuple((to_rad(_number(a, where)), to_rad(_number(b, where)))
                      for a, b in _pairs(doc.get("constant_intervals_deg"), f"{where}.constant_intervals_deg"))
        return FunctionDocument(extrema, spans)


@dataclass(frozen=True)
class TransferDocument:
    """A transfer function in a document (radians): its steps ``(start, end, fixed
    point)`` and ramps ``(start, end)``, periods, and why it cannot orient when it cannot."""

    period: float
    symmetry_period: float
    steps: tuple[tuple[float, float, float], ...]
    ramps: tuple[tuple[float, float], ...]
    orientable: bool
    reason: str | None = None

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "period_deg": to_deg(self.period), "symmetry_period_deg": to_deg(self.symmetry_period),
            "steps": [{"start_deg": to_deg(a), "end_deg": to_deg(b), "fixed_point_deg": to_deg(f)} for a, b, f in self.steps],
            "ramps": [{"start_deg": to_deg(a), "end_deg": to_deg(b)} for a, b in self.ramps],
            "orientable": self.orientable}
        return out if self.reason is None else {**out, "reason": self.reason}

    @staticmethod
    def from_json(doc: Any, where: str) -> TransferDocument:
        if not isinstance(doc, Mapping):
            raise PartDocumentError(where, "expected an object")

        def deg(x: Any, at: str) -> float:
            return to_rad(_number(x, f"{where}.{at}"))

        steps = tuple((deg(s.get("start_deg"), f"steps[{i}].start_deg"), deg(s.get("end_deg"), f"steps[{i}].end_deg"),
                       deg(s.get("fixed_point_deg"), f"steps[{i}].fixed_point_deg"))
                      for i, s in enumerate(_get(doc, "steps", list, where)))
        ramps = tuple((deg(r.get("start_deg"), f"ramps[{i}].start_deg"), deg(r.get("end_deg"), f"ramps[{i}].end_deg"))
                      for i, r in enumerate(_get(doc, "ramps", list, where)))
        return TransferDocument(deg(doc.get("period_deg"), "period_deg"), deg(doc.get("symmetry_period_deg"),
                                "symmetry_period_deg"), steps, ramps, bool(doc.get("orientable", True)), doc.get("reason"))


@dataclass(frozen=True)
class AnalysisDocument:
    """The analysis document (``algrasp analyze --json``, ``POST /v1/analyses``, records'
    ``/analysis``) in radians. ``part`` is the part's summary (area, hull perimeter, centre
    of mass in part units); ``robust`` the set-valued summary of conventions §7 as written."""

    part: Mapping[str, Any]
    diameter: FunctionDocument
    radius: FunctionDocument
    squeeze: TransferDocument
    push: TransferDocument
    push_grasp: TransferDocument
    model: str
    robust: Mapping[str, Any] | None = None

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {"part": dict(self.part), "diameter": self.diameter.to_json(),
                               "radius": self.radius.to_json()}
        for name in ("squeeze", "push", "push_grasp"):
            out[name] = getattr(self, name).to_json()
        out["model"] = self.model
        return out if self.robust is None else {**out, "robust": dict(self.robust)}

    @staticmethod
    def from_json(doc: Any, field_name: str = "analysis") -> AnalysisDocument:
        """Read an analysis document; PartDocumentError names the first malformed field."""
        if not isinstance(doc, Mapping):
            raise PartDocumentError(field_name, "an analysis document must be an object")
        fn = {k: FunctionDocument.from_json(doc.get(k), f"{field_name}.{k}") for k in ("diameter", "radius")}
        tf = {k: TransferDocument.from_json(doc.get(k), f"{field_name}.{k}") for k in ("squeeze", "push", "push_grasp")}
        return AnalysisDocument(_get(doc, "part", Mapping, field_name), fn["diameter"], fn["radius"], tf["squeeze"],
                                tf["push"], tf["push_grasp"], str(doc.get("model", "exact")), doc.get("robust"))


@dataclass(frozen=True)
class SetTransferDocument:
    """A set-valued transfer function F_κ in a document (conventions §7, radians): its
    dead zones over one natural period and its images over one symmetry period, each
    piece ``(start, end, lower, upper)`` mapping θ into [lower, upper] (None: θ itself)."""

    orientable: bool
    symmetry_period: float
    dead_zones: tuple[tuple[float, float], ...]
    images: tuple[tuple[float, float, float | None, float | None], ...]

    @staticmethod
    def from_set(S: Any) -> SetTransferDocument:
        """The document of a :class:`~algrasp.planning.setvalued.SetTransfer`."""
        cuts = sorted({p.start for p in S.lower.pieces} | {p.start for p in S.upper.pieces})
        # one symmetry period: the pieces may span the natural period (twice it, for the squeeze)
        cuts = [c for c in cuts if c < cuts[0] + S.symmetry - ROUNDING]
        edges = [*cuts, cuts[0] + S.symmetry]
        images = []
        for a, b in zip(edges[:-1], edges[1:]):
            lo, k_lo = S.lower.piece_at(0.5 * (a + b))
            hi, k_hi = S.upper.piece_at(0.5 * (a + b))
            images.append((a, b, None if lo.value is None else lo.value + k_lo, None if hi.value is None else hi.value + k_hi))
        return SetTransferDocument(bool(S.orientable), S.symmetry, tuple(S.rest_zones), tuple(images))

    def to_json(self) -> dict[str, Any]:
        def opt(x: float | None) -> float | None:
            return None if x is None else to_deg(x)

        return {"orientable": self.orientable, "symmetry_period_deg": to_deg(self.symmetry_period),
                "dead_zones_deg": [[to_deg(a), to_deg(b)] for a, b in self.dead_zones],
                "images": [{"start_deg": to_deg(a), "end_deg": to_deg(b), "lower_deg": opt(lo), "upper_deg": opt(hi)}
                           for a, b, lo, hi in self.images]}
