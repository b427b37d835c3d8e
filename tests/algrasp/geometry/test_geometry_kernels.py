"""The compiled geometry kernels (algrasp.geometry._geometry) against the Python path they
replace: cells, runs, extrema and whole analyses bit for bit, on random polygons, regular
polygons, parts with circular arcs (point-like features of nonzero radius), made-up
breakpoint lists (cuts closer than the angle tolerance, coinciding centres, |Δ| at the
concentric limit itself) and made-up runs. The Python path is the reference (run here
with the hook switched off)."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from algrasp.compiled import GEOMETRY
from algrasp.errors import PartDocumentError
from algrasp.geometry import functions
from algrasp.geometry.angles import TWO_PI
from algrasp.geometry.functions import Run, analyse, theta_runs
from algrasp.geometry.part import SIMPLE_RING_MAX_POINTS, load_part
from algrasp.geometry.tolerances import DEFAULT_TOLERANCES as TOL
from algrasp.testing import shapes
from algrasp.testing.kernels import bits, both, families

needs_kernels = pytest.mark.skipif(GEOMETRY is None, reason="compiled geometry kernels not built (or ALGRASP_PURE set)")


def _both(make: Callable[[], Any]) -> tuple[Any, Any]:
    """(compiled, Python) results of ``make`` in :func:`bits` form, or the error each raised."""
    return both(lambda: bits(make()))


DOCS = families("polygon", "regular", "reuleaux", "flats", "pie", "disk", "rectangle")


@needs_kernels
@settings(max_examples=150, deadline=None)
@given(shape=st.sampled_from(sorted(DOCS)), seed=st.integers(0, 10_000), n=st.integers(3, 40),
       snap=st.booleans())
def test_analyses_are_bit_identical(shape: str, seed: int, n: int, snap: bool) -> None:
    part = load_part(DOCS[shape](seed, n), TOL, snap=snap)

    def made() -> Any:
        out = []
        for kind in ("diameter", "radius"):
            f = analyse(kind, part.hull, part.center_of_mass, part.size, TOL)  # type: ignore[arg-type]
            out.append((functions._cells(kind, part.hull, TOL.angle_rad), f.runs, f.extrema, f.constant_intervals))
        return out

    compiled, python = _both(made)
    assert compiled == python


class _Table:
    def __init__(self, bp: list[float]) -> None:
        self.breakpoint_list = bp
        self.s0 = np.zeros(0)


class _Feature:
    point_like = True

    def __init__(self, center: tuple[float, float]) -> None:
        self.center = center


class _Hull:
    """What the cells and runs read of a hull whose features are all point-like."""

    def __init__(self, bp: list[float], centers: list[tuple[float, float]]) -> None:
        self.table = _Table(bp)
        self.features = [_Feature(c) for c in centers]


def _breakpoints(start: float, gaps: list[float]) -> list[float]:
    """Sorted breakpoints from ``start`` covering less than a turn (gaps scaled to fit)."""
    total = sum(gaps)
    scale = (TWO_PI - 1e-3) / total if total > 0.0 else 0.0
    out, x = [], start
    for g in gaps:
        out.append(x)
        x += g * scale
    return out


GAP = st.one_of(st.floats(0.0, 2.0), st.sampled_from([0.0, 1e-12, 0.5 * TOL.angle_rad, TOL.angle_rad, 1e-8]))
COORD = st.one_of(st.floats(-3.0, 3.0), st.sampled_from([0.0, -0.0, 1.0, 1e-13]))


@needs_kernels
@settings(max_examples=300, deadline=None)
@given(start=st.floats(-7.0, 7.0), gaps=st.lists(GAP, min_size=1, max_size=12), kind=st.sampled_from(["diameter", "radius"]),
       coords=st.lists(st.tuples(COORD, COORD), min_size=13, max_size=13), repeat=st.lists(st.integers(0, 12), max_size=4),
       com=st.tuples(COORD, COORD), size=st.sampled_from([1.0, 3.0, 1e-6, 1e6]))
def test_made_up_runs_are_bit_identical(start: float, gaps: list[float], kind: str, coords: list[tuple[float, float]],
                                        repeat: list[int], com: tuple[float, float], size: float) -> None:
    bp = _breakpoints(start, gaps)
    centers = coords[: len(bp)]
    for k in repeat:  # coinciding centres: constant cells
        centers[k % len(bp)] = centers[0]
    hull = _Hull(bp, centers)
    compiled, python = _both(lambda: (functions._cells(kind, hull, TOL.angle_rad),  # type: ignore[arg-type]
                                      theta_runs(kind, hull, com, size, TOL)))  # type: ignore[arg-type]
    assert compiled == python


@needs_kernels
@settings(max_examples=200, deadline=None)
@given(dx=st.floats(1e-12, 10.0), angle=st.floats(0.0, TWO_PI), nudge=st.sampled_from([-2, -1, 0, 1, 2]),
       start=st.floats(-4.0, 4.0))
def test_concentric_limit_is_decided_alike(dx: float, angle: float, nudge: int, start: float) -> None:
    """|Δ| within an ulp or two of the concentric limit: the kernel must ask Python's hypot."""
    g = (dx * math.cos(angle), dx * math.sin(angle))
    size = math.hypot(*g) / TOL.concentric_rel
    for _ in range(abs(nudge)):
        size = math.nextafter(size, math.inf if nudge > 0 else 0.0)
    hull = _Hull(_breakpoints(start, [1.0, 1.0, 1.0]), [(0.0, 0.0), g, (0.0, 0.0)])
    for kind in ("diameter", "radius"):
        compiled, python = _both(lambda: theta_runs(kind, hull, (0.0, 0.0), size, TOL))  # type: ignore[arg-type]  # noqa: B023
        assert compiled == python


