"""The compiled set-valued kernels of round 7 against the numpy path they replace, bit for
bit: the fused cells-to-bounds call (``_kernels.set_bounds``: both classification passes,
the refinement, the bounds and the rest zones in one call), the barrier search by records
(``_kernels.barriers``), and whole robust analyses (squeeze, push, push-grasp and the
off-centre squeeze) of random, regular and arc-sided parts under random physics. The
numpy path is the reference (run here with every module's hook switched off)."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from algrasp.compiled import KERNELS
from algrasp.errors import NotOrientableError
from algrasp.geometry.tolerances import DEFAULT_TOLERANCES as TOL
from algrasp.planning import barriers, edges, placement, setvalued, symmetry
from algrasp.planning.analysis import Analysis, Model, analyse_document
from algrasp.planning.setvalued import set_transfer
from algrasp.testing import shapes
from algrasp.testing.kernels import bits, both, families, reference_path, set_args, support_function

pytestmark = pytest.mark.skipif(KERNELS is None, reason="compiled kernels not built (or ALGRASP_PURE set)")


DOCS = families("polygon", "regular", "reuleaux", "flats", "pie")
"""Parts whose contacts are all point-like (vertices, circular arcs): the fused call's."""




# Small stalls and slope tolerances with a value error: the first pass asks for the
# refinement grid; deep shallow-basin depths: rims and a second pass.
BAND = st.tuples(st.sampled_from([0.0, 1e-3, 0.01, 0.05, 0.2]), st.floats(0.0, 0.1),
                 st.sampled_from([0.0, 1e-4, 1e-3, 0.02, 2.0]), st.sampled_from([1e-9, 1e-6, 1e-3]),
                 st.sampled_from([0.0, 1e-4, 1e-3, 1e-2, 0.05]), st.floats(0.0, 0.4),
                 st.sampled_from([0.0, 1e-4, 1e-2, 0.1]))


@settings(max_examples=200, deadline=None)
@given(shape=st.sampled_from(sorted(DOCS)), seed=st.integers(0, 10_000), n=st.integers(3, 12),
       kind=st.sampled_from(["diameter", "radius"]), band=BAND)
def test_fused_set_transfer_is_bit_identical(shape: str, seed: int, n: int, kind: str, band: tuple[float, ...]) -> None:
    """set_transfer through one set_bounds call (every contact point-like) equals the numpy
    path's passes, refinement, bounds and rest zones."""
    f = support_function(DOCS[shape](seed, n), kind)
    assert edges.point_contacts(f, setvalued._tolerances(TOL.angle_rad)) is not None  # the fused call is taken
    args = set_args(f, band)

    def made() -> Any:
        s = set_transfer(f, **args)
        return (s.lower.pieces, s.upper.pieces, s.symmetry, s.rest_zones, s.outcomes)

    compiled, numpy_ = both(made)
    assert bits(compiled) == bits(numpy_)


def test_the_refinement_and_second_pass_are_reached() -> None:
    """The fused call's rarer branches are exercised: a first pass that marks cells for the
    grid and one that finds shallow basins (checked on the numpy path's own passes)."""
    f = support_function(DOCS["polygon"](3, 7), "radius")
    scale = float(np.max(f.values(np.linspace(0.0, np.pi, 64))))
    band = setvalued._Band((1e-3 * scale, 2e-3 * scale), 1e-3 * scale, 0.0, 1e-2 * scale, 0.1 * scale)
    slopes_at, jaw = band.thresholds()
    with reference_path():
        found, _ = edges.crossings(f, slopes_at, jaw, TOL, edges.CURVE_GRID_RAD)
        first = setvalued._classify(f, f.period, found, np.zeros(0), band, first=True)
        assert first.rims and setvalued._to_refine(first, band).any()
    compiled, numpy_ = both(lambda: setvalued._bounds(f, f.period, band, TOL.angle_rad))
    assert bits(compiled) == bits(numpy_)


VALUES = st.lists(st.sampled_from([0.0, -0.0, 0.5, 1.0, 1.0 + 2.0 ** -52, 2.0, 3.0, 1e300, -1e300]), min_size=1,
                  max_size=80)


@settings(max_examples=300, deadline=None)
@given(values=VALUES, K=st.integers(1, 3), stall=st.sampled_from([0.0, 1e-3, 0.5, 3.0]),
       eps=st.sampled_from([0.0, 0.25, 1.0]), spacing=st.floats(1e-3, 1.0), seed=st.integers(0, 1000))
def test_barriers_are_bit_identical(values: list[float], K: int, stall: float, eps: float, spacing: float,
                                    seed: int) -> None:
    """The records search finds the linear scan's barriers: ties (plateaus, ±0.0), huge
    values, several copies; sizes on both sides of the numpy path's SCAN_SIZE."""
    rng = np.random.default_rng(seed)
    n = len(values)
    x = np.cumsum(np.full(n, spacing)) - spacing
    T = float(x[-1] + spacing)
    node = np.array([rng.permutation(values) for _ in range(K)], dtype=float)
    cell_max = np.maximum(node, np.roll(node, -1, axis=1)) + rng.choice([0.0, 0.25], size=node.shape)
    assert KERNELS is not None
    compiled = KERNELS.barriers(x, T, node, cell_max, stall, eps)
    numpy_ = barriers.barriers(x, T, node, cell_max, stall, eps)
    assert bits(list(compiled)) == bits(list(numpy_))


