"""Verification of plans (conventions §5, §7): a plan's claimed final orientations are
checked by running its actions from every start, exactly where the transfer function
allows and densely on its ramps. Pure: no I/O; angles in radians."""

from __future__ import annotations

from collections.abc import Sequence
from types import ModuleType
from typing import Protocol

import numpy as np

from algrasp.compiled import LOOKUPS
from algrasp.geometry.angles import signed_diff
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.tolerances import PROBE_RAD
from algrasp.planning.setvalued import SetTransfer
from algrasp.planning.transfer import TransferFunction


class PlanStep(Protocol):
    """What verification reads of a plan step (:class:`algrasp.planning.plans.PlanStep`)."""

    @property
    def gripper_angle(self) -> float: ...


class Plan(Protocol):
    """What verification reads of a plan (:class:`algrasp.planning.plans.Plan`; a protocol,
    so that this module does not import the one that calls it)."""

    @property
    def transfer(self) -> TransferFunction: ...
    @property
    def steps(self) -> Sequence[PlanStep]: ...
    @property
    def final_orientations(self) -> Sequence[float]: ...
    @property
    def final_uncertainty(self) -> float: ...
    @property
    def bounds(self) -> SetTransfer | None: ...

FINAL_CLUSTER_RAD = 1e-6
"""Final orientations closer than this are one orientation in verification."""
VERIFY_SAMPLES = 3600


def through(F: TransferFunction, steps: Sequence[PlanStep], phi: FloatArray) -> FloatArray:
    """World orientations after ``steps`` of the exact model from ``phi`` (radians)."""
    for s in steps:
        phi = F.apply(phi - s.gripper_angle) + s.gripper_angle
    return phi


def verify(plan: Plan, samples: int = VERIFY_SAMPLES) -> bool:
    """True when the plan leaves exactly 360/T final orientations, the reported ones.

    The first action sends each step interval to the step's value and leaves each ramp
    where it is, so its outcomes from the whole circle are every step value over a turn —
    exactly, with no sampling — and, on its ramps only, a dense set of ``samples``
    orientations plus every breakpoint (and its neighbours) of every action. Each outcome
    is run through the remaining actions. O(nN log n) for n pieces and N actions when F
    has no ramp, O((s + nN) N log n) with s samples when it has.
    """
    F = plan.transfer
    a1 = plan.steps[0].gripper_angle
    turns = [k * F.period for k in range(round(2 * np.pi / F.period))]
    steps = F.steps
    phi = np.array([(p.value + t) + a1 for p in steps for t in turns])  # type: ignore[operator]
    if len(steps) < len(F.pieces):  # ramps: orientations on them are not collapsed
        grid = np.linspace(0.0, 2 * np.pi, samples, endpoint=False)
        starts = F.starts_array
        shifts = np.array([s.gripper_angle for s in plan.steps])[:, None, None]
        probes = np.array([-PROBE_RAD, 0.0, PROBE_RAD])[None, :, None]
        lifted = np.concatenate([starts, starts + F.period])[None, None, :]
        x = np.concatenate([grid, (lifted + shifts + probes).ravel()])
        phi = np.concatenate([phi, x[F.on_ramp(x - a1)]])
    final = np.sort(np.mod(through(F, plan.steps[1:], phi), 2 * np.pi))
    clusters = _clusters(final)
    want = np.array(plan.final_orientations)
    if len(clusters) != len(want):
        return False
    off = np.abs(signed_diff(clusters[:, None], want))
    return bool((off.min(axis=1) <= FINAL_CLUSTER_RAD).all())


def _clusters(sorted_angles: FloatArray) -> FloatArray:
    """Means (radians, [0, 2π)) of runs of sorted angles closer than FINAL_CLUSTER_RAD,
    the last run joined to the first across 2π. O(m), one pass in plain floats."""
    xs = sorted_angles.tolist()
    if not xs:
        return np.zeros(0)
    sums, counts = [xs[0]], [1]
    for prev, x in zip(xs, xs[1:]):
        if x - prev > FINAL_CLUSTER_RAD:
            sums.append(x)
            counts.append(1)
        else:
            sums[-1] += x
            counts[-1] += 1
    means = [s / c for s, c in zip(sums, counts)]
    if len(means) > 1 and xs[0] + 2 * np.pi - xs[-1] <= FINAL_CLUSTER_RAD:
        last, n_last = means.pop() - 2 * np.pi, counts.pop()
        means[0] = (means[0] * counts[0] + last * n_last) / (counts[0] + n_last)
    out: FloatArray = np.mod(np.array(means), 2 * np.pi)
    return out


