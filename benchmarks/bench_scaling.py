"""Cost against size (issue 34): analysis time on the default model (robust, default
ranges) and on the exact model for random polygons of 10 … 10,000 vertices, and
planning time for plans of growing length N (the Fig. 11 part, N ~ 1/z), each with the
exponent of a least-squares fit t ~ size^k. Under the default ranges the Fig. 11 squeeze
is refused (its near-constant width and jaw friction up to 0.1); the plan table adds the
robust model in the one ideal cell of the paper (frictionless jaws, centred, support
μ 0.3, 20 g, an exact part), where plans exist and grow with 1/z.

The paper's bound is O(n² log n + N) for the exact analysis and plan; the robust model
adds the grid of set-valued cells (O(c log c), c ≈ π / 2 mrad per function), so at small n
its time is the grid's, not the part's.
"""

from __future__ import annotations

import contextlib
import statistics
import time
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np

from algrasp.errors import NotOrientableError
from algrasp.geometry.arcforms import document, fig11_outline
from algrasp.planning.analysis import EXACT, ROBUST, Model, analyse_document
from algrasp.planning.physics import DEFAULT_PHYSICS
from algrasp.planning.plans import make_plan
from algrasp.testing import shapes


def median_s(fn: Callable[[], Any], repeats: int) -> float:
    fn()
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def exponent(sizes: list[float], times: list[float]) -> float:
    """k of the least-squares fit log t = k log size + c."""
    return float(np.polyfit(np.log(sizes), np.log(times), 1)[0])


def analysis_table() -> None:
    sizes = [10, 100, 1000, 10000]
    print(f"{'vertices':>9s} {'exact analysis ms':>18s} {'robust analysis ms':>19s}")
    cols: dict[str, list[float]] = {"exact": [], "robust": []}
    for n in sizes:
        doc = shapes.random_polygon(n, 1)
        repeats = 3 if n >= 10000 else 7
        for label, model in (("exact", EXACT), ("robust", ROBUST)):
            cols[label].append(median_s(lambda d=doc, m=model: analyse_document(d, m), repeats))
        print(f"{n:9d} {1000 * cols['exact'][-1]:18.2f} {1000 * cols['robust'][-1]:19.2f}")
    print(f"{'exponent':>9s} {exponent(sizes, cols['exact']):18.2f} {exponent(sizes, cols['robust']):19.2f}"
          f"   (fit over all sizes; 1,000 → 10,000: exact {exponent(sizes[2:], cols['exact'][2:]):.2f}, "
          f"robust {exponent(sizes[2:], cols['robust'][2:]):.2f})")


IDEAL = Model(exact=False, physics=replace(DEFAULT_PHYSICS.with_values(
    jaw_friction=0.0, support_friction=0.3, part_mass_kg=0.02, profile_tolerance=0.0, com_tolerance=0.0),
    placement="centred"))


def plan_table() -> None:
    models = (("exact", EXACT), ("robust", ROBUST), ("ideal cell", IDEAL))
    print(f"\n{'z (deg)':>8s}" + "".join(f" {label + ' N':>13s} {'ms':>8s}" for label, _ in models))
    rows: dict[str, tuple[list[float], list[float]]] = {label: ([], []) for label, _ in models}
    for z in (8.0, 4.0, 2.0, 1.0, 0.5):
        doc = document(fig11_outline(z_deg=z), "arc")
        line = f"{z:8.2f}"
        for label, model in models:
            n, t = _plan(doc, model)
            line += f" {n or 'refused':>13} {1000 * t:8.2f}" if n else f" {'refused':>13s} {'':8s}"
            if n:
                rows[label][0].append(n)
                rows[label][1].append(t)
        print(line)
    fits = [f"{label} {exponent(*rows[label]):.2f}" for label in rows if len(rows[label][0]) >= 2]
    print(f"exponent of planning time against N: {', '.join(fits)}")


def _plan(doc: dict[str, Any], model: Model) -> tuple[int, float]:
    a = analyse_document(doc, model)
    try:
        n = len(make_plan(a, "squeeze").steps)
    except NotOrientableError:
        return 0, 0.0
    with contextlib.suppress(NotOrientableError):
        return n, median_s(lambda: make_plan(a, "squeeze"), 5)
    return 0, 0.0


if __name__ == "__main__":
    analysis_table()
    plan_table()
