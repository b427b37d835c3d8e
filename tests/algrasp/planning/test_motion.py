"""The plan document's images (``algrasp.planning.motion``): each step's ``image_deg``
holds where the plan's own run puts the part after that action, from every start, and the
last step's arcs lie within the claimed final orientations' uncertainty."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from algrasp import plan
from algrasp.planning.motion import motion

EXAMPLES = Path(__file__).resolve().parents[3] / "algrasp" / "examples"


def inside(lo: float, hi: float, arcs: tuple[tuple[float, float], ...], tol: float = 1e-7) -> bool:
    start = lo % (2 * math.pi)
    return any(a - tol <= s and s + (hi - lo) <= b + tol for a, b in arcs for s in (start, start + 2 * math.pi, start - 2 * math.pi))


@pytest.mark.parametrize(("name", "action", "exact"), [("pie-20", "squeeze", True), ("pie-20", "push_grasp", True),
                                                       ("bracket", "push_grasp", False)])
def test_every_start_stays_within_each_steps_image(name: str, action: str, exact: bool) -> None:
    p = plan(json.loads((EXAMPLES / f"{name}.json").read_text()), action=action, exact=exact)
    m = motion(p)
    assert len(m.after) == len(p.steps)
    starts = np.linspace(0.0, 2 * math.pi, 721)[:-1]
    for k in range(1, len(p.steps) + 1):
        if p.bounds is None:
            from algrasp.planning.verification import through as _through

            lo = hi = _through(p.transfer, p.steps[:k], starts)
        else:
            lo, hi = p.run_set(starts, starts, k)
        assert all(inside(a, b, m.after[k - 1]) for a, b in zip(lo, hi)), f"step {k}"
    tol = p.final_uncertainty + 1e-7
    for a, b in m.after[-1]:
        assert any(abs((a - f + math.pi) % (2 * math.pi) - math.pi) <= tol and
                   abs((b - f + math.pi) % (2 * math.pi) - math.pi) <= tol for f in p.final_orientations)