def verify_set(plan: Plan, circle: tuple[float, float], samples: int = VERIFY_SAMPLES) -> bool:
    """Set semantics. The first action leaves the part in one of its outcomes, all inside
    the circular hull ``circle`` (checked); from there, a dense set of orientations of
    that arc, every piece boundary of the bounds inside it (and its neighbours) and the
    arc as a whole are run through the remaining actions: the hull of where each can
    end must lie within ``final_uncertainty`` of a claimed final orientation.

    The second action runs over every sample in one vectorised pass; the samples are
    mostly sorted and the bounds monotone, so its images repeat in runs, and each later
    action runs over the runs the one before left, once each (they shrink as the plan
    collapses orientations). As soon as at most ``FEW_ARCS`` runs are left, the rest of
    the actions and the check run in plain floats instead, each distinct arc once (the
    same values: :meth:`~algrasp.planning.transfer.TransferFunction.apply_floats`). O(m)
    for m samples, then O(runs) per action."""
    assert plan.bounds is not None
    S = plan.bounds
    if not _outcomes_within(S, circle):
        return False
    if LOOKUPS is not None:  # typed loops, the same floats and verdict (algrasp.compiled)
        return _verify_arcs(plan, circle, samples, LOOKUPS)
    lo, hi = _runs(*run_steps(S, plan.steps[1:2], *_samples(plan, circle, samples)))
    k = 2
    while len(lo) > FEW_ARCS and k < len(plan.steps):
        lo, hi = _runs(*run_steps(S, plan.steps[k:k + 1], lo, hi))
        k += 1
    want, bound = plan.final_orientations, plan.final_uncertainty + FINAL_CLUSTER_RAD
    if len(lo) <= FEW_ARCS:
        arcs = _run_floats(S, plan.steps[k:], dict.fromkeys(zip(lo.tolist(), hi.tolist())))
        return all(min(abs(signed_diff(0.5 * (x + y), w)) for w in want) + 0.5 * (y - x) <= bound for x, y in arcs)
    off = np.abs(signed_diff((0.5 * (lo + hi))[:, None], np.array(want))).min(axis=1)
    return bool((off + 0.5 * (hi - lo) <= bound).all())


def _verify_arcs(plan: Plan, circle: tuple[float, float], samples: int, lookups: ModuleType) -> bool:
    """:func:`verify_set` after the outcome check in one compiled pass (the same arcs,
    the same floats: repeats dropped alike, each arc's verdict alike)."""
    S = plan.bounds
    assert S is not None
    starts = np.concatenate([S.lower.starts_array, S.upper.starts_array])
    return bool(lookups.verify_arcs(S.lower, S.upper, starts, *circle, S.symmetry, [s.gripper_angle for s in plan.steps],
                                    samples, PROBE_RAD, list(plan.final_orientations),
                                    plan.final_uncertainty + FINAL_CLUSTER_RAD))


def _runs(lo: FloatArray, hi: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The arcs [lo, hi] with runs of equal ones kept once (a repeat is run alike)."""
    new = np.empty(len(lo), dtype=bool)
    new[:1] = True
    np.not_equal(lo[1:], lo[:-1], out=new[1:])
    new[1:] |= hi[1:] != hi[:-1]
    return lo[new], hi[new]


FEW_ARCS = 32
"""Up to this many distinct arcs the actions after the second run in plain floats (about
1 µs an arc, against ~25 µs for a vectorised pass of any size)."""


def _outcomes_within(S: SetTransfer, circle: tuple[float, float]) -> bool:
    """Whether every outcome of ``S`` lies in the arc ``circle`` (to FINAL_CLUSTER_RAD);
    plain floats (a few outcomes)."""
    c0, c1 = circle
    T, top = S.symmetry, c1 - c0 + FINAL_CLUSTER_RAD
    # An outcome starting a rounding error before c0 must not wrap to the far end.
    return not any((a - c0 + FINAL_CLUSTER_RAD) % T - FINAL_CLUSTER_RAD + (b - a) > top for a, b in S.outcomes)


def _samples(plan: Plan, circle: tuple[float, float], samples: int) -> tuple[FloatArray, FloatArray]:
    """The arcs [lo, hi] (world, radians) :func:`verify_set` starts the second action
    from: ``samples`` points of ``circle``, every piece start of the bounds inside it and
    its neighbours (each a point), and the whole arc last."""
    assert plan.bounds is not None
    S = plan.bounds
    c0, c1 = circle
    a1 = plan.steps[0].gripper_angle
    starts = np.concatenate([S.lower.starts_array, S.upper.starts_array])
    cuts = c0 + np.mod(starts - c0, S.symmetry)
    inner = cuts[cuts <= c1]
    pts = np.concatenate([np.linspace(c0, c1, samples), inner - PROBE_RAD, inner, inner + PROBE_RAD])
    pts = pts.clip(c0, c1) + a1
    return np.concatenate([pts, [c0 + a1]]), np.concatenate([pts, [c1 + a1]])


def _run_floats(S: SetTransfer, steps: Sequence[PlanStep],
                arcs: dict[tuple[float, float], None]) -> dict[tuple[float, float], None]:
    """:func:`run_steps` over a few distinct arcs (the keys) in plain floats, value for
    value, repeats dropped after each action. O(d log n) per action for d arcs."""
    for s in steps:
        a = s.gripper_angle
        ends = zip(S.lower.apply_floats([x - a for x, _ in arcs]), S.upper.apply_floats([y - a for _, y in arcs]))
        arcs = dict.fromkeys((x + a, y + a) for x, y in ends)
    return arcs


def run_steps(bounds: SetTransfer, steps: Sequence[PlanStep], lo: FloatArray,
              hi: FloatArray) -> tuple[FloatArray, FloatArray]:
    """World arcs [lo, hi] (radians) after ``steps`` of the set-valued push ``bounds`` (set
    semantics; :meth:`Plan.run_set`). O(m · len(steps) · log n)."""
    for s in steps:
        lo, hi = bounds.image(lo - s.gripper_angle, hi - s.gripper_angle)
        lo, hi = lo + s.gripper_angle, hi + s.gripper_angle
    return lo, hi
