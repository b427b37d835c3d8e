"""The compiled kernels (algrasp.planning._kernels) against the numpy path they reproduce
(issue 34: the default robust model's triangle work unit, analysis + squeeze plan +
push-grasp plan, toward ≤ 1 ms).

Records one work unit's own calls of each ported function, then times them replayed,
compiled and with the hooks switched off (the numpy path), CPU medians per work unit;
then the whole work unit both ways (the hooks switched off in-process, so the two runs
share one interpreter). Prints figures; needs the kernels built (``make``).
"""

from __future__ import annotations

import contextlib
import statistics
import time
from collections.abc import Callable
from typing import Any

from algrasp.errors import NotOrientableError
from algrasp.pipeline import WARM_UP_PART
from algrasp.planning import edges, placement, planner, plans, setcells, setvalued, transfer
from algrasp.planning.analysis import analyse_document
from algrasp.planning.plans import make_plan
from algrasp.planning.setcells import Cells

HOOKED: tuple[Any, ...] = (edges, placement, planner, setvalued, setcells, transfer)
sv: Any = setvalued  # patched and replayed below (its imported names too)
pl: Any = plans
TF: Any = transfer.TransferFunction


def work() -> None:
    a = analyse_document(WARM_UP_PART)
    for action in ("squeeze", "push_grasp"):
        with contextlib.suppress(NotOrientableError):  # a refused plan costs its search too
            make_plan(a, action, limits="none")


def record() -> dict[str, list[tuple[Any, ...]]]:
    """The arguments of every call of the ported functions in one work unit."""
    calls: dict[str, list[tuple[Any, ...]]] = {"classify": [], "bounds": [], "compose_after": [], "crossings": [],
                                               "set_a_prime": [], "rest_zones": [], "lookups": [], "pointwise": []}
    orig = sv._classify, sv.bounds, TF.compose_after, sv.crossings
    more = pl.set_a_prime, sv.rest_zones, TF.apply_on_ramp, TF.steps_floats, placement.pointwise

    def pointwise(*a: Any) -> Any:
        calls["pointwise"].append(a)
        return more[4](*a)

    def a_prime(*a: Any, **kw: Any) -> Any:
        calls["set_a_prime"].append((a, {k: v for k, v in kw.items() if k != "lifted"}))
        return more[0](*a, **kw)

    def zones(*a: Any) -> Any:
        calls["rest_zones"].append(a)
        return more[1](*a)

    def on_ramp(F: Any, thetas: Any) -> Any:
        calls["lookups"].append((F, thetas, True))
        return more[2](F, thetas)

    def steps(F: Any, thetas: Any) -> Any:
        calls["lookups"].append((F, list(thetas), False))
        return more[3](F, thetas)

    pl.set_a_prime, sv.rest_zones, TF.apply_on_ramp, TF.steps_floats = a_prime, zones, on_ramp, steps
    placement.pointwise = pointwise

    def classify(*a: Any, first: bool = False) -> Any:
        calls["classify"].append((*a, first))
        return orig[0](*a, first=first)

    def bounds(*a: Any) -> Any:
        calls["bounds"].append(a)
        return orig[1](*a)

    def compose(*a: Any) -> Any:
        calls["compose_after"].append(a)
        return orig[2](*a)

    def crossings(*a: Any, **kw: Any) -> Any:
        calls["crossings"].append((a, kw))
        return orig[3](*a, **kw)

    sv._classify, sv.bounds, TF.compose_after, sv.crossings = classify, bounds, compose, crossings
    try:
        work()
    finally:
        sv._classify, sv.bounds, TF.compose_after, sv.crossings = orig
        pl.set_a_prime, sv.rest_zones, TF.apply_on_ramp, TF.steps_floats, placement.pointwise = more
    return calls


def median_ms(fn: Callable[[], object], reps: int) -> float:
    for _ in range(reps // 10):
        fn()
    times = []
    for _ in range(reps):
        t = time.process_time()
        fn()
        times.append(time.process_time() - t)
    return 1e3 * statistics.median(times)


def replays(calls: dict[str, list[tuple[Any, ...]]]) -> dict[str, Callable[[], None]]:
    def classify() -> None:
        for a in calls["classify"]:
            sv._classify(*a[:-1], first=a[-1])

    def bounds() -> None:
        for c, *rest in calls["bounds"]:  # fresh cells: their runs are not cached
            sv.bounds(Cells(c.x, c.T, c.right, c.left, c.rest, c.barrier_right, c.barrier_left), *rest)

    def compose() -> None:
        for outer, *rest in calls["compose_after"]:
            outer.compose_after(*rest)

    def crossings() -> None:
        for a, kw in calls["crossings"]:
            sv.crossings(*a, **kw)

    def a_prime() -> None:  # fresh copies: lifted pieces, keys, _fixed, _widest, sink widths
        for (lo, up, *rest), kw in calls["set_a_prime"]:
            with contextlib.suppress(NotOrientableError):
                planner.set_a_prime(TF(lo.period, lo.pieces), TF(up.period, up.pieces), *rest, **kw)

    def pointwise() -> None:
        for a in calls["pointwise"]:
            placement.pointwise(*a)

    def zones() -> None:
        for a in calls["rest_zones"]:
            setcells.rest_zones(*a)

    def lookups() -> None:  # apply_on_ramp and steps_floats
        for F, thetas, vectorised in calls["lookups"]:
            F.apply_on_ramp(thetas) if vectorised else F.steps_floats(thetas)

    return {"classify": classify, "bounds": bounds, "compose_after": compose, "crossings": crossings,
            "set_a_prime": a_prime, "pointwise": pointwise, "rest_zones": zones, "lookups": lookups, "work unit": work}


def main() -> None:
    kernels = sv.KERNELS
    if kernels is None:
        print("compiled kernels not built (or ALGRASP_PURE set): nothing to compare")
        return
    calls = record()
    print("calls per work unit: " + ", ".join(f"{k} {len(v)}" for k, v in calls.items()))
    runs = replays(calls)
    print(f"{'ms per work unit':<18}{'compiled':>10}{'numpy':>10}{'saved':>8}")
    for name, fn in runs.items():
        reps = 300 if name == "work unit" else 2000
        fast = median_ms(fn, reps)
        for m in HOOKED:
            m.KERNELS = None
        try:
            slow = median_ms(fn, reps)
        finally:
            for m in HOOKED:
                m.KERNELS = kernels
        print(f"{name:<18}{fast:>10.4f}{slow:>10.4f}{1 - fast / slow:>8.0%}")


if __name__ == "__main__":
    main()