PHYSICS = st.fixed_dictionaries({}, optional={
    "jaw_friction": st.sampled_from([0.0, 0.1, [0.0, 0.3]]), "support_friction": st.sampled_from([0.2, [0.1, 0.5]]),
    "placement": st.sampled_from(["any", "centred"]), "creep": st.booleans(),
    "profile_tolerance": st.sampled_from([0.0, 1e-3, 0.02]), "com_tolerance": st.sampled_from([0.0, 0.01, 0.05])})


@settings(max_examples=60, deadline=None)
@given(shape=st.sampled_from([*sorted(DOCS), "blob"]), seed=st.integers(0, 10_000), n=st.integers(3, 10),
       physics=PHYSICS)
def test_robust_analyses_are_bit_identical(shape: str, seed: int, n: int, physics: dict[str, Any]) -> None:
    """A whole robust analysis: dead band, squeeze, push, push-grasp, off-centre squeeze
    and the refusals, on a fresh part for each path (no cache shared)."""
    make_doc = shapes.bezier_blob if shape == "blob" else None
    doc = make_doc(max(n, 4), seed) if make_doc else DOCS[shape](seed, n)
    model = Model.from_options({"physics": physics})
    compiled, numpy_ = both(lambda: _everything(analyse_document(doc, model)))
    assert bits(compiled) == bits(numpy_)


def _everything(a: Analysis) -> Any:
    """Every field of an analysis's set-valued functions, and its document."""
    assert a.robust is not None
    sets = [getattr(a.robust, name) for name in ("squeeze", "push", "push_grasp")]
    return a.to_dict(), [None if s is None else (s.lower.pieces, s.upper.pieces, s.period, s.symmetry, s.rest_zones,
                                                 s.outcomes, s.circle_images()) for s in sets]


@settings(max_examples=120, deadline=None)
@given(shape=st.sampled_from(sorted(DOCS)), seed=st.integers(0, 10_000), n=st.integers(3, 12), band=BAND,
       other=st.sampled_from(sorted(DOCS)))
def test_set_compositions_and_push_hulls_are_bit_identical(shape: str, seed: int, n: int, band: tuple[float, ...],
                                                           other: str) -> None:
    """SetTransfer.compose_after (both bounds and the outcomes that meet, over every copy
    of a symmetric outer function) and the off-centre squeeze's hull of partial pushes
    (symmetric pushes: a period T below 2π), on functions made once, on the numpy path."""
    with reference_path():
        sets = []
        for sh, kind in ((shape, "diameter"), (shape, "radius"), (other, "radius")):
            f = support_function(DOCS[sh](seed, n), kind)
            try:
                sets.append(set_transfer(f, **set_args(f, band)))
            except NotOrientableError:
                return

    def made() -> Any:
        out: list[Any] = []
        for a, b in ((sets[0], sets[1]), (sets[1], sets[2]), (sets[0], sets[0]), (sets[2], sets[1])):
            c = a.compose_after(b, TOL.angle_rad)
            out.append((c.lower.pieces, c.upper.pieces, c.symmetry, c.rest_zones, c.outcomes))
        for push in sets[1:]:
            out.append([F.pieces for F in placement._push_hull.__wrapped__(push, TOL.angle_rad)])  # type: ignore[attr-defined]
            s = placement.off_centre_squeeze(sets[0], push, TOL.angle_rad)
            out.append((s.lower.pieces, s.upper.pieces, s.symmetry, s.rest_zones, s.outcomes))
        return out

    compiled, numpy_ = both(made)
    assert bits(compiled) == bits(numpy_)


@settings(max_examples=150, deadline=None)
@given(shape=st.sampled_from(sorted(DOCS)), seed=st.integers(0, 10_000), n=st.integers(3, 12),
       kind=st.sampled_from(["diameter", "radius"]), tol=st.sampled_from([1e-12, 1e-9, 1e-6, 1e-3, 0.05]))
def test_symmetry_and_contacts_are_bit_identical(shape: str, seed: int, n: int, kind: str, tol: float) -> None:
    """The symmetry screen's run test (symmetry._none_by_runs) and the contact cells'
    arrays (edges._grid), uncached, on parts with and without symmetry."""
    f = support_function(DOCS[shape](seed, n), kind)
    if not f.extrema:  # constant width: no screen at an extremum
        return
    lowest = min(f.extrema, key=lambda e: e.value)

    def made() -> Any:
        grid = edges._grid.__wrapped__(f, TOL, edges.CURVE_GRID_RAD)  # type: ignore[attr-defined]
        c = grid.contacts
        return (symmetry.tolerant_symmetry(f, tol * lowest.value),
                symmetry._none_by_runs(f, lowest.theta, lowest.value, tol * lowest.value),
                [symmetry._none_by_runs(f, e.theta, e.value, tol) for e in f.extrema],
                c.rho, c.R, c.phi0, c.a, c.b, [a.flags.writeable for a in (c.rho, c.R, c.phi0, c.a, c.b)])

    compiled, numpy_ = both(made)
    assert bits(compiled) == bits(numpy_)
