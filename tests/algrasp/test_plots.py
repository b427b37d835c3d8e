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


PIE = Path(__file__).resolve().parents[2] / "algrasp" / "examples" / "pie-20.json"


def _panels(action: str, exact: bool = False) -> tuple[object, object, object, object]:
    """The function and transfer panels of the pie's figure, drawn (Agg) for reading back."""
    import json

    import matplotlib.pyplot as plt

    from algrasp.plots import _function_panel, _transfer_panel

    a = analyse(json.loads(PIE.read_text()), exact=exact)
    p = plan(a, action=action)
    fig = plt.figure(figsize=(6, 8))
    f_ax, t_ax = fig.add_subplot(2, 1, 1), fig.add_subplot(2, 1, 2)
    _function_panel(f_ax, a, p)
    _transfer_panel(t_ax, p)
    fig.canvas.draw()
    return fig, f_ax, t_ax, p


def _pixel(fig: object, ax: object, x: float, y_frac: float) -> tuple[int, int, int]:
    """The rendered colour at data x and a fraction of the axes' height."""
    import matplotlib.transforms as mt

    px, py = mt.blended_transform_factory(ax.transData, ax.transAxes).transform((x, y_frac))  # type: ignore[attr-defined]
    rgba = np.asarray(fig.canvas.buffer_rgba())  # type: ignore[attr-defined]
    r, g, b, _ = rgba[rgba.shape[0] - int(round(py)), int(round(px))]
    return int(r), int(g), int(b)


def test_constant_region_wraps_and_renders_orange() -> None:
    """The pie's d is constant on [160°, 200°) (conventions §6: the squeeze's 40° ramp): on
    the 0–180° axis that is 160–180° and 0–20°, both orange (not grey-brown), and its dead
    zone covers both ends too."""
    import matplotlib.pyplot as plt

    fig, f_ax, _, p = _panels("squeeze")
    try:
        for x in (10.0, 170.0):  # inside both pieces of the wrapped constant region
            r, g, b = _pixel(fig, f_ax, x, 0.03)
            assert r > 220 and 140 < g < 210 and b < 120, (x, (r, g, b))  # orange, not brown or grey
        r, g, b = _pixel(fig, f_ax, 45.0, 0.03)  # outside: white
        assert min(r, g, b) > 240
        # every dead zone is drawn in all its pieces on [0, 180]
        P = 180.0  # d's period
        grey = [patch for patch in f_ax.patches if patch.get_facecolor()[:3] == pytest.approx((158 / 255,) * 3, abs=0.01)]
        inv = f_ax.transData.inverted()
        drawn = sorted((round(inv.transform(pt.get_window_extent().p0)[0], 3), round(inv.transform(pt.get_window_extent().p1)[0], 3))
                       for pt in grey)
        want = []
        for a, b in p.bounds.rest_zones:  # type: ignore[union-attr]
            lo, hi = math.degrees(a), math.degrees(b)
            for k in range(-2, 3):
                s, e = max(lo + k * P, 0.0), min(hi + k * P, P)
                if e - s > 1e-6:
                    want.append((round(s, 3), round(e, 3)))
        want = sorted(set(want))
        assert len(drawn) == len(want)
        assert [x for d in drawn for x in d] == pytest.approx([x for w in want for x in w], abs=0.05)
        assert any(s == pytest.approx(0.0, abs=0.05) for s, _ in drawn) and any(e == pytest.approx(P, abs=0.05) for _, e in drawn)
    finally:
        plt.close(fig)


def test_intervals_are_labelled_rows_and_wrap() -> None:
    """Each Θᵢ is one bar row of its own, labelled Θᵢ; an interval past the period is drawn in
    two pieces on the same row, together as long as the interval."""
    import matplotlib.pyplot as plt

    fig, _, t_ax, p = _panels("push_grasp", exact=True)
    try:
        labels = {t.get_text(): t.get_position()[1] for t in t_ax.texts}
        assert [f"Θ{i + 1}" for i in range(len(p.intervals))] == sorted(labels, key=lambda s: int(s[1:]))
        assert len(set(labels.values())) == len(labels)  # one row each
        bars = [ln for ln in t_ax.lines if ln.get_color() == "tab:purple"]
        span = 360.0
        for i, (a, b) in enumerate(p.intervals):
            row = [ln for ln in bars if ln.get_ydata()[0] == labels[f"Θ{i + 1}"]]
            widths = [float(np.diff(ln.get_xdata())[0]) for ln in row]
            assert sum(widths) == pytest.approx(math.degrees(b - a), abs=1e-6)
            assert all(0.0 <= x <= span + 1e-9 for ln in row for x in ln.get_xdata())
        assert t_ax.get_xlim() == pytest.approx((0.0, span))
    finally:
        plt.close(fig)
