"""Figures of an analysis and a plan (matplotlib adapter; the core never imports it).

``plan_figure`` draws what an engineer wants to see: the diameter (or radius)
function with its extrema (axes labelled, in the part's unit), the transfer function
with the intervals Θᵢ as bars below it (both axes shifted by θ₀ and labelled so; a
legend says what the bars are), and traces of the plan for four initial orientations
with holes drawn and the jaws where they grip the part (Figs. 2, 7, 16, 17).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only: no display needed
matplotlib.rcParams["svg.fonttype"] = "none"  # text stays text in SVG: smaller, searchable, selectable

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.transforms import blended_transform_factory  # noqa: E402

from algrasp.errors import ConfigError  # noqa: E402
from algrasp.geometry.angles import to_deg, to_rad  # noqa: E402
from algrasp.geometry.curves import FloatArray  # noqa: E402
from algrasp.geometry.segments import loop_polyline  # noqa: E402
from algrasp.geometry.tolerances import ROUNDING  # noqa: E402
from algrasp.planning.analysis import Analysis  # noqa: E402
from algrasp.planning.plans import Plan  # noqa: E402

MAX_TRACE_ROWS = 8


def _outline(analysis: Analysis) -> list[FloatArray]:
    """Closed polylines of the boundary, then of each hole, about the centre of mass."""
    com = np.asarray(analysis.part.center_of_mass)
    loops = []
    for loop in (analysis.part.boundary, *analysis.part.holes):
        pts, _ = loop_polyline(loop, to_rad(3.0))
        loops.append(np.vstack([pts, pts[:1]]) - com)
    return loops


def jaw_offsets(points: FloatArray, alpha: float) -> tuple[float, float]:
    """Where two jaws closed along n = (−sin α, cos α) on ``points`` (n, 2) touch them:
    the least and greatest projections on n (the part's support in both directions)."""
    proj = points @ np.array([-np.sin(alpha), np.cos(alpha)])
    return float(proj.min()), float(proj.max())


def wrapped_spans(a: float, b: float, period: float) -> list[tuple[float, float]]:
    """The pieces of [a, b] inside [0, period] on a periodic axis: the interval and its
    copies shifted by whole periods, so a region crossing 0 or the period is two pieces."""
    if b - a >= period:
        return [(0.0, period)]
    out = []
    for k in range(int(np.floor(-b / period)), int(np.ceil((period - a) / period)) + 1):
        lo, hi = max(a + k * period, 0.0), min(b + k * period, period)
        if hi - lo > ROUNDING:
            out.append((lo, hi))
    return out


CONSTANT = "#ffb74d"  # orange 300, opaque: drawn over the translucent grey it stays orange
DEAD = "#9e9e9e"


def _function_panel(ax: Axes, analysis: Analysis, plan: Plan) -> None:
    f = analysis.diameter if plan.action == "squeeze" else analysis.radius
    P = f.period
    theta = np.linspace(0.0, P, 1441)
    ax.plot(to_deg(theta), f.values(theta), color="black", lw=1.2, zorder=3)
    for e in f.extrema:
        ax.plot(to_deg(e.theta % P), e.value, "v" if e.kind == "min" else "^",
                color="tab:green" if e.kind == "min" else "tab:red", ms=5, zorder=4)
    dead = "" if plan.bounds is None else "; grey: dead zones |f′| ≤ κ"
    if plan.bounds is not None:
        for a, b in plan.bounds.rest_zones:
            for lo, hi in wrapped_spans(a, b, P):  # zones may wrap past 0 or the period
                ax.axvspan(to_deg(lo), to_deg(hi), color=DEAD, alpha=0.3, lw=0, zorder=1)
    for a, b in f.constant_intervals:
        for lo, hi in wrapped_spans(a, b, P):
            ax.axvspan(to_deg(lo), to_deg(hi), color=CONSTANT, lw=0, zorder=2)
    ax.set_title(f"{'diameter d' if plan.action == 'squeeze' else 'radius r'}(θ) with extrema "
                 f"(▲ max, ▼ min; orange: constant{dead})", fontsize=9)
    name = "d" if plan.action == "squeeze" else "r"
    ax.set_xlabel("θ, part orientation relative to the gripper (deg)")
    ax.set_ylabel(f"{name}(θ) ({analysis.part.units})")
    ax.set_xlim(0, to_deg(P))


def _transfer_panel(ax: Axes, plan: Plan) -> None:
    F = plan.transfer if plan.bounds is None else plan.bounds.lower
    base = F.pieces[0].start
    if plan.bounds is None:
        for p in F.pieces:
            x = to_deg([p.start - base, p.end - base])
            y = to_deg([p.start, p.end]) if p.value is None else to_deg([p.value, p.value])
            ax.plot(x, y - to_deg(base), color="tab:blue" if p.value is not None else "tab:orange", lw=1.5)
            if p.value is None:  # a ramp: shaded over its whole width, wrapped
                for a, b in wrapped_spans(p.start - base, p.end - base, F.period):
                    ax.axvspan(to_deg(a), to_deg(b), color=CONSTANT, alpha=0.35, lw=0)
    else:  # the set-valued images [lower(θ), upper(θ)] (conventions §7)
        theta = base + np.linspace(0.0, F.period, 2881)
        lo, hi = plan.bounds.image(theta, theta)
        x = to_deg(theta - base)
        ax.fill_between(x, to_deg(lo - base), to_deg(hi - base), color="tab:green", alpha=0.35, lw=0,
                        label="image F_κ(θ) = [lower, upper]")
        ax.plot(x, to_deg(lo - base), color="tab:blue", lw=1.0)
        ax.plot(x, to_deg(hi - base), color="tab:blue", lw=1.0, ls="--")
    span = to_deg(F.period)
    n = len(plan.intervals)
    rows = list(range(n)) if n <= 12 else [*range(6), *range(n - 6, n)]
    label_at = blended_transform_factory(ax.transAxes, ax.transData)
    for row, i in enumerate(rows):  # one row per Θᵢ, labelled; a bar past the period wraps to 0
        a, b = plan.intervals[i]
        y_bar = -span * (0.07 + 0.07 * row)  # rows apart by more than a label's height
        start = (a - base) % F.period
        for k, (x0, x1) in enumerate(wrapped_spans(start, start + (b - a), F.period)):
            ax.plot(to_deg([x0, x1]), [y_bar, y_bar], color="tab:purple", lw=3, solid_capstyle="butt",
                    label="intervals Θᵢ of A′ (below 0; top bar Θ₁)" if row == 0 and k == 0 else None)
        ax.text(1.005, y_bar, f"Θ{i + 1}", transform=label_at, ha="left", va="center", fontsize=7)
    ax.axhline(0.0, color="gray", lw=0.5)
    ax.legend(loc="upper left", fontsize=7)
    ax.set_xlim(0, span)
    theta0 = f"{to_deg(base):.1f}°"
    ax.set_title(f"transfer function ({plan.action}), both axes shifted by θ₀ = {theta0}", fontsize=9)
    ax.set_xlabel(f"θ − θ₀, orientation before the action (deg; θ₀ = {theta0})")
    ax.set_ylabel("F(θ) − θ₀, after the action (deg)")


def _trace_panel(fig: plt.Figure, grid: object, analysis: Analysis, plan: Plan) -> None:
    loops = _outline(analysis)
    outline = loops[0]
    extent = float(np.max(np.hypot(*outline.T))) * 1.25
    starts = to_rad([17.0, 103.0, 197.0, 283.0])
    steps = list(range(len(plan.steps)))
    if len(steps) > MAX_TRACE_ROWS:
        steps = steps[: MAX_TRACE_ROWS // 2] + steps[-MAX_TRACE_ROWS // 2:]
    rows = len(steps) + 1
    sub = grid.subgridspec(rows, 4, hspace=0.05, wspace=0.05)  # type: ignore[attr-defined]
    for col, phi0 in enumerate(starts):
        trace = plan.trace(float(phi0))
        for r in range(rows):
            ax = fig.add_subplot(sub[r, col])
            phi = trace[0] if r == 0 else trace[steps[r - 1] + 1]
            c, s = np.cos(phi), np.sin(phi)
            turned = [lp @ np.array([[c, s], [-s, c]]) for lp in loops]
            pts = turned[0]
            ax.fill(pts[:, 0], pts[:, 1], color="lightsteelblue", ec="black", lw=0.6)
            for hole in turned[1:]:
                ax.fill(hole[:, 0], hole[:, 1], color="white", ec="black", lw=0.5)
            ax.plot([0, 0.5 * extent * c], [0, 0.5 * extent * s], color="crimson", lw=0.8)  # registration mark
            if r > 0:
                alpha = plan.steps[steps[r - 1]].gripper_angle
                d = np.array([np.cos(alpha), np.sin(alpha)])
                n = np.array([-d[1], d[0]])
                for offset in jaw_offsets(pts, alpha):  # the jaws where they grip the part
                    q = offset * n
                    ax.plot([q[0] - extent * d[0], q[0] + extent * d[0]], [q[1] - extent * d[1], q[1] + extent * d[1]],
                            color="dimgray", lw=1.6)
            if r == rows - 1 and plan.final_uncertainty > 0.0:
                _uncertainty_wedge(ax, phi, plan.final_uncertainty, 0.5 * extent)
            ax.set_xlim(-extent, extent)
            ax.set_ylim(-extent, extent)
            ax.set_aspect("equal")
            ax.axis("off")
            if col == 0:
                ax.text(-extent, extent * 0.8, "start" if r == 0 else f"{steps[r - 1] + 1}", fontsize=7)


def _uncertainty_wedge(ax: Axes, phi: float, half_width: float, radius: float) -> None:
    """The guaranteed final interval φ ± u around the registration mark."""
    t = np.linspace(phi - half_width, phi + half_width, 30)
    ax.fill(np.r_[0.0, radius * np.cos(t)], np.r_[0.0, radius * np.sin(t)], color="crimson", alpha=0.25, lw=0)


def plan_figure(analysis: Analysis, plan: Plan, path: str | Path) -> Path:
    """Write the figure to ``path`` (.svg or .png). Returns the path."""
    out = Path(path)
    if out.suffix.lower() not in (".svg", ".png"):
        raise ConfigError("figure", f"unsupported format {out.suffix!r} (use .svg or .png)")
    fig = plt.figure(figsize=(11, 8.5))
    grid = fig.add_gridspec(2, 2, width_ratios=[1.1, 1], height_ratios=[1, 1], hspace=0.32)
    _function_panel(fig.add_subplot(grid[0, 0]), analysis, plan)
    _transfer_panel(fig.add_subplot(grid[1, 0]), plan)
    _trace_panel(fig, grid[:, 1], analysis, plan)
    u = "" if plan.bounds is None else f" ± {to_deg(plan.final_uncertainty):.3g}° (robust model)"
    fig.suptitle(f"{analysis.part.name}: {len(plan.steps)}-step {plan.action} plan, "
                 f"{len(plan.final_orientations)} final orientation(s){u}", fontsize=11)
    try:
        fig.savefig(out, dpi=110)
    except OSError as exc:
        raise ConfigError("figure", f"cannot write {out}: {exc.strerror}") from None
    finally:
        plt.close(fig)
    return out
