"""Diameter/radius extrema and transfer functions against independent truth."""

from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest

from algrasp.geometry.part import load_part
from algrasp.planning.analysis import analyse_part
from algrasp.testing import shapes
from tests.algrasp.helpers import diameter_of_points, match_angles, squeeze_by_flow, wrapped_close

DEG = math.pi / 180


def widths_deg(pieces: list) -> list[float]:
    return sorted(round(math.degrees(p.end - p.start), 9) for p in pieces)


def test_pie_squeeze_function_matches_paper() -> None:
    """Conventions §6 / paper §4: two steps of 70° and one ramp of 40° per 180°."""
    a = analyse_part(load_part(shapes.pie()))
    assert widths_deg(list(a.squeeze.steps)) == [70.0, 70.0]
    assert widths_deg(list(a.squeeze.ramps)) == [40.0]
    # Paper: steps [0, 70) → 50 and [70, 140) → 90, ramp [140, 180) in a frame turned by 20°.
    ramp = a.squeeze.ramps[0]
    offsets = sorted(round(math.degrees(s.value - (ramp.end - math.pi)) % 180.0, 9) for s in a.squeeze.steps)
    assert offsets == [50.0, 90.0]
    # d on the ramp is the radius (arc centred on the opposite vertex), minima 5 sin 40°, max 10 sin 20°.
    d = a.to_dict()["diameter"]
    assert {round(e["value"], 12) for e in d["extrema"] if e["kind"] == "min"} == {round(5 * math.sin(40 * DEG), 12)}
    assert any(abs(e["value"] - 10 * math.sin(20 * DEG)) < 1e-12 and e["equilibrium"] == "unstable" for e in d["extrema"])
    assert sorted(e["equilibrium"] for e in d["extrema"] if e["kind"] == "max").count("semiunstable") == 2


def test_rectangle_closed_form() -> None:
    """d(θ) = w|sin θ| + h|cos θ|: minima at 0, 90°, maxima at atan(w/h) and its mirror."""
    w, h = 3.0, 1.0
    a = analyse_part(load_part(shapes.rectangle(w, h)))
    theta = np.linspace(0, 2 * np.pi, 997)
    assert a.diameter.values(theta) == pytest.approx(w * np.abs(np.sin(theta)) + h * np.abs(np.cos(theta)), rel=1e-12)
    star = math.degrees(math.atan2(w, h))
    ext = a.to_dict()["diameter"]["extrema"]
    match_angles([e["theta_deg"] for e in ext if e["kind"] == "max"], [star, 180 - star], 180, 1e-9)
    match_angles([e["theta_deg"] for e in ext if e["kind"] == "min"], [0.0, 90.0], 180, 1e-9)
    sq = a.to_dict()["squeeze"]
    assert sq["symmetry_period_deg"] == pytest.approx(180.0)
    steps = sorted((s["start_deg"], s["end_deg"], s["fixed_point_deg"]) for s in sq["steps"])
    assert np.allclose(steps, [(star, 180 - star, 90.0), (180 - star, 180 + star, 0.0)], atol=1e-9)


@pytest.mark.parametrize("sides", [3, 4, 5, 6, 7, 8])
def test_regular_polygon_periods(sides: int) -> None:
    """Paper §2.2: T_r = 2π / (r(1 + r mod 2)); the push function has period 2π/r."""
    a = analyse_part(load_part(shapes.regular_polygon(sides, phase_deg=7.0)))
    d = a.to_dict()
    assert d["squeeze"]["symmetry_period_deg"] == pytest.approx(360.0 / (sides * (1 + sides % 2)))
    assert d["push"]["symmetry_period_deg"] == pytest.approx(360.0 / sides)
    assert len(a.squeeze.steps) == sides * (1 + sides % 2) // 2


@pytest.mark.parametrize("z_deg", [5.0, 10.0, 30.0])
def test_disk_with_flats(z_deg: float) -> None:
    """Fig. 11: one step of width 2z and one ramp of width 180° − 2z per period."""
    a = analyse_part(load_part(shapes.disk_with_flats(2.0, z_deg)))
    assert widths_deg(list(a.squeeze.steps)) == [pytest.approx(2 * z_deg)]
    assert widths_deg(list(a.squeeze.ramps)) == [pytest.approx(180 - 2 * z_deg)]


@pytest.mark.parametrize("doc", [shapes.disk(2.0), shapes.reuleaux(1.5)])
def test_constant_width_has_no_squeeze_step(doc: dict) -> None:
    a = analyse_part(load_part(doc))
    assert not a.squeeze.steps and not a.squeeze_orientable
    out = a.to_dict()
    assert out["squeeze"]["orientable"] is False and "constant diameter" in out["squeeze"]["reason"]
    assert out["diameter"]["constant_intervals_deg"] == [[0.0, 180.0]]


def test_arc_centred_on_centre_of_mass_is_a_push_ramp() -> None:
    """r is constant where the lower jaw touches an arc centred on the centre of mass."""
    a = analyse_part(load_part(shapes.disk_with_flats(2.0, 20.0)))
    assert widths_deg(list(a.push.ramps)) == [pytest.approx(140.0), pytest.approx(140.0)]
    assert a.radius(math.radians(90.0)) == pytest.approx(2.0)


