"""Set-valued transfer functions F_κ (conventions §7): where a real part may come to rest.

For f = d (squeeze) or r (push) and the dead band (s, σ), each orientation θ is
classified by the drawn slope g = f′(θ) (part units per radian):

* rest is possible where |g| ≤ μ_j·f + s_hi + σ (μ_j the largest jaw friction of a
  squeeze, 0 for a push), certain where |g| ≤ s_lo − σ (conventions §8: the weakest
  holding cell of the ranges);
* downhill motion (direction −sign g) is possible where |g| > s_lo − σ; uphill too where
  moreover |g| ≤ σ (the real slope may have either sign).

A part starting at θ rests somewhere in ``[lower(θ), upper(θ)]``: ``upper`` is the end of
the run of right-movable zones containing θ (it stops at the first zone it cannot cross),
θ itself where it may stay, or the start of the forced-left run it slides down; ``lower``
mirrors it. Both are monotone step/ramp functions — :class:`~algrasp.planning.transfer.TransferFunction`
— so an interval [a, b) maps into [lower(a), upper(b⁻)]. With s = σ = 0 both equal the
exact function of §3.

The classification is made on cells between nodes: every exact threshold crossing
(:mod:`algrasp.planning.edges`: closed form on lines, arcs and vertices; a grid of
``GRID_RAD`` on curve pieces only), each guarded by a sliver of ±``EDGE_RAD`` that takes
both sides' permissions; every Gauss-map breakpoint (where f′ jumps) and every extremum of
the exact analysis. The uniform grid is added only inside cells where one value could hide
a staircase (an energy barrier that may cut a run short, a shallow basin). Each cell takes
the union of the permissions sampled just inside its two ends, in every copy θ + kT of the
symmetry period T judged to tolerance (a tessellated gear has the period of its teeth):
the union is conservative, so images only grow. O(c·K) for c cells and K copies, all in
vectorised passes.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import cast

import numpy as np

from algrasp.compiled import KERNELS
from algrasp.geometry.curves import FloatArray
from algrasp.geometry.functions import SupportPairFunction
from algrasp.geometry.lazy import cached_property
from algrasp.geometry.tolerances import ROUNDING, Tolerances
from algrasp.planning.barriers import barrier_sets, basin_cells, basins
from algrasp.planning.edges import CURVE_GRID_RAD, crossings, point_contacts, slopes
from algrasp.planning.setcells import Cells, bounds, rest_zones, turning_error
from algrasp.planning.symmetry import symmetry_period
from algrasp.planning.transfer import TransferFunction, arcs_holding

GRID_RAD = 2e-3
"""Largest cell of the classification grid (0.115°): dead-zone edges are placed to this
(kinks and extrema are nodes of their own, so stable orientations are exact)."""
EDGE_RAD = 2e-4
"""Half-width of the sliver around each exact dead-zone edge that takes both sides'
permissions (0.011°, a tenth of the grid the edges were once rounded to): a plan never
rests on a knife edge that a part's real slope, a jaw's angle or an integrator's step
could cross, and every margin it states is real."""
SLOPE_NOISE = ROUNDING
"""Relative size (to f) below which a drawn slope is rounding, not a slope."""
_INSIDE = 1e-6
"""Relative offset of the end samples inside a cell (kinks sit on cell nodes)."""


@dataclass(frozen=True, eq=False)
class SetTransfer:
    """F_κ as its lower and upper bounds (both of period ``symmetry``).

    ``rest_zones`` are the dead zones {|f′| ≤ κ} over one natural period (radians,
    [start, end)); ``period`` is the natural period (π or 2π).
    """

    lower: TransferFunction
    upper: TransferFunction
    period: float
    symmetry: float
    rest_zones: tuple[tuple[float, float], ...]
    outcomes: tuple[tuple[float, float], ...]
    """Closed intervals (radians, lifted) holding every orientation the part can rest in
    after the action, from any start: the rest zones and the stops of the steps."""

    @property
    def orientable(self) -> bool:
        return bool(self.lower.steps or self.upper.steps)

    def image(self, lo: FloatArray, hi: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Hull of the images of the closed intervals [lo, hi] (radians, lifted)."""
        return self.lower.apply(lo), self.upper.apply(hi)

    def circle_images(self) -> list[tuple[float, float]]:
        """The arcs, on the circle of period T, that hold every orientation the part can
        end in from any start (``outcomes``), each leaving out one gap between them:
        [start, end] lifted, end − start ≤ T, shortest first (the first is their circular
        hull; :func:`~algrasp.planning.transfer.holding_arcs`). The image of the whole
        circle: hulls of single points would fill the gaps that uncertain zones bridge, but
        a part only ever rests at an outcome. Made once per function: a plan's search and
        its gripper angles read it, and so does every limit probe that shares the function."""
        return list(self._circle_images)

    def circle_width(self) -> float:
        """The width (radians) of the whole circle's image: its circular hull's."""
        a, b = self._circle_images[0]
        return b - a

    @cached_property
    def _circle_images(self) -> tuple[tuple[float, float], ...]:
        return tuple(arcs_holding([a for a, _ in self.outcomes], [b for _, b in self.outcomes], self.symmetry))

    def compose_after(self, inner: SetTransfer, tol_rad: float) -> SetTransfer:
        """self ∘ inner (inner acts first): bounds compose since both are monotone. The
        outcomes are self's outcomes (where it can leave a part at all) that meet the
        image of one of inner's outcomes. (One compiled call when built: algrasp.compiled.)"""
        if KERNELS is not None:
            copies = max(1, int(round(inner.symmetry / self.symmetry)))
            lo_pieces, hi_pieces, kept = KERNELS.compose_sets(self.lower, self.upper, inner.lower, inner.upper,
                                                              inner.outcomes, self.outcomes, self.symmetry,
                                                              inner.symmetry, copies, tol_rad)
            return SetTransfer(TransferFunction(inner.lower.period, lo_pieces), TransferFunction(inner.upper.period, hi_pieces),
                               inner.period, inner.symmetry, inner.rest_zones, kept)
        lower = self.lower.compose_after(inner.lower, tol_rad)
        upper = self.upper.compose_after(inner.upper, tol_rad)
        lo = self.lower.apply_list([a for a, _ in inner.outcomes]).tolist()  # self.image of inner's outcomes
        hi = self.upper.apply_list([b for _, b in inner.outcomes]).tolist()
        return SetTransfer(lower, upper, inner.period, inner.symmetry, inner.rest_zones,
                           self._meeting(lo, hi, inner.symmetry))

    def _meeting(self, lo: list[float], hi: list[float], T: float) -> tuple[tuple[float, float], ...]:
        """self's outcomes, in each copy over the period T (they repeat with self's
        symmetry), that meet one of the arcs [lo_i, hi_i] on the circle of circumference T
        (radians, lifted). Plain floats, a few outcomes and arcs: O(n·m)."""
        widths = [y - x for x, y in zip(lo, hi)]
        kept = []
        for c in [k * self.symmetry for k in range(max(1, int(round(T / self.symmetry))))]:
            for a, b in self.outcomes:
                a, b = float(a + c), float(b + c)
                for x, w in zip(lo, widths):
                    start = (a - x) % T  # the outcome's start relative to the arc's
                    if start <= w or start + (b - a) >= T:
                        kept.append((a, b))
                        break
        return tuple(kept)

