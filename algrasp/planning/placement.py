"""Off-centre placement (docs/conventions.md §8): a squeeze that starts with a push.

With the part anywhere between the open jaws, the first jaw to touch pushes it by an
unknown distance before the other arrives; either jaw may be first. From θ the part may
reach anything between θ and where the push by jaw L (p) or by jaw H (p(θ + π) − π, the
push with the gripper turned half a turn) would leave it, so the squeeze's image from θ is
Γ of that hull:

    lower(θ) = Γ_lo(min(θ, p_lo(θ), p_lo(θ + π) − π)),  upper likewise with max.

Min and max of step/ramp functions are step/ramp functions again (:func:`pointwise`), so
the result is a :class:`~algrasp.planning.setvalued.SetTransfer` the planner uses as is.
Pure: no I/O. O(n log n) in the pieces.
"""

from __future__ import annotations

import functools
import math

from algrasp.compiled import KERNELS
from algrasp.planning.setvalued import SetTransfer
from algrasp.planning.transfer import TransferFunction, TransferPiece, canonical


def identity(period: float) -> TransferFunction:
    """F(θ) = θ: one ramp over the period."""
    return TransferFunction(period, (TransferPiece(0.0, period, None),))


def shifted(F: TransferFunction, d: float) -> TransferFunction:
    """θ ↦ F(θ + d) − d (radians)."""
    if KERNELS is not None:  # typed loops, the same pieces (algrasp.compiled)
        return TransferFunction(F.period, tuple(canonical(KERNELS.shifted(F, -d), F.period, 0.0)))
    return TransferFunction(F.period, tuple(canonical([p.shifted(-d) for p in F.pieces], F.period, 0.0)))


def _cuts(fs: list[TransferFunction], a: float, P: float) -> list[float]:
    """Every piece start of ``fs`` lifted into [a, a + P), sorted, with a and a + P."""
    out = {a, a + P}
    for F in fs:
        for p in F.pieces:
            out.add(a + (p.start - a) % P)
    return sorted(c for c in out if a <= c <= a + P)


def pointwise(fs: list[TransferFunction], take_max: bool, tol_rad: float) -> TransferFunction:
    """The pointwise min (or max) of transfer functions of one period (radians).

    On each cell between the functions' breakpoints every function is a constant or the
    identity; the identity and the extreme constant c cross at θ = c, which splits the cell.
    Plain floats: a few cells and functions, where numpy's per-call cost would dominate.
    """
    P = fs[0].period
    if KERNELS is not None:  # typed loops, the same pieces (algrasp.compiled)
        return TransferFunction(P, tuple(canonical(KERNELS.pointwise(fs, take_max), P, tol_rad)))
    cuts = _cuts(fs, fs[0].pieces[0].start, P)
    cells = [(a, b) for a, b in zip(cuts[:-1], cuts[1:]) if b - a > 0.0]
    mids = [0.5 * (a + b) for a, b in cells]
    # Every function's step at every cell's middle (NaN on a ramp). The identity is a ramp
    # everywhere: it adds the ramp and no constant to every cell, with no lookup.
    steps = [F.steps_floats(mids) for F in fs if len(F.pieces) > 1 or F.pieces[0].value is not None]
    ramp_always = len(steps) < len(fs)
    pieces: list[TransferPiece] = []
    for (a, b), vs in zip(cells, zip(*steps) if steps else [()] * len(cells)):
        consts = [v for v in vs if v == v]
        pieces.extend(_extreme(a, b, ramp_always or len(consts) < len(vs), consts, take_max))
    return TransferFunction(P, tuple(canonical(pieces, P, tol_rad)))


def _extreme(a: float, b: float, ramp: bool, consts: list[float], take_max: bool) -> list[TransferPiece]:
    """min/max of the identity (if ``ramp``) and ``consts`` on [a, b)."""
    if not consts:
        return [TransferPiece(a, b, None)]
    c = max(consts) if take_max else min(consts)
    if not ramp or (c >= b if take_max else c <= a):
        return [TransferPiece(a, b, c)]
    if (c <= a) if take_max else (c >= b):
        return [TransferPiece(a, b, None)]
    first, second = (TransferPiece(a, c, c), TransferPiece(c, b, None)) if take_max else \
        (TransferPiece(a, c, None), TransferPiece(c, b, c))
    return [first, second]


def _order(T: float) -> int:
    """k with T = 2π/k."""
    return max(1, int(round(2.0 * math.pi / T)))


def off_centre_squeeze(squeeze: SetTransfer, push: SetTransfer, tol_rad: float) -> SetTransfer:
    """Γ after a partial push by either jaw (see module docs), of period 2π; its symmetry
    is what both the squeeze and the hull of partial pushes repeat with."""
    P = push.period
    lo, hi = _push_hull(push, tol_rad)
    k_hull = math.lcm(_order(push.symmetry), 2)
    symmetry = 2.0 * math.pi / math.gcd(k_hull, _order(squeeze.symmetry))
    zones = tuple((a + k * squeeze.period, b + k * squeeze.period) for k in range(int(round(P / squeeze.period)))
                  for a, b in squeeze.rest_zones)
    # Γ ∘ hull (SetTransfer.compose_after) written out: the hull's one outcome is the
    # whole circle, whose image [Γ_lo(0), Γ_hi(2π)] is over a period long, and both orders
    # are even (Γ has period π), so the symmetry is at most π: every outcome of Γ, in
    # each of its copies over the symmetry period, meets it and is kept, in that order.
    copies = [k * squeeze.symmetry for k in range(max(1, int(round(symmetry / squeeze.symmetry))))]
    outcomes = tuple((a + c, b + c) for c in copies for a, b in squeeze.outcomes)
    return SetTransfer(squeeze.lower.compose_after(lo, tol_rad), squeeze.upper.compose_after(hi, tol_rad), P, symmetry,
                       zones, outcomes)


@functools.lru_cache(maxsize=8)
def _push_hull(push: SetTransfer, tol_rad: float) -> tuple[TransferFunction, TransferFunction]:
    """The bounds of the hull of θ and the partial pushes by either jaw (module docs),
    once per push function (identity): a limit search's probes that share the push (its
    jaw-friction probes) share it."""
    P = push.period
    if KERNELS is not None:  # one call, the same pieces (algrasp.compiled)
        lo, hi = KERNELS.push_hull(push.lower, push.upper, P, tol_rad)
        return TransferFunction(P, lo), TransferFunction(P, hi)
    return (pointwise([identity(P), push.lower, shifted(push.lower, math.pi)], False, tol_rad),
            pointwise([identity(P), push.upper, shifted(push.upper, math.pi)], True, tol_rad))