def _bezier_part() -> dict:
    return {"boundary": [
        {"type": "line", "start": [0, 0], "end": [4, 0]},
        {"type": "bezier", "points": [[4, 0], [6.5, 1.0], [5.0, 4.0], [2.0, 4.2]]},
        {"type": "bezier", "points": [[2.0, 4.2], [0.5, 4.3], [-0.8, 2.5], [-0.5, 1.5], [-0.3, 0.6], [0, 0]]}]}


def _mp_diameter_extrema(doc: dict, digits: int = 30) -> list[float]:
    """Extrema of d by an independent mpmath computation on the raw curves (radians)."""
    mp.mp.dps = digits
    curves = [[mp.matrix(p) for p in s["points"]] if s["type"] == "bezier" else [mp.matrix(s["start"]), mp.matrix(s["end"])]
              for s in doc["boundary"]]

    def bez(cps: list, t: mp.mpf) -> tuple:
        n = len(cps) - 1
        x = sum(mp.binomial(n, i) * t**i * (1 - t) ** (n - i) * cps[i][0] for i in range(n + 1))
        y = sum(mp.binomial(n, i) * t**i * (1 - t) ** (n - i) * cps[i][1] for i in range(n + 1))
        return x, y

    def support_points(theta: mp.mpf) -> tuple:
        u = (mp.sin(theta), mp.cos(theta))
        best_hi, best_lo = None, None
        for cps in curves:
            n = len(cps) - 1
            # ⟨B′(t), u⟩ = n Σ (P_{i+1} − P_i)·u B_{i,n-1}(t): roots by mpmath's polynomial solver.
            diffs = [(cps[i + 1][0] - cps[i][0]) * u[0] + (cps[i + 1][1] - cps[i][1]) * u[1] for i in range(n)]
            coeffs = [mp.mpf(0)] * n
            for i, c in enumerate(diffs):
                for j in range(n - i):
                    coeffs[i + j] += mp.binomial(n - 1, i) * mp.binomial(n - 1 - i, j) * (-1) ** j * c
            ts = [mp.mpf(0), mp.mpf(1)]
            if n >= 2 and any(abs(c) > 0 for c in coeffs):
                deg = max(k for k, c in enumerate(coeffs) if abs(c) > mp.mpf(10) ** (-digits + 5))
                if deg >= 1:
                    for r in mp.polyroots(coeffs[: deg + 1], maxsteps=200, extraprec=200, asc=True):
                        if abs(mp.im(r)) < mp.mpf(10) ** -20 and 0 <= mp.re(r) <= 1:
                            ts.append(mp.re(r))
            for t in ts:
                p = bez(cps, t)
                v = p[0] * u[0] + p[1] * u[1]
                if best_hi is None or v > best_hi[0]:
                    best_hi = (v, p)
                if best_lo is None or v < best_lo[0]:
                    best_lo = (v, p)
        return best_hi[1], best_lo[1]

    def dprime(theta: mp.mpf) -> mp.mpf:
        hi, lo = support_points(theta)
        du = (mp.cos(theta), -mp.sin(theta))
        return (hi[0] - lo[0]) * du[0] + (hi[1] - lo[1]) * du[1]

    # Sign changes of d′ over a grid offset from 0 (a flat edge puts a kink exactly at 0),
    # each located by bisection: d′ jumps at kinks, so no derivative-based solver.
    n = 360
    grid = [mp.pi * (k - mp.mpf(0.5)) / n for k in range(n + 1)]
    vals = [dprime(t) for t in grid]
    out = []
    for k in range(n):
        if vals[k] * vals[k + 1] < 0:
            lo, hi, s_lo = grid[k], grid[k + 1], vals[k]
            for _ in range(90):
                mid = (lo + hi) / 2
                if dprime(mid) * s_lo > 0:
                    lo = mid
                else:
                    hi = mid
            out.append(float((lo + hi) / 2) % math.pi)
    return out


def test_bezier_extrema_match_mpmath_reference() -> None:
    doc = _bezier_part()
    a = analyse_part(load_part(doc))
    ours = [e.theta for e in a.diameter.extrema]
    ref = _mp_diameter_extrema(doc)
    match_angles(ours, ref, math.pi, 1e-9)


@pytest.mark.parametrize("seed", range(6))
def test_squeeze_matches_brute_force_flow(seed: int) -> None:
    """Γ(θ) equals where downhill motion on d (brute force over raw vertices) stops."""
    doc = shapes.random_polygon(9, seed)
    a = analyse_part(load_part(doc))
    pts = np.array(doc["polygon"])
    breaks = [p.start for p in a.squeeze.pieces]
    rng = np.random.default_rng(seed)
    for theta in rng.uniform(0, np.pi, 25):
        if any(wrapped_close(theta, b, np.pi, 2e-3) for b in breaks):
            continue
        assert wrapped_close(a.squeeze(theta), squeeze_by_flow(pts, theta), np.pi, 3e-4)


def test_diameter_values_match_brute_force_on_curves() -> None:
    doc = shapes.bezier_blob(9, 5)
    a = analyse_part(load_part(doc))
    from algrasp.geometry.part import load_part as lp
    part = lp(doc)
    dense = np.concatenate([np.asarray(s.piece().point(np.linspace(0, 1, 4001))) for s in part.boundary])
    theta = np.linspace(0, np.pi, 181)
    assert a.diameter.values(theta) == pytest.approx(diameter_of_points(dense, theta), abs=1e-6)
