"""Fast paths of the robust model (issue 34): each gives the general path's values bit
for bit, on parts and piece lists the tests make themselves."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from algrasp.geometry.functions import SupportPairFunction, analyse
from algrasp.geometry.part import load_part
from algrasp.geometry.tolerances import DEFAULT_TOLERANCES as TOL
from algrasp.planning import symmetry
from algrasp.planning.analysis import ROBUST, analyse_document
from algrasp.planning.setvalued import SetTransfer
from algrasp.planning.transfer import TransferFunction, TransferPiece, arcs_holding, canonical, holding_arcs
from algrasp.testing import shapes

_DOCS = [shapes.regular_polygon(3, 2.0, 7.0), shapes.rectangle(3.0, 1.0), shapes.pie(5.0, 20.0),
         *(shapes.random_polygon(n, seed) for n, seed in ((5, 1), (7, 2), (9, 3), (10, 4)))]


def _sets() -> list[SetTransfer]:
    out = []
    for doc in _DOCS:
        r = analyse_document(doc, ROBUST).robust
        assert r is not None
        out += [S for S in (r.squeeze, r.push, r.push_grasp) if S is not None]
    return out


_SETS = _sets()


def _bits(xs: object) -> bytes:
    return np.array(xs, dtype=float).tobytes()


@pytest.mark.parametrize("F", [F for S in _SETS for F in (S.lower, S.upper)])
def test_floats_are_the_arrays_floats(F: TransferFunction) -> None:
    """The plain-float lookup table is the array one's, bit for bit (NaN on ramps)."""
    first, starts, values = F._floats
    a_first, a_values = F._search
    assert _bits(first) == _bits(float(a_first)) and _bits(starts) == _bits(F._arrays[0])
    assert _bits(values) == a_values.tobytes()


def _general_canonical(pieces: list[TransferPiece], period: float, tol_rad: float) -> list[TransferPiece]:
    """canonical written out without its shortcut: merge, wrap, shift each piece, sort."""
    merged: list[TransferPiece] = []
    for p in pieces:
        if merged and ((merged[-1].value is None and p.value is None) or (
                merged[-1].value is not None and p.value is not None and abs(merged[-1].value - p.value) <= tol_rad)):
            merged[-1] = TransferPiece(merged[-1].start, p.end, merged[-1].value)
        else:
            merged.append(p)
    if len(merged) > 1:
        a, b = merged[-1], merged[0].shifted(period)
        if (a.value is None and b.value is None) or (
                a.value is not None and b.value is not None and abs(a.value - b.value) <= tol_rad):
            last = merged.pop()
            merged[0] = TransferPiece(last.start - period, merged[0].end,
                                      None if last.value is None else last.value - period)
    out = []
    for p in merged:
        k = math.floor(p.start / period + 1e-12) if p.start >= 0 else math.floor(p.start / period)
        if k:
            p = p.shifted(-k * period)
        out.append(p.shifted(-period) if p.start >= period - tol_rad else p)
    return sorted(out, key=lambda p: p.start)


_piece_lists = st.lists(st.tuples(st.floats(-1.0, 7.5), st.floats(0.0, 2.0), st.one_of(st.none(), st.floats(-7.0, 14.0)),
                                  st.booleans()), min_size=1, max_size=12)


