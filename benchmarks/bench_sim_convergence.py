"""Do simulated final orientations converge as the time step shrinks, with jaw friction?

One squeeze at gripper angle 0 (the validation's default schedule for a one-step plan:
jaws open to ``open_margin_factor``·reach, fast approach, slow contact, hold with grasp
detection, fast release) of three parts whose width has smooth minima, a 5 × 3 mm
ellipse (``ellipse_arc``), an 8 × 4 mm lens (two ``arc`` segments) and the paper's
pie-20, from seeded random orientations, at each jaw μ and time step. Per (part, μ,
placement) it prints, for each step:

- the largest and mean |Δφ| from the finest step, and the largest from the next finer;
- the statics gap: how far the worst outcome lies from any orientation where the part
  can rest, |d′(θ)| ≤ μ·d(θ) or a minimum of d, on the exact hull (the support friction
  is viscous at rest and holds nothing; the collision hull's chords may add up to half a
  chord's turn, 0.86°);
- runs Drake's solver failed on and repeated on a fallback (``model.SOLVER_FALLBACKS``),
  and runs that failed on every one (counted, not compared);
- wall and simulated seconds (workers share the cores: compare costs with ``--workers 1``).

The criterion: the two finest steps agree well under 0.25°.

Measured (16 samples, seed 0, both placements): the 0.5 and 0.25 ms steps agree within
0.09° on every part and μ, and their outcomes lie within 0.21° of a static rest (the
ellipse at μ 0.3 stops at its band's edge, 10.44°, at every step). The default 1 ms step
is off the converged outcome by up to 0.86° (lens, μ 0.1) and 1.04° (pie, μ 0.3, random
placement): a squeeze that ends in a sticky band reaches its edge still turning (the
jaws close at 10 mm/s while d′ → 0), and how far it coasts is resolved only below 1 ms
(the pie's 1.04° coasted past the edge to 1.2° from it, where the compliant patch at a
nearly flat edge holds it); with ``--jaw-speed 0.002`` 1 ms agrees with 0.25 ms within
0.09°. At 2 ms the frictionless and μ 0.1 pie spins away on some samples (172°). Drake's
solver failed on 6 of the 768 friction runs (lens, μ 0.3), all rescued by a fallback.

    .venv/bin/python benchmarks/bench_sim_convergence.py                  # 16 samples, 2 workers
    .venv/bin/python benchmarks/bench_sim_convergence.py --samples 8 --only pie --placement random
    .venv/bin/python benchmarks/bench_sim_convergence.py --jaw-speed 0.002  # slower contact phase

A script that prints a table, not a timed test.
"""

from __future__ import annotations

import argparse
import json
import math
import multiprocessing
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from pathlib import Path

import numpy as np

from algrasp.geometry.part import Part, load_part
from algrasp.sim.config import DEFAULT_SIM, OPEN_CLEARANCE_M, schedule, similar_config
from algrasp.sim.geometry import part_geometry

_LENS_DEG = math.degrees(math.atan2(3.0, 4.0))  # arcs of radius 5 mm about (0, ∓3) meet at (±4, 0)
PARTS: dict[str, dict] = {
    "ellipse 5x3": {"name": "ellipse-5x3", "units": "mm", "boundary": [
        {"type": "ellipse_arc", "center": [0, 0], "rx": 5, "ry": 3, "rotation_deg": 0, "start_deg": 0, "end_deg": 360}]},
    "lens 8x4": {"name": "lens-8x4", "units": "mm", "boundary": [
        {"type": "arc", "center": [0, -3], "radius": 5, "start_deg": _LENS_DEG, "end_deg": 180 - _LENS_DEG},
        {"type": "arc", "center": [0, 3], "radius": 5, "start_deg": 180 + _LENS_DEG, "end_deg": 360 - _LENS_DEG}]},
    "pie-20": json.loads((Path(__file__).parents[1] / "algrasp" / "examples" / "pie-20.json").read_text()),
}
STATICS_GRID_DEG = 0.02
"""Grid of the statics check (degrees): finer than any difference the table reports."""