SIGN = st.sampled_from([-1, 0, 1])


def _near_rounding_edge(n: int, ulps: int) -> float:
    """(n + ½)·1e-9 moved by ``ulps`` units in the last place: where round(·, 9) turns."""
    x = (n + 0.5) * 1e-9
    for _ in range(abs(ulps)):
        x = math.nextafter(x, math.inf if ulps > 0 else -math.inf)
    return x


START = st.one_of(st.floats(-10.0, 10.0),
                  st.sampled_from([0.0, -0.0, math.pi, TWO_PI, -math.pi, math.pi - 1e-12, TWO_PI - 1e-13, 1 / 1024,
                                   3 / 1024, 0.5 + 1 / 1024]),
                  st.builds(_near_rounding_edge, st.integers(0, 6_000_000_000), st.integers(-3, 3)),
                  st.builds(lambda k: k / 1024, st.integers(0, 6400)))


@needs_kernels
@settings(max_examples=500, deadline=None)
@given(starts=st.lists(START, max_size=10), signs=st.lists(SIGN, min_size=20, max_size=20),
       period=st.sampled_from([math.pi, TWO_PI]), twins=st.lists(st.tuples(st.integers(0, 9), st.integers(-3, 3)), max_size=4))
def test_extremum_keys_are_bit_identical(starts: list[float], signs: list[int], period: float,
                                         twins: list[tuple[int, int]]) -> None:
    """Keys a few ulps apart, on and beside the edges where rounding to 9 digits turns,
    exact ties (multiples of 1/1024), and the diameter's θ + π copies."""
    for k, ulps in twins:  # a copy of a start a few ulps off, or half a turn on
        if k < len(starts):
            starts.append(math.nextafter(starts[k], math.inf) if ulps > 0 else starts[k] + (math.pi if ulps else 0.0))
    runs = [Run(s, s + 0.1, sg) for s, sg in zip(sorted(starts), signs)]
    compiled, python = _both(lambda: functions._extremum_keys(runs, period, TOL.angle_rad))
    assert compiled == python


@needs_kernels
def test_bad_signs_are_refused() -> None:
    with pytest.raises(ValueError, match="run signs"):
        GEOMETRY.extremum_keys([Run(0.0, 1.0, 2)], math.pi, TOL.angle_rad, functions._LABELS)  # type: ignore[union-attr]


POINTS = st.lists(st.tuples(st.one_of(st.floats(-2.0, 2.0), st.integers(-2, 2).map(float)),
                            st.one_of(st.floats(-2.0, 2.0), st.integers(-2, 2).map(float))), min_size=3, max_size=12)


@needs_kernels
@settings(max_examples=400, deadline=None)
@given(points=POINTS)
def test_a_ring_proved_simple_is_valid_for_geos(points: list[tuple[float, float]]) -> None:
    """simple_ring may be unsure, never wrong: what it proves simple GEOS finds valid."""
    import shapely

    if GEOMETRY.simple_ring([list(p) for p in points]):  # type: ignore[union-attr]
        assert shapely.is_valid_reason(shapely.polygons(np.array(points))) == "Valid Geometry"