def _nodes(f: SupportPairFunction, T: float, edges: FloatArray, grid: FloatArray) -> tuple[FloatArray, np.ndarray]:
    """Cell nodes in [0, T): ``edges`` (threshold crossings), ``grid``, breakpoints (θ of
    every Gauss-map breakpoint) and extrema; and whether each is sampled on both sides:
    where f′ jumps (breakpoints, extrema) and where a permission changes (the edges: the
    sample just past one belongs to the next cell's class). Grid nodes serve both. Nodes
    within ``ROUNDING`` are one (the first of them; a node a hair below T is node 0)."""
    # Each edge becomes a sliver [e − EDGE_RAD, e + EDGE_RAD) holding both classes.
    raw = np.concatenate([_ZERO, grid, edges - EDGE_RAD, edges + EDGE_RAD, f.kink_thetas])
    np.mod(raw, T, out=raw)
    order = raw.argsort(kind="stable")
    raw, flags = raw[order], order >= 1 + len(grid)  # node 0 and the grid: no kinks
    new = np.empty(len(raw), dtype=bool)
    new[0] = True
    np.greater(raw[1:] - raw[:-1], ROUNDING, out=new[1:])
    starts = new.nonzero()[0]
    kink = np.logical_or.reduceat(flags, starts)
    if T - raw[-1] <= ROUNDING and len(starts) > 1:  # the last group is node 0's
        kink[0] |= kink[-1]
        starts, kink = starts[:-1], kink[:-1]
    return raw[starts], kink


