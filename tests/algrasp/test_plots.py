"""Figures (issue 20's list of defects): labelled axes with units, the θ₀ shift said on
both axes, a legend for the Θ bars, holes drawn, and jaws that touch the part."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from algrasp import analyse, plan
from algrasp.plots import jaw_offsets, plan_figure

PLATE = {"name": "plate", "units": "mm", "boundary": [[0, 0], [40, 0], [40, 20], [10, 30], [0, 20]],
         "holes": [[[8, 8], [14, 8], [14, 14], [8, 14]]]}


@pytest.mark.parametrize("alpha_deg", [0.0, 30.0, 90.0, 135.0])
def test_jaws_touch_the_part(alpha_deg: float) -> None:
    """A 4 × 2 rectangle about its centre: the jaws closing along n sit at ± its half
    extent along n, |n_x|·2 + |n_y|·1 (computed by hand)."""
    pts = np.array([[-2.0, -1.0], [2.0, -1.0], [2.0, 1.0], [-2.0, 1.0]])
    a = math.radians(alpha_deg)
    half = abs(math.sin(a)) * 2.0 + abs(math.cos(a)) * 1.0
    lo, hi = jaw_offsets(pts, a)
    assert lo == pytest.approx(-half) and hi == pytest.approx(half)


def test_figure_labels_legend_and_holes(tmp_path: Path) -> None:
    a = analyse(PLATE, exact=True)
    p = plan(a, action="squeeze")
    svg = plan_figure(a, p, tmp_path / "f.svg").read_text()
    for text in ("d(θ) (mm)", "θ − θ₀", "F(θ) − θ₀", "intervals Θᵢ of A′", "part orientation relative to the gripper"):
        assert text in svg, text
    rows = min(len(p.steps), 8) + 1
    assert svg.count("fill: #ffffff") >= 4 * rows  # one hole in each of the 4 × rows trace panels