@needs_kernels
@pytest.mark.parametrize("n", [3, 4, 7, 30])
def test_convex_and_star_rings_are_proved_simple(n: int) -> None:
    regular = shapes.regular_polygon(n, 2.0, 7.0)["polygon"]
    assert GEOMETRY.simple_ring(regular)  # type: ignore[union-attr]
    star = [[(0.6 + (k % 2)) * math.cos(k * TWO_PI / (2 * n)), (0.6 + (k % 2)) * math.sin(k * TWO_PI / (2 * n))]
            for k in range(2 * n)]
    assert GEOMETRY.simple_ring(star)  # type: ignore[union-attr]
    if n > 3:  # two corners of a convex ring swapped: edges 0 → 2 and 1 → 3 cross
        assert not GEOMETRY.simple_ring([regular[0], regular[2], regular[1], *regular[3:]])  # type: ignore[union-attr]
    assert not GEOMETRY.simple_ring([*star, star[0]])  # type: ignore[union-attr]  # a zero-length closing edge: unsure


TURN = st.one_of(st.floats(-0.5, 0.5), st.sampled_from([0.0, math.pi, TOL.snap_turn_rad, -TOL.tessellation_turn_rad,
                                                        TOL.tessellation_turn_rad + 1e-15, 2.0, -2.5]))


@settings(max_examples=400, deadline=None)
@given(turns=st.lists(TURN, min_size=3, max_size=14), lengths=st.lists(st.floats(0.01, 3.0), min_size=14, max_size=14),
       heading=st.floats(-4.0, 4.0))
def test_no_small_run_agrees_with_numpy(turns: list[float], lengths: list[float], heading: float) -> None:
    """recognise._no_small_run (libm's atan2 with a margin) may be unsure, never wrong: when
    it finds no run, numpy's turns have no run of small vertices either (open chains of
    the given turns: the loop's closing vertex takes what it gets)."""
    from algrasp.geometry import recognise
    from algrasp.geometry.segments import Line

    pts, x, y = [], 0.0, 0.0
    for t, ell in zip(turns, lengths):
        pts.append((x, y))
        heading += t
        x, y = x + ell * math.cos(heading), y + ell * math.sin(heading)
    loop = [Line(a, b) for a, b in zip(pts, [*pts[1:], pts[0]]) if a != b]
    amount = np.abs(recognise._signed_turns(loop))
    for limit, zero_small in ((TOL.snap_turn_rad, False), (TOL.tessellation_turn_rad, True)):
        if recognise._no_small_run(loop, limit, zero_small, TOL.tessellation_min_run):
            small = (amount <= limit) & ((amount > 0.0) | zero_small)
            assert not small.all()
            assert not recognise._run_list(small, TOL.tessellation_min_run)


@needs_kernels
@settings(max_examples=150, deadline=None)
@given(shape=st.sampled_from(["polygon", "regular", "rectangle"]), seed=st.integers(0, 10_000), n=st.integers(3, 40))
def test_nominal_size_is_bit_identical(shape: str, seed: int, n: int) -> None:
    from algrasp.planning import deadband

    part = load_part(DOCS[shape](seed, n), TOL)
    compiled, python = _both(lambda: deadband.nominal_size(part))
    assert compiled == python


@needs_kernels
@settings(max_examples=150, deadline=None)
@given(shape=st.sampled_from(["polygon", "regular", "rectangle"]), seed=st.integers(0, 10_000), n=st.integers(3, 40),
       psi=st.lists(st.one_of(st.floats(-30.0, 30.0), st.sampled_from([0.0, -0.0, math.pi, -TWO_PI, math.nan])),
                    max_size=20))
def test_vertex_support_is_bit_identical(shape: str, seed: int, n: int, psi: list[float]) -> None:

    hull = load_part(DOCS[shape](seed, n), TOL).hull
    assert hull.table.vertices_only
    normals = [np.array(psi), hull.breakpoints, hull.breakpoints + math.pi]
    compiled, python = _both(lambda: [hull.support_many(a) for a in normals])
    assert compiled == python


CLOUD = st.lists(st.tuples(COORD, COORD), min_size=1, max_size=40)


