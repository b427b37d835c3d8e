"""The compiled kernels (algrasp.planning._kernels) against the numpy path they replace:
every array and every piece bit for bit, on random polygons, symmetric polygons (several
copies of the symmetry period), circular arcs and Bezier curves, over random dead bands.
The numpy path is the reference (run here with the hooks switched off)."""

from __future__ import annotations

from contextlib import suppress
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from algrasp.compiled import KERNELS
from algrasp.errors import NotOrientableError
from algrasp.geometry.tolerances import DEFAULT_TOLERANCES as TOL
from algrasp.planning import placement, planner, setcells
from algrasp.planning.edges import CURVE_GRID_RAD, crossings
from algrasp.planning.setvalued import GRID_RAD, _Band, _classify, set_transfer
from algrasp.planning.transfer import TransferFunction, TransferPiece, canonical, from_runs
from algrasp.testing.kernels import bits, both, families, reference_path, set_args, support_function

pytestmark = pytest.mark.skipif(KERNELS is None, reason="compiled kernels not built (or ALGRASP_PURE set)")


DOCS = families("polygon", "regular", "reuleaux", "flats", "pie", "blob")




BAND = st.tuples(st.sampled_from([0.0, 0.01, 0.05, 0.2]), st.floats(0.0, 0.1), st.sampled_from([0.0, 1e-3, 0.02, 2.0]),
                 st.sampled_from([1e-9, 1e-6, 1e-3]), st.sampled_from([0.0, 1e-4, 1e-2]), st.floats(0.0, 0.4),
                 st.sampled_from([0.0, 1e-4, 1e-2]))


@settings(max_examples=120, deadline=None)
@given(shape=st.sampled_from(sorted(DOCS)), seed=st.integers(0, 10_000), n=st.integers(3, 11),
       kind=st.sampled_from(["diameter", "radius"]), band=BAND)
def test_set_transfer_is_bit_identical(shape: str, seed: int, n: int, kind: str, band: tuple[float, ...]) -> None:
    f = support_function(DOCS[shape](seed, n), kind)
    args = set_args(f, band)

    def made() -> Any:
        st_ = set_transfer(f, **args)
        return (st_.lower.pieces, st_.upper.pieces, st_.symmetry, st_.rest_zones, st_.outcomes)

    compiled, numpy_ = both(made)
    assert bits(compiled) == bits(numpy_)


@settings(max_examples=80, deadline=None)
@given(shape=st.sampled_from(sorted(DOCS)), seed=st.integers(0, 10_000), n=st.integers(3, 11),
       kind=st.sampled_from(["diameter", "radius"]), band=BAND, first=st.booleans(), grid=st.booleans())