@settings(max_examples=400, deadline=None)
@given(_piece_lists, st.sampled_from([np.pi, 2.0 * np.pi]), st.sampled_from([0.0, 1e-9, 0.3]), st.booleans())
def test_canonical_is_the_general_path(raw: list[tuple[float, float, float | None, bool]], period: float,
                                       tol_rad: float, contiguous: bool) -> None:
    """Piece lists sorted and in range (the shortcut), and not (shifted, unsorted, wrapping
    merges, starts a hair below the period): the same pieces, bit for bit."""
    if contiguous:  # sorted pieces tiling [s, s + period): the shortcut's case when s ≥ 0
        s = abs(raw[0][0]) % period
        cuts = sorted({s + (period * abs(a) / 7.5) % period for a, _, _, _ in raw} | {s})
        ends = [*cuts[1:], s + period]
        pieces = [TransferPiece(a, b, None if v is None else v) for a, b, (_, _, v, _) in zip(cuts, ends, raw)]
    else:
        pieces = [TransferPiece(period - 1e-13 if near else a, (period - 1e-13 if near else a) + w, v)
                  for a, w, v, near in raw]
    got, want = canonical(list(pieces), period, tol_rad), _general_canonical(list(pieces), period, tol_rad)
    assert [(p.start, p.end, p.value) for p in got] == [(p.start, p.end, p.value) for p in want]
    assert _bits([(p.start, p.end, math.nan if p.value is None else p.value) for p in got]) == \
        _bits([(p.start, p.end, math.nan if p.value is None else p.value) for p in want])


def _meeting_arrays(S: SetTransfer, lo: list[float], hi: list[float], T: float) -> tuple[tuple[float, float], ...]:
    """The outcome test in arrays (as composition first wrote it)."""
    lo_a, hi_a = np.array(lo), np.array(hi)
    copies = np.arange(max(1, int(round(T / S.symmetry)))) * S.symmetry
    mine = (np.array(S.outcomes)[None, :, :] + copies[:, None, None]).reshape(-1, 2)
    start = np.mod(mine[:, 0] - lo_a[:, None], T)
    meets = (start <= (hi_a - lo_a)[:, None]) | (start + (mine[:, 1] - mine[:, 0])[None, :] >= T)
    return tuple(map(tuple, mine[meets.any(axis=0)].tolist()))


@pytest.mark.parametrize("S", _SETS)
def test_meeting_is_the_array_test(S: SetTransfer) -> None:
    """Random arcs (and the arcs a composition passes) over T = the symmetry and 2π."""
    rng = np.random.default_rng(5)
    for T in {S.symmetry, 2.0 * np.pi}:
        for _ in range(30):
            lo = rng.uniform(-T, 2.0 * T, int(rng.integers(1, 6)))
            hi = lo + rng.uniform(0.0, T, len(lo)) * rng.choice([0.0, 0.01, 1.0], len(lo))
            got = S._meeting(lo.tolist(), hi.tolist(), T)
            assert _bits(got) == _bits(_meeting_arrays(S, lo.tolist(), hi.tolist(), T)) and len(got) == len(
                _meeting_arrays(S, lo.tolist(), hi.tolist(), T))
        for inner in _SETS:
            if inner.symmetry == T:
                lo_l = S.lower.apply_list([a for a, _ in inner.outcomes]).tolist()
                hi_l = S.upper.apply_list([b for _, b in inner.outcomes]).tolist()
                assert S._meeting(lo_l, hi_l, T) == _meeting_arrays(S, lo_l, hi_l, T)


def _lowest(f: SupportPairFunction) -> tuple[float, float]:
    e = min(f.extrema, key=lambda e: e.value)
    return e.theta, e.value


def _functions_of(doc: dict[str, object]) -> list[SupportPairFunction]:
    part = load_part(doc, TOL, snap=True)
    return [analyse(kind, part.hull, part.center_of_mass, part.size, TOL) for kind in ("diameter", "radius")]


@settings(max_examples=60, deadline=None)
@given(st.integers(3, 12), st.integers(0, 10_000), st.sampled_from([1e-7, 7e-7, 1e-4, 1e-2, 0.2]))
def test_none_by_runs_only_when_every_order_fails(n: int, seed: int, value_tol: float) -> None:
    """Random polygons: the runs' verdict, when it gives one, is the test of every shifted
    point (all 359 evaluated here), and the symmetry found with and without it agree."""
    for f in _functions_of(shapes.random_polygon(n, seed)):
        if not f.extrema:
            continue
        theta, value = _lowest(f)
        threshold = value_tol + symmetry.SCREEN_SLACK * abs(value)
        every = bool((np.abs(f.values(theta + f.period / symmetry._ORDERS) - value) > threshold).all())
        assert not symmetry._none_by_runs(f, theta, value, threshold) or every
        assert symmetry._none_at(f, theta, value, symmetry._ORDERS, value_tol) == every