Task = tuple[str, float, float, str, int, int, float]  # part, μ, step s, placement, samples, seed, jaw speed


def _starts(samples: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Initial φ (rad) and offsets (fractions of the open jaws' play), as validation draws them."""
    rng = np.random.default_rng(seed)
    return rng.uniform(0.0, 2 * math.pi, samples), rng.uniform(-0.5, 0.5, samples)


Result = tuple[list[float], float, float, int]  # final φ (°), wall s, simulated s, runs on a solver fallback


def simulate(task: Task) -> Result:
    """Final φ (degrees, unwrapped; NaN where every solver fallback failed) of every
    sample of one (part, μ, step, placement), wall and simulated seconds, and how many
    runs fell back (``SOLVER_FALLBACKS``). Runs in a worker: pydrake is imported here."""
    from algrasp.sim.model import PlanarGripperSim

    name, mu, step, placement, samples, seed, jaw_speed = task
    part = load_part(PARTS[name])
    cfg = similar_config(replace(DEFAULT_SIM, jaw_friction=mu, jaw_speed_m_s=jaw_speed),
                         part_geometry(part, DEFAULT_SIM).reach_m)
    cfg = replace(cfg, time_step_s=step)
    t0 = time.perf_counter()
    sim = PlanarGripperSim(part, cfg)
    reach = sim.geom.reach_m
    W = cfg.open_margin_factor * reach + OPEN_CLEARANCE_M
    phases = schedule([0.0], "squeeze", W, 0.0, cfg, reach_m=reach)
    centred = placement == "centred"
    finals, simulated = [], 0.0
    for phi0, frac in zip(*_starts(samples, seed)):
        offset = 0.0 if centred else float(frac) * (W - reach)
        try:
            phi, _, _ = sim.run(phases, float(phi0), offset, 0.0, W, centring=centred)
        except RuntimeError as exc:  # every fallback failed: a result here, not a crash
            print(f"{name}, μ {mu:g}, {1e3 * step:g} ms, φ0 {math.degrees(phi0):.2f}°, offset {1e3 * offset:.3f} mm: "
                  f"{str(exc).splitlines()[0]}", flush=True)
            phi = math.nan
        finals.append(math.degrees(phi))
        simulated += sim.sim_seconds
    return finals, time.perf_counter() - t0, simulated, sim.fallback_runs


def width_ratio(part: Part) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """θ (degrees, one period of d), d′(θ)/d(θ) (per radian) and whether d has a local
    minimum there, on the exact hull: d(θ) = h(π/2 − θ) + h(3π/2 − θ) for jaws closing
    along world y and the part turned by θ."""
    theta = np.radians(np.arange(0.0, 180.0, STATICS_GRID_DEG))
    psi = np.concatenate([np.pi / 2 - theta, 3 * np.pi / 2 - theta])
    h = np.sum(part.hull.support_points(psi) * np.column_stack([np.cos(psi), np.sin(psi)]), axis=1)
    d = h[:theta.size] + h[theta.size:]
    spacing = math.pi / theta.size  # rad; d has period π, so the differences wrap
    slope = (np.roll(d, -1) - np.roll(d, 1)) / (2 * spacing)
    minimum = (d <= np.roll(d, 1)) & (d <= np.roll(d, -1))
    return np.degrees(theta), slope / d, minimum


def statics_gap_deg(finals_deg: list[float], ratio: tuple[np.ndarray, np.ndarray, np.ndarray], mu: float) -> float:
    """Largest distance (degrees) from a final orientation to the nearest one where the
    part can rest between the jaws: |d′| ≤ μ·d (friction holds the squeeze couple F·d′
    with μF·d) or a minimum of d (the only rests without friction)."""
    theta, r, minimum = ratio
    rest = theta[(np.abs(r) <= mu + 1e-6) | minimum]  # 1e-6/rad: rounding on d's flat stretches
    gaps = [float(np.min(np.abs((f - rest + 90.0) % 180.0 - 90.0))) for f in finals_deg if math.isfinite(f)]
    return max(gaps, default=math.nan)


def _diff(a: list[float], b: list[float]) -> np.ndarray:
    return np.abs((np.asarray(a) - np.asarray(b) + 180.0) % 360.0 - 180.0)


def report(name: str, mu: float, placement: str, steps: list[float],
           results: dict[float, Result]) -> float:
    """Print one (part, μ, placement) block; returns the two finest steps' largest |Δφ| (°)."""
    finest, ratio = steps[-1], width_ratio(load_part(PARTS[name]))
    print(f"\n{name}, jaw μ {mu:g}, {placement} placement")
    print(f"  {'step ms':>7s} {'max|Δ| fin':>10s} {'mean|Δ| fin':>11s} {'max|Δ| next':>11s} "
          f"{'statics gap':>11s} {'fallback':>8s} {'failed':>6s} {'wall s':>7s} {'sim s':>6s}")
    for i, step in enumerate(steps):
        finals, wall, simulated, fallbacks = results[step]
        to_fin = _diff(finals, results[finest][0])
        nxt = f"{np.nanmax(_diff(finals, results[steps[i + 1]][0])):11.3f}" if i + 1 < len(steps) else f"{'':11s}"
        print(f"  {1e3 * step:7.2f} {np.nanmax(to_fin):10.3f} {np.nanmean(to_fin):11.3f} {nxt} "
              f"{statics_gap_deg(finals, ratio, mu):11.3f} {fallbacks:8d} {int(np.sum(np.isnan(finals))):6d} "
              f"{wall:7.1f} {simulated:6.1f}")
    return float(np.nanmax(_diff(results[steps[-2]][0], results[finest][0]))) if len(steps) > 1 else 0.0


def _run(tasks: list[Task], workers: int) -> list[Result]:
    """All tasks, finest steps first (the longest), in spawned workers (never a forked pydrake)."""
    if workers <= 1:
        return [simulate(t) for t in tasks]
    order = sorted(range(len(tasks)), key=lambda i: tasks[i][2])
    with ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn")) as pool:
        done = dict(zip(order, pool.map(simulate, [tasks[i] for i in order])))
    return [done[i] for i in range(len(tasks))]


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=16)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--friction", default="0,0.1,0.3", help="jaw μ values, comma-separated")
    ap.add_argument("--steps-ms", default="2,1,0.5,0.25", help="time steps (ms), coarsest first")
    ap.add_argument("--placement", default="centred,random", help="centred and/or random")
    ap.add_argument("--only", default="", help="parts whose name contains one of these (comma-separated)")
    ap.add_argument("--jaw-speed", type=float, default=DEFAULT_SIM.jaw_speed_m_s, help="contact-phase jaw speed (m/s)")
    args = ap.parse_args(argv)
    steps = [1e-3 * float(s) for s in args.steps_ms.split(",")]
    names = [n for n in PARTS if not args.only or any(k in n for k in args.only.split(","))]
    keys = [(n, float(mu), p) for n in names for mu in args.friction.split(",") for p in args.placement.split(",")]
    tasks = [(n, mu, s, p, args.samples, args.seed, args.jaw_speed) for n, mu, p in keys for s in steps]
    t0 = time.perf_counter()
    out = iter(_run(tasks, args.workers))
    worst = {k: report(*k, steps, {s: next(out) for s in steps}) for k in keys}
    print(f"\n{args.samples} samples each, seed {args.seed}, jaw speed {args.jaw_speed:g} m/s, "
          f"{time.perf_counter() - t0:.0f} s in all")
    for (n, mu, p), w in worst.items():
        print(f"  two finest steps, {n}, μ {mu:g}, {p}: max |Δφ| = {w:.3f}°{'' if w < 0.25 else '  (NOT converged)'}")


if __name__ == "__main__":
    main()