@needs_kernels
@settings(max_examples=300, deadline=None)
@given(points=CLOUD, line=st.integers(0, 12), slope=st.sampled_from([0.0, 1.0, 3.0, 1e-13]))
def test_hull_order_is_bit_identical(points: list[tuple[float, float]], line: int, slope: float) -> None:
    """Clouds with repeated points and runs of (nearly) collinear ones, where the left-turn
    test is within rounding of its limit and the kernel must ask Python's hypot."""
    from algrasp.geometry import hull

    cloud = [*points, *((t / 7.0, slope * t / 7.0) for t in range(line))]
    compiled, python = _both(lambda: hull.hull_order(np.array(cloud)))
    assert compiled == python


@needs_kernels
@settings(max_examples=200, deadline=None)
@given(shape=st.sampled_from(["polygon", "regular", "rectangle"]), seed=st.integers(0, 10_000), n=st.integers(3, 60),
       sliver=st.sampled_from([TOL.sliver_rad, 0.0, 0.3, 1.0]))
def test_corner_ranges_are_bit_identical(shape: str, seed: int, n: int, sliver: float) -> None:
    from algrasp.geometry import hull

    part = load_part(DOCS[shape](seed, n), TOL)
    corners = [f.center for f in part.hull.features]
    assert bits(GEOMETRY.corner_ranges(corners, sliver)) == bits(hull._corner_ranges(corners, sliver))  # type: ignore[union-attr]


@needs_kernels
@settings(max_examples=150, deadline=None)
@given(shape=st.sampled_from(["polygon", "regular", "rectangle"]), seed=st.integers(0, 10_000), n=st.integers(3, 40),
       theta=st.lists(st.one_of(st.floats(-30.0, 30.0), st.sampled_from([0.0, -0.0, math.pi, -TWO_PI, math.nan])),
                      max_size=20))
def test_values_are_bit_identical(shape: str, seed: int, n: int, theta: list[float]) -> None:
    """SupportPairFunction.values (the diameter's compiled pair of supports) and kink_thetas
    (in plain floats) against numpy's arrays."""

    part = load_part(DOCS[shape](seed, n), TOL)
    for kind in ("diameter", "radius"):
        f = analyse(kind, part.hull, part.center_of_mass, part.size, TOL)  # type: ignore[arg-type]
        compiled, python = _both(lambda: [f.values(np.array(theta)), f.values(f.kink_thetas)])  # noqa: B023
        assert compiled == python
        bp = part.hull.breakpoints
        kinks = [np.pi / 2 - bp, 1.5 * np.pi - bp] if kind == "diameter" else [1.5 * np.pi - bp]
        assert bits(f.kink_thetas) == bits(np.concatenate([*kinks, np.array([r.start for r in f.runs])]))


@needs_kernels
@settings(max_examples=150, deadline=None)
@given(seed=st.integers(0, 10_000), n=st.integers(3, 90), scale=st.sampled_from([1e-5, 1.0, 1e3]),
       shift=st.sampled_from([0.0, 7.0, -1e3]), holes=st.booleans())
def test_mean_radius_is_bit_identical(seed: int, n: int, scale: float, shift: float, holes: bool) -> None:
    """Polygons of up to 90 vertices: 540 terms, past numpy's blocks of 8 and 128 in its
    pairwise summation."""
    from algrasp.planning import deadband

    pts = [[shift + scale * x, shift + scale * y] for x, y in shapes.random_polygon(n, seed)["polygon"]]
    doc: dict[str, Any] = {"polygon": pts}
    if holes:
        doc["holes"] = [[[shift + scale * x, shift + scale * y] for x, y in ((-0.1, -0.1), (0.1, -0.1), (0.0, 0.1))]]
    try:
        part = load_part(doc, TOL)
    except PartDocumentError:  # too small for its place, or a hole crossing the boundary
        assume(False)
        return
    compiled, python = _both(lambda: deadband.mean_radius(part))
    assert compiled == python


@pytest.mark.parametrize("n", [SIMPLE_RING_MAX_POINTS, SIMPLE_RING_MAX_POINTS + 1, 400])
def test_long_rings_are_judged_alike_on_both_sides_of_the_proof_limit(n: int) -> None:
    """Past SIMPLE_RING_MAX_POINTS the O(n²) proof is skipped for GEOS: a simple ring is
    still accepted and a crossed one (two corners swapped) still refused (its explanation as before)."""
    regular = shapes.regular_polygon(n, 2.0, 7.0)
    assert len(load_part(regular).hull.features) == n
    crossed = regular["polygon"]
    with pytest.raises(PartDocumentError, match="self-intersecting boundary"):
        load_part({**regular, "polygon": [crossed[0], crossed[2], crossed[1], *crossed[3:]]})