_ZERO = np.zeros(1)


def _samples(f: SupportPairFunction, x: FloatArray, kink: np.ndarray, T: float) -> tuple[FloatArray, FloatArray]:
    """f′ and f just inside both ends of every cell in every copy: (n, 2, K) each.

    f′ is continuous at grid nodes, so one evaluation there serves the cells on both sides;
    at kinks the left and right limits are evaluated apart. The end of the last cell is
    node 0 of the next copy."""
    K, n = int(round(f.period / T)), len(x)
    ends = np.empty(n)
    ends[:-1], ends[-1] = x[1:], T
    widths = ends - x
    at_kink = kink.nonzero()[0]
    theta = np.concatenate([x + _INSIDE * widths, x[at_kink] - _INSIDE * widths[at_kink - 1]])
    if K > 1:  # (never −0.0, so one copy needs no + 0·T)
        theta = theta[:, None] + np.arange(K) * T
    g, v = (a.reshape(-1, K) for a in slopes(f, theta.ravel()))
    # The end of cell i: node i + 1's sample, or its left limit where node i + 1 is a kink.
    src = np.arange(n)
    src[at_kink] = np.arange(n, n + len(at_kink))
    pick = np.empty((n, 2), dtype=np.intp)
    pick[:, 0], pick[:-1, 1], pick[-1, 1] = np.arange(n), src[1:], src[0]
    G, V = g[pick], v[pick]
    if K > 1:  # the last cell ends at node 0 of the next copy
        G[-1, 1], V[-1, 1] = np.concatenate([G[-1, 1, 1:], G[-1, 1, :1]]), np.concatenate([V[-1, 1, 1:], V[-1, 1, :1]])
    return G, V