def test_classify_is_bit_identical(shape: str, seed: int, n: int, kind: str, band: tuple[float, ...], first: bool,
                                   grid: bool) -> None:
    f = support_function(DOCS[shape](seed, n), kind)
    a = set_args(f, band)
    b = _Band(a["stall"], a["sigma"], a["jaw_friction"], a["value_err"], a["shallow"])
    slopes_at, jaw = b.thresholds()
    edges, curves = crossings(f, slopes_at, jaw, TOL, CURVE_GRID_RAD)
    T = f.period / (1 + seed % 3 if kind == "diameter" and shape == "regular" and n % 2 == 0 else 1)
    if grid:  # the refinement grid of a second pass
        curves = np.concatenate([curves, np.linspace(0.0, T, int(np.ceil(T / GRID_RAD)) // 7, endpoint=False)])

    def made() -> Any:
        p = _classify(f, T, edges, curves, b, first)
        c = p.cells
        return (c.x, c.right, c.left, c.rest, c.barrier_right, c.barrier_left, p.g, p.rims, p.near, c.runs)

    compiled, numpy_ = both(made)
    assert bits(compiled) == bits(numpy_)


@settings(max_examples=300, deadline=None)
@given(cuts=st.lists(st.floats(-0.5, 7.0), min_size=1, max_size=12), kinds=st.lists(st.integers(0, 3), min_size=12,
       max_size=12), period=st.sampled_from([np.pi, 2.0 * np.pi, np.pi / 3]), tol=st.sampled_from([1e-9, 1e-3, 0.1]))
def test_canonical_is_bit_identical(cuts: list[float], kinds: list[int], period: float, tol: float) -> None:
    """Sorted cells over one period, ramps and steps (some equal to tol, some across the wrap)."""
    starts = sorted(cuts)
    ends = [*starts[1:], starts[0] + period]
    values = [None, 0.5, 0.5 + tol / 2, starts[0] + period + 0.25]
    pieces = [TransferPiece(a, b, values[k] if k != 3 else values[3] - (period if i == 0 else 0.0))
              for i, (a, b, k) in enumerate(zip(starts, ends, kinds))]
    compiled, numpy_ = both(lambda: canonical(list(pieces), period, tol))
    assert bits(compiled) == bits(numpy_)
    assert all(type(p) is TransferPiece for p in compiled)


@settings(max_examples=80, deadline=None)
@given(shape=st.sampled_from(sorted(DOCS)), seed=st.integers(0, 10_000), n=st.integers(3, 11), band=BAND)
def test_compositions_are_bit_identical(shape: str, seed: int, n: int, band: tuple[float, ...]) -> None:
    """Set-valued bounds (steps, ramps where a part may stay) and exact functions (ramps on
    constant runs), composed both ways round."""
    d, r = (support_function(DOCS[shape](seed, n), kind) for kind in ("diameter", "radius"))

    def made() -> Any:
        out: list[Any] = []
        exact = [from_runs(list(f.runs), f.period, TOL.angle_rad) for f in (d, r)]
        out += [exact[0].compose_after(exact[1], TOL.angle_rad).pieces, exact[1].compose_after(exact[0], TOL.angle_rad).pieces]
        try:
            sets = [set_transfer(f, **set_args(f, band)) for f in (d, r)]
        except NotOrientableError:
            return out  # the exact compositions alone
        for a, b in ((sets[0], sets[1]), (sets[1], sets[0]), (sets[0], sets[0])):
            for fa, fb in ((a.lower, b.lower), (a.upper, b.upper), (a.lower, exact[1])):
                out.append(fa.compose_after(fb, TOL.angle_rad).pieces)
            out.append(a.compose_after(b, TOL.angle_rad).outcomes)
        return out

    compiled, numpy_ = both(made)
    assert bits(compiled) == bits(numpy_)


@settings(max_examples=120, deadline=None)
@given(shape=st.sampled_from(sorted(DOCS)), seed=st.integers(0, 10_000), n=st.integers(3, 11),
       kind=st.sampled_from(["diameter", "radius"]), slopes=st.lists(st.floats(1e-6, 2.0), min_size=1, max_size=4),
       jaw=st.none() | st.tuples(st.floats(0.0, 0.6), st.floats(0.0, 0.5)), levels=st.lists(st.floats(0.0, 3.0), max_size=2))
def test_crossings_are_bit_identical(shape: str, seed: int, n: int, kind: str, slopes: list[float],
                                     jaw: tuple[float, float] | None, levels: list[float]) -> None:
    f = support_function(DOCS[shape](seed, n), kind)
    compiled, numpy_ = both(lambda: crossings(f, tuple(slopes), jaw, TOL, CURVE_GRID_RAD, levels=tuple(levels)))
    assert bits(compiled) == bits(numpy_)


def _probes(F: TransferFunction, rng: np.random.Generator) -> list[float]:
    """θ where a lookup can go wrong: every piece start, end and value, lifted by −2 … 3
    periods, with their float neighbours, ±0.0, and random θ."""
    base = [v for p in F.pieces for v in (p.start, p.end, p.value) if v is not None]
    lifted = [v + k * F.period for v in base for k in range(-2, 4)]
    near = [float(np.nextafter(v, d)) for v in lifted for d in (-np.inf, np.inf)]
    return [*lifted, *near, 0.0, -0.0, *rng.uniform(-10.0, 20.0, 16).tolist()]


def _lookups(F: TransferFunction, thetas: list[float]) -> list[Any]:
    """Every lookup of a fresh copy of F (no cached tables) at ``thetas``, and A′'s pieces."""
    G = TransferFunction(F.period, F.pieces)
    th = np.array(thetas)
    pieces = planner._Pieces.of(G)
    flags = [a.flags.writeable for a in G.lifted]
    return [G.lifted, flags, pieces.keys, G.apply_on_ramp(th), G.on_ramp(th), G._lookup(th), G.apply(th[::2]),
            G.steps_floats(thetas), G.apply_floats(thetas), G.apply_list(thetas[:16]), G.apply_list(thetas)]


@settings(max_examples=80, deadline=None)
@given(shape=st.sampled_from(sorted(DOCS)), seed=st.integers(0, 10_000), n=st.integers(3, 11), band=BAND)
def test_lookups_and_plans_are_bit_identical(shape: str, seed: int, n: int, band: tuple[float, ...]) -> None:
    """Exact functions and set-valued bounds (and their compositions): the lifted pieces,
    A′'s keys, the vectorised and plain-float lookups, shifts, pointwise minima and maxima,
    and the plans A′ finds."""
    d, r = (support_function(DOCS[shape](seed, n), kind) for kind in ("diameter", "radius"))
    with reference_path():
        fs = [from_runs(list(f.runs), f.period, TOL.angle_rad) for f in (d, r)]
        sets = []
        for f in (d, r):
            with suppress(NotOrientableError):
                sets.append(set_transfer(f, **set_args(f, band)))
        fs += [F for s in sets for F in (s.lower, s.upper)] + [fs[0].compose_after(fs[1], TOL.angle_rad)]
    rng = np.random.default_rng(seed)
    probes = [_probes(F, rng) for F in fs]

    def made() -> Any:
        out: list[Any] = [_lookups(F, th) for F, th in zip(fs, probes)]
        for F in fs[:2]:
            G = TransferFunction(F.period, F.pieces)
            try:
                out.append(planner.algorithm_a_prime(G, G.period / (1 + seed % 2)))
            except NotOrientableError as e:
                out.append(str(e))
        for P in {F.period for F in fs}:  # min and max of the functions of one period, with the identity
            same = [TransferFunction(P, F.pieces) for F in fs if F.period == P]
            groups = [same, [placement.identity(P), *same], [placement.identity(P), *(placement.shifted(F, 0.5 * P)
                                                                                      for F in same)]]
            out += [placement.pointwise(g, m, tol).pieces for g in groups for m in (False, True) for tol in (0.0, 1e-9)]
            out += [placement.shifted(F, d).pieces for F in same for d in (0.5 * P, np.pi, -1.3, 0.0, -0.0)]
        for s_ in sets:
            lo, up = TransferFunction(s_.period, s_.lower.pieces), TransferFunction(s_.period, s_.upper.pieces)
            lifted = planner.Lifted.of(lo, up)
            out += [planner._fixed(lo, lifted), planner._fixed(up, planner.Lifted.of(up))]
            out += [planner._sink_widths(lo, up, lifted, m) for m in (0.0, 1e-3, 0.3, np.pi)]
            out += [planner._widest(lo, lifted, room) for room in (1e-9, 0.01, 0.1, 0.5, 1.0, 3.0, float(seed % 5))]
            try:
                plan = planner.set_a_prime(lo, up, s_.symmetry, s_.circle_width())
                out += [plan, planner.images(lo, plan, up)]
                again = np.random.default_rng(seed)  # the same θ on both paths
                probes_ = list(zip(_probes(lo, again), _probes(up, again)))  # at and beside every piece
                out.append(planner.images(lo, probes_, up, planner.Lifted.of(lo, up)))
            except NotOrientableError as e:
                out.append(str(e))
        return out

    compiled, numpy_ = both(made)
    assert bits(compiled) == bits(numpy_)


@settings(max_examples=300, deadline=None)
@given(cuts=st.lists(st.floats(0.0, 1.0), max_size=12), rest=st.lists(st.booleans(), min_size=12, max_size=12),
       T=st.sampled_from([np.pi, 2.0 * np.pi, np.pi / 3, 0.7]), K=st.integers(1, 4))
def test_rest_zones_are_bit_identical(cuts: list[float], rest: list[bool], T: float, K: int) -> None:
    """Zones over K copies of random cells: all, none, runs through 0 and ±0.0 nodes."""
    nodes = np.array(sorted({c * T for c in cuts}) or [0.0])
    nodes[0] = -0.0 if K % 2 else nodes[0]
    r = np.array(rest[:len(nodes)])
    compiled, numpy_ = both(lambda: setcells.rest_zones(nodes, T, r, K * T))
    assert bits(compiled) == bits(numpy_)


def test_the_comparison_can_fail() -> None:
    """_bits tells apart what float equality does not."""
    assert bits(np.array([0.0])) != bits(np.array([-0.0]))
    assert bits([0.0]) != bits([-0.0])
    assert bits(np.array([True])) != bits(np.array([1], dtype=np.uint8))