@pytest.mark.parametrize("doc", [shapes.rectangle(3.0, 1.0), shapes.regular_polygon(5), shapes.regular_polygon(7, 1.0, 3.0),
                                 shapes.pie(5.0, 20.0), shapes.disk_with_flats(), shapes.reuleaux(),
                                 shapes.bezier_cam(), *_DOCS])
def test_symmetry_with_and_without_the_runs_verdict(doc: dict[str, object], monkeypatch: pytest.MonkeyPatch) -> None:
    """Symmetric, arc and curve parts: the same period with the runs' verdict as without."""
    for value_tol in (1e-7, 1e-4, 1e-2):
        fast = [symmetry.tolerant_symmetry(f, value_tol) for f in _functions_of(doc)]
        with monkeypatch.context() as m:
            m.setattr(symmetry, "_none_by_runs", lambda *a: False)
            slow = [symmetry.tolerant_symmetry(f, value_tol) for f in _functions_of(doc)]
        assert _bits(fast) == _bits(slow)


_intervals = st.lists(st.tuples(st.sampled_from([-7.0, -3.1, -0.0, 0.0, 0.5, 1.0, 3.1, 6.2]) | st.floats(-8.0, 8.0),
                                st.sampled_from([0.0, 0.5, 1.0]) | st.floats(0.0, 7.0)), min_size=1, max_size=20)


@settings(max_examples=500, deadline=None)
@given(_intervals, st.sampled_from([np.pi, 2.0 * np.pi, 2.0 * np.pi / 5, 1.0]))
def test_arcs_holding_is_holding_arcs(pairs: list[tuple[float, float]], T: float) -> None:
    """Random intervals (±0.0, repeated ends, ties between gaps, wider than T): the plain-float
    arcs are the vectorised ones, bit for bit."""
    lo = [a for a, _ in pairs]
    hi = [a + w for a, w in pairs]
    got, want = arcs_holding(lo, hi, T), holding_arcs(np.array(lo), np.array(hi), T)
    assert len(got) == len(want) and _bits(got) == _bits(want)


@pytest.mark.parametrize("S", _SETS)
def test_circle_images_in_floats(S: SetTransfer) -> None:
    """The arcs every robust function of the parts keeps are the vectorised ones."""
    want = holding_arcs(np.array([a for a, _ in S.outcomes]), np.array([b for _, b in S.outcomes]), S.symmetry)
    assert _bits(S.circle_images()) == _bits(want) and len(S.circle_images()) == len(want)
    for F in (S.lower, S.upper):
        lo = np.array([p.start if p.value is None else p.value for p in F.pieces])
        hi = np.array([p.end if p.value is None else p.value for p in F.pieces])
        assert _bits(F.circle_images(S.symmetry)) == _bits(holding_arcs(lo, hi, S.symmetry))


def _lifted_arrays(F: TransferFunction) -> tuple[np.ndarray, ...]:
    """The lifted pieces as first written: starts, ends and values (a ramp's start) of
    every piece plus k·P for k = −1 … 3, and the ramp flags."""
    starts = np.array([p.start for p in F.pieces])
    values = np.array([np.nan if p.value is None else p.value for p in F.pieces])
    ramp = np.isnan(values)
    lift = (np.arange(-1, 4) * F.period)[:, None]
    return ((starts + lift).ravel(), (np.array([p.end for p in F.pieces]) + lift).ravel(),
            (np.where(ramp, starts, values) + lift).ravel(), np.concatenate([ramp] * 5))


@pytest.mark.parametrize("F", [F for S in _SETS for F in (S.lower, S.upper)])
def test_lifted_is_the_piecewise_lifting(F: TransferFunction) -> None:
    got = F.lifted
    assert all(g.tobytes() == w.tobytes() and g.dtype == w.dtype for g, w in zip(got, _lifted_arrays(F)))
    assert not any(g.flags.writeable for g in got)