def _permissions(g: FloatArray, v: FloatArray, stall: tuple[float, float], sigma: float,
                 jaw_friction: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(right, left, rest) possible, each OR-ed over the last two axes (samples, copies).

    Motion is possible only where the weakest holding cell lets go (least stall, no jaw
    friction): |g| > s_lo − σ; rest wherever the strongest cell may hold:
    |g| ≤ μ_j·f + s_hi + σ (``v`` holds f, so the jaw term is the friction couple of two
    contacts f apart; 0 for a push)."""
    a, size = np.abs(g), np.abs(v)
    # A slope within rounding of zero (a constant-width stretch, concentric arcs) is no
    # slope: with creep (s_lo = 0) its noise's sign would otherwise decide the motion.
    movable = a > np.maximum(stall[0] - sigma, SLOPE_NOISE * size)
    either = a <= sigma
    right = movable & ((g < 0.0) | either)
    left = movable & ((g > 0.0) | either)
    rest = a <= jaw_friction * size + stall[1] + sigma
    n = len(g)
    out = (right.reshape(n, -1).any(axis=1), left.reshape(n, -1).any(axis=1), rest.reshape(n, -1).any(axis=1))
    return cast("tuple[np.ndarray, np.ndarray, np.ndarray]", out)  # .any(axis=1) of a 2-d array: arrays


@dataclass(frozen=True)
class _Band:
    """The dead band of one set-valued function: stall range (s_lo, s_hi), slope
    tolerance σ, largest jaw friction μ_j, value error ε and shallow-basin depth."""

    stall: tuple[float, float]
    sigma: float
    jaw_friction: float
    err: float
    shallow: float

    def thresholds(self) -> tuple[tuple[float, ...], tuple[float, float]]:
        """The slopes where a permission (or the monotony of f ± s_lo·θ, which the
        barriers need) changes, and the rest bound's (μ_j, s_hi + σ)."""
        s_lo, sigma = self.stall[0], self.sigma
        return (s_lo - sigma, sigma, s_lo, s_lo + sigma), (self.jaw_friction, self.stall[1] + sigma)


@dataclass(frozen=True)
class _Pass:
    """One classification of the cells between given nodes; ``near``: the barriers from
    each cell's least f (the first pass, when the value error is positive)."""

    cells: Cells
    g: FloatArray
    rims: list[float]
    near: tuple[FloatArray, FloatArray] | None


def _classify(f: SupportPairFunction, T: float, edges: FloatArray, grid: FloatArray, band: _Band,
              first: bool = False) -> _Pass:
    """Nodes, samples, permissions and barriers of the cells between ``edges``, ``grid``
    and the breakpoints and extrema of f. O(c·K·log c)."""
    if KERNELS is not None:  # the same arrays from typed loops (algrasp.compiled)
        x, right, left, rest, b_right, b_left, g, rims, near_found = KERNELS.classify(f, T, edges, grid, band, first)
        return _Pass(Cells(x, T, right, left, rest, b_right, b_left), g, rims, near_found)
    x, kink = _nodes(f, T, edges, grid)
    g, v = _samples(f, x, kink, T)
    right, left, rest = _permissions(g, v, band.stall, band.sigma, band.jaw_friction)
    # A drawn minimum shallower than the manufacturing tolerance may be no minimum of the
    # real part (nor of the simulation's compliant contact): its basin may go either way.
    starts = v[:, 0, :].T
    flat = starts.ravel()
    found_basins = basins(flat, band.shallow)
    if found_basins:
        basin = np.asarray(basin_cells(flat, found_basins).reshape(v.shape[2], -1).any(axis=0))
        right, left = right | basin, left | basin
    # The energy bound holds for the weakest stall: every cell lowers f at least that fast.
    # A first pass that found shallow basins is classified again (with their rims' nodes):
    # only the barriers from each cell's least f (``near``, for _to_refine) are read of it.
    near = first and band.err > 0.0
    final = not (near and found_basins)
    levels = ((v.max(axis=1).T,) if final else ()) + ((v.min(axis=1).T,) if near else ())
    found = barrier_sets(x, T, starts, levels, band.stall[0], band.err)
    cells = Cells(x, T, right, left, rest, *(found[0] if final else (_NONE, _NONE)))
    return _Pass(cells, g, [rim for _, rim in found_basins], found[-1] if near else None)


_NONE = np.zeros(0)
"""The barriers of a pass that is classified again: never read."""


def _to_refine(p: _Pass, band: _Band) -> np.ndarray:
    """Cells whose one value may hide a staircase: where an energy barrier could cut a
    run short for some start inside the cell (tested with the cell's least f, the nearest
    barrier any start in it can have) and, when one can, where barriers land (movable
    cells slower than s_lo + σ, where f ± s_lo·θ can climb)."""
    c = p.cells
    if p.near is None:
        return np.zeros(len(c.x), dtype=bool)
    near_r, near_l = p.near
    run_right, run_left = c.run_limits
    bind = (c.right & (near_r < run_right)) | (c.left & (near_l > run_left))
    if not bind.any():
        return bind
    slow = (np.abs(p.g).min(axis=(1, 2)) < band.stall[0] + band.sigma) & (c.right | c.left)
    return np.asarray(slow | bind)


def _cells_of(f: SupportPairFunction, T: float, band: _Band, tol_rad: float) -> Cells:
    """The cells of F_κ: nodes at every exact threshold crossing (closed form on
    point-like contacts, bracketed on curves); then, if the first pass finds shallow
    basins, nodes where f crosses their rims (their exact extent), and the uniform grid
    of ``GRID_RAD`` only inside the cells :func:`_to_refine` marks; classified again."""
    slopes_at, jaw = band.thresholds()
    tol = _tolerances(tol_rad)
    edges, curves = crossings(f, slopes_at, jaw, tol, CURVE_GRID_RAD)
    first = _classify(f, T, edges, curves, band, first=True)
    rims = first.rims
    refine = _to_refine(first, band)
    if not rims and not refine.any():
        return first.cells
    if rims:
        edges = np.concatenate([edges, crossings(f, (), None, tol, CURVE_GRID_RAD, levels=tuple(rims))[0]])
    if refine.any():
        grid = np.linspace(0.0, T, max(8, int(np.ceil(T / GRID_RAD))), endpoint=False)
        curves = np.concatenate([curves, grid[refine[np.searchsorted(first.cells.x, grid, side="right") - 1]]])
    return _classify(f, T, edges, curves, band).cells


def set_transfer(f: SupportPairFunction, stall: tuple[float, float], sigma: float, value_tol: float, tol_rad: float,
                 jaw_friction: float = 0.0, value_err: float | None = None, shallow: float = 0.0) -> SetTransfer:
    """F_κ of d or r (see module docs) over a stall range ``(s_lo, s_hi)`` and, for a
    squeeze, the largest jaw friction. ``value_tol`` judges the drawing's symmetry;
    ``value_err`` (default the same) bounds how far the real f is from the drawn one
    (the barriers: the manufacturing profile tolerance counts here); basins of f less
    than ``shallow`` deep may be left either way (:func:`~algrasp.planning.barriers.shallow_basins`). Raises
    NotOrientableError when the part may turn without end. O((c + b)·K·log) for c cells
    (threshold crossings, refined grid), b breakpoints, K symmetric copies."""
    P = f.period
    T = symmetry_period(f, value_tol)
    band = _Band(stall, sigma, jaw_friction, value_tol if value_err is None else value_err, shallow)
    lower, upper, zones, zones_P = _bounds(f, T, band, tol_rad)
    stops = [(p.value, p.value) for F in (lower, upper) for p in F.pieces if p.value is not None]
    return SetTransfer(lower, upper, P, T, zones_P, (*zones, *stops))


Zones = tuple[tuple[float, float], ...]


def _bounds(f: SupportPairFunction, T: float, band: _Band, tol_rad: float) -> tuple[
        TransferFunction, TransferFunction, Zones, Zones]:
    """The lower and upper bounds of F_κ and its rest zones over T and over f's period.
    Where every crossing is closed-form (no curve contact), the compiled kernels make
    them in one call from the contact cells (the same floats: algrasp.compiled)."""
    if KERNELS is not None and (contacts := point_contacts(f, _tolerances(tol_rad))) is not None:
        slopes_at, jaw = band.thresholds()
        found = KERNELS.set_bounds(f, T, band, tol_rad, contacts, tuple(t for t in slopes_at if t > 0.0), jaw)
        if found is None:
            raise turning_error()
        return TransferFunction(T, found[0]), TransferFunction(T, found[1]), found[2], found[3]
    cells = _cells_of(f, T, band, tol_rad)
    lower, upper = bounds(cells, tol_rad)
    zones = rest_zones(cells.x, T, cells.rest, T)
    return lower, upper, zones, zones if f.period == T else rest_zones(cells.x, T, cells.rest, f.period)


@functools.lru_cache(maxsize=8)
def _tolerances(angle_rad: float) -> Tolerances:
    """The tolerances of the crossings: the defaults with ``angle_rad`` (made once each)."""
    return Tolerances(angle_rad=angle_rad)
