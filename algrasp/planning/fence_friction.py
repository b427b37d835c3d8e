"""The fence's friction in the fence push (conventions §9). Pure: no I/O; angles in radians.

A part pushed along a fence slides along the wall (the fence is admissible only then), so
the wall's reaction lies on the edge of its friction cone: N(n − s μ t) in the jaw frame
(t the wall's direction (cos α, sin α), n = (−sin α, cos α) into the part), with s = +1 on
the right rail (the part slides along +t, downstream) and s = −1 on the left (along −t).
With r(θ) the part's radius function relative to the jaw (θ = φ − α), the contact point
relative to the centre of mass is c = (−r′(θ), −r(θ)) in (t, n), so the moment of the
reaction is N(c × n − s μ c × t) = −N (r′ + s μ r): the part turns towards smaller θ
where r′ + s μ r > 0 and towards larger θ where it is < 0 (μ = 0: down r, §3). By
Mason's voting theorem this sense holds whether the contact slides or sticks: the fence's
push direction relative to the belt, 90° − β from n on the side of −s t, lies outside
the friction cone (β < 90° − atan μ) on the side of the sliding edge, so it votes with it.

So the equilibria are the zeros of (ln r)′ + s μ: the balance on a sharp vertex moves by
exactly s atan μ (r = ρ cos(θ − θ_v)), on a rounded corner (radius R about a centre at ρ
from the centre of mass) by more, s (atan μ + asin(μ R / (ρ √(1 + μ²)))); an edge flush
on the fence (a kink of r) stays stable where it was while μ is below the kink's slopes;
a smooth minimum (the part resting on a curved piece) moves. As s μ grows every zero
where (ln r)′ falls moves up and every zero where it rises moves down, monotonically
(comparison of 1-d flows), so over μ ∈ [μ_lo, μ_hi] the push at μ lies between the
pushes at the two ends. :func:`fence_tilt` writes the push at μ as the frictionless
one after a monotone map of its input and with its rests moved:
``p_μ(θ) = p(m_μ(θ)) + o`` where m_μ maps each basin of p_μ linearly onto the basin of p
whose rest survives in it (a rest that friction makes vanish — the part rolls off an edge
whose kink is below μ — gives its basin to its neighbour) and o is how far that rest
moved (0 on a kink). A :class:`Tilt` per rail holds the envelope over μ sampled in the
range, ``m_lo ≤ m_μ ≤ m_hi`` and ``o ∈ [o_lo, o_hi]``, so that
``p(m_lo(θ)) + o_lo ≤ p_μ(θ) ≤ p(m_hi(θ)) + o_hi``
(:meth:`~algrasp.planning.fence_model.Push.image`, which takes the robust bounds for p).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Literal

import numpy as np

from algrasp.geometry.angles import TWO_PI, to_rad
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.functions import SupportPairFunction

TILT_GRID_RAD = to_rad(0.01)
"""Spacing of the radius-function samples the equilibria and maps are found on."""
TILT_PAD_RAD = 2.0 * TILT_GRID_RAD
"""The maps and every nonzero rest shift are widened by this either way (zeros lie between samples)."""
REST_STILL_RAD = 1.5 * TILT_GRID_RAD
"""A rest found within this of where it was has not moved (a kink's zero may fall one sample over)."""
FRICTION_SAMPLES = 5
"""μ values sampled over the fence friction range (its ends included) for the envelope."""


@dataclass(frozen=True, eq=False)
class Tilt:
    """The friction's effect on one rail (radians): the input maps m_lo ≤ m_μ ≤ m_hi,
    sampled at ``grid`` over one turn (lifted: m(θ + 2π) = m(θ) + 2π, non-decreasing),
    and each frictionless rest's (``rests``, one turn) shift o ∈ [o_lo, o_hi] (0 for a
    rest on a kink). Without ``grid``: no tilt."""

    grid: FloatArray | None = None
    m_lo: FloatArray | None = None
    m_hi: FloatArray | None = None
    rests: FloatArray = field(default_factory=lambda: np.zeros(1))
    o_lo: FloatArray = field(default_factory=lambda: np.zeros(1))
    o_hi: FloatArray = field(default_factory=lambda: np.zeros(1))
    shifts: tuple[float, float] = (0.0, 0.0)
    """The least and largest shift of a surviving basin boundary (radians, for reports)."""

    def maps(self, theta: FloatArray) -> tuple[FloatArray, FloatArray]:
        """(m_lo(θ), m_hi(θ)) for an array of lifted θ (radians); O(m)."""
        return self.map_lo(theta), self.map_hi(theta)

    def map_lo(self, theta: FloatArray) -> FloatArray:
        """m_lo(θ) for an array of lifted θ (radians), linear between samples; O(m)."""
        return self._map(theta, 0)

    def map_hi(self, theta: FloatArray) -> FloatArray:
        """m_hi(θ) for an array of lifted θ (radians), linear between samples; O(m)."""
        return self._map(theta, 1)

    @cached_property
    def _extended(self) -> tuple[FloatArray, FloatArray]:
        """m_lo and m_hi with one more sample a turn on (at 2π)."""
        assert self.m_lo is not None and self.m_hi is not None
        return np.append(self.m_lo, self.m_lo[0] + TWO_PI), np.append(self.m_hi, self.m_hi[0] + TWO_PI)

    def _map(self, theta: FloatArray, which: int) -> FloatArray:
        theta = np.asarray(theta, dtype=float)
        if self.grid is None:
            return theta
        k = np.floor(theta / TWO_PI) * TWO_PI
        f = (theta - k) / TILT_GRID_RAD
        i = np.minimum(np.floor(f).astype(int), len(self.grid) - 1)
        w = f - i
        m = self._extended[which]
        return m[i] * (1.0 - w) + m[i + 1] * w + k

    def rest_shift(self, a: FloatArray, b: FloatArray) -> tuple[FloatArray, FloatArray]:
        """How far the ends of image arcs [a, b] (lifted, radians) may move (≤ 0, ≥ 0): a
        rest v within ``REST_MATCH_RAD`` (M) of the arc moves its image by o_v, so the
        lower end by min(0, o_lo,v + max(0, v − a − M)) over them (its own end's rest by
        all of o_lo,v, an inner rest only as far as its image may pass a), the upper end
        likewise. O(m k) for k rests."""
        a, b = np.asarray(a, dtype=float)[..., None], np.asarray(b, dtype=float)[..., None]
        v = (self.rests[None, :] + TWO_PI * np.arange(-2, 4)[:, None]).ravel()
        lo, hi = np.tile(self.o_lo, 6), np.tile(self.o_hi, 6)
        inside = (v >= a - REST_MATCH_RAD) & (v <= b + REST_MATCH_RAD)
        down = np.where(inside, lo + np.maximum(0.0, v - a - REST_MATCH_RAD), 0.0).min(axis=-1)
        up = np.where(inside, hi - np.maximum(0.0, b - v - REST_MATCH_RAD), 0.0).max(axis=-1)
        return np.minimum(down, 0.0), np.maximum(up, 0.0)

    @property
    def moves_rests(self) -> bool:
        """Whether some rest moves with the friction (a smooth minimum of r)."""
        return bool(np.any(self.o_lo != 0.0) or np.any(self.o_hi != 0.0))


REST_MATCH_RAD = to_rad(5.0)
"""An image end this close to a frictionless rest is that rest (the robust bands move a
rest's image by less: the largest claimable uncertainty, ±5°)."""


NO_TILT = (Tilt(), Tilt())


def equilibria(g: FloatArray, theta: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Zeros of the sampled rate function g (radians⁻¹, at ``theta`` + half a step, cyclic):
    (unstable, stable) θ, sorted, where g falls through 0 and where it rises through 0. O(n)."""
    pos = g > 0.0
    nxt = np.roll(pos, -1)
    at = np.roll(theta, -1)
    return np.sort(at[pos & ~nxt]), np.sort(at[~pos & nxt])


def _lifted_near(values: FloatArray, x: FloatArray, side: Literal["left", "right"]) -> tuple[FloatArray, np.ndarray]:
    """The first of ``values`` (sorted, one turn) at or above x (``side`` "left") or at or
    below it ("right"), lifted by whole turns next to x, and its index (radians)."""
    n = len(values)
    k = np.floor(x / TWO_PI) * TWO_PI
    slack = -0.5 * TILT_GRID_RAD if side == "left" else 0.5 * TILT_GRID_RAD  # samples equal up to rounding are equal
    j = np.searchsorted(values, x - k + slack, side=side) - (0 if side == "left" else 1)
    return values[j % n] + TWO_PI * (j // n) + k, j % n


def input_map(rate: FloatArray, theta: FloatArray, mu_s: float) -> tuple[FloatArray, FloatArray, FloatArray]:
    """m_μ on ``theta`` (lifted values) for the signed friction s μ (``mu_s`` ≠ 0), the
    rests' shifts (2, k: the frictionless rest's index, the shift) and the surviving boundaries' shifts (radians): each basin of
    (ln r)′ + s μ is mapped linearly onto the frictionless basin whose rest is the first
    at or beyond its own rest in the sense rests move (−s); a run of new basins sharing
    one (friction made a new rest) shares it, split at that rest. O(n log n)."""
    u0, s0 = equilibria(rate, theta)
    u, s = equilibria(rate + mu_s, theta)
    if len(u) == 0:  # no rest at all: the part may spin on; a whole turn either way
        return theta - TWO_PI, theta + TWO_PI, np.zeros((2, 0))
    n = len(u)
    lo = u  # basin c runs from u[c] to u[c] + gap, its rest the first stable zero past u[c]
    hi = np.append(u[1:], u[0] + TWO_PI)
    rest, _ = _lifted_near(s, lo, "left")
    orig, j = _lifted_near(s0, rest, "left" if mu_s > 0 else "right")
    olo, _ = _lifted_near(u0, orig, "right")
    ohi, _ = _lifted_near(u0, orig, "left")
    same_before, same_after = j == np.roll(j, 1), j == np.roll(j, -1)
    if n == 1:
        same_before = same_after = np.zeros(1, dtype=bool)
    tlo = np.where(same_before, orig, olo)
    thi = np.where(same_after, orig, ohi)
    c = np.searchsorted(u, theta, side="right") - 1  # -1: the last basin, a turn back
    x = np.where(c < 0, theta + TWO_PI, theta)
    c = c % n
    m = tlo[c] + (x - lo[c]) * (thi[c] - tlo[c]) / (hi[c] - lo[c]) - (x - theta)
    survived = ~same_before
    return m, np.stack([j, rest - orig]), np.concatenate([(lo - olo)[survived], (hi - ohi)[~same_after]])


def rail_tilt(rate: FloatArray, theta: FloatArray, sense: int, friction: tuple[float, float]) -> Tilt:
    """The :class:`Tilt` of one rail (``sense`` s = +1 right, −1 left) over μ ∈ ``friction``
    (``FRICTION_SAMPLES`` values) from the sampled (ln r)′ (``rate``, at ``theta`` + half
    a step). O(k n log n)."""
    _, rests = equilibria(rate, theta)
    o_lo, o_hi = np.zeros(len(rests)), np.zeros(len(rests))
    maps, bounds = ([theta], [np.zeros(1)]) if friction[0] == 0.0 else ([], [])
    for mu in np.linspace(friction[0], friction[1], FRICTION_SAMPLES):
        if mu > 0.0:
            m, o, b = input_map(rate, theta, sense * float(mu))
            maps.append(m)
            bounds.append(b)
            j = o[0].astype(int)
            shift = np.where(np.abs(o[1]) <= REST_STILL_RAD, 0.0, o[1])
            np.minimum.at(o_lo, j, shift)
            np.maximum.at(o_hi, j, shift)
    b_all = np.concatenate(bounds) if bounds else np.zeros(0)
    if b_all.size == 0:  # no surviving boundary (one rest keeps every basin): 0
        b_all = np.zeros(1)
    return Tilt(theta, np.min(maps, axis=0) - TILT_PAD_RAD, np.max(maps, axis=0) + TILT_PAD_RAD, rests,
                np.where(o_lo < 0.0, o_lo - TILT_PAD_RAD, 0.0), np.where(o_hi > 0.0, o_hi + TILT_PAD_RAD, 0.0),
                (float(b_all.min()), float(b_all.max())))


def fence_tilt(radius: SupportPairFunction, friction: tuple[float, float]) -> tuple[Tilt, Tilt]:
    """(right, left) :class:`Tilt` of a part with radius function r (about its centre of
    mass) over the fence friction range μ ∈ [μ_lo, μ_hi]: the zeros of (ln r)′ + s μ
    against those of (ln r)′, r sampled every ``TILT_GRID_RAD``. O(k n log n) for n samples
    and k = ``FRICTION_SAMPLES``.

    >>> from algrasp.geometry.angles import to_deg
    >>> from algrasp.planning.analysis import analyse_document
    >>> square = analyse_document({"name": "s", "boundary": [[0, 0], [2, 0], [2, 2], [0, 2]]})
    >>> right, left = fence_tilt(square.radius, (0.1, 0.3))
    >>> [round(float(to_deg(x)), 2) for x in right.shifts + left.shifts]  # ± atan μ at the vertices
    [5.71, 16.7, -16.7, -5.71]
    >>> right.moves_rests  # rests on edges (kinks) do not move
    False
    """
    if friction[1] == 0.0:
        return NO_TILT
    theta = np.arange(0.0, TWO_PI, TILT_GRID_RAD)
    lr = np.log(radius.values(theta))
    rate = (np.roll(lr, -1) - lr) / TILT_GRID_RAD
    rate[-1] = (lr[0] - lr[-1]) / (TWO_PI - theta[-1])
    return rail_tilt(rate, theta, 1, friction), rail_tilt(rate, theta, -1, friction)
