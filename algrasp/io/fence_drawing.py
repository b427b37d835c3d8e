"""Shop drawings of a fence layout (conventions §9): the belt and its fences, dimensioned,
in the part's unit, as SVG or DXF (ezdxf).

Belt frame: x along the belt's motion, y across it (y = 0 the right rail looking
downstream, y = W the left). Each fence is one line from its root on its rail to its tip;
dimensions give the belt width, every fence's root position and length, and its angle
to the belt. DXF layers: ``BELT`` (rails), ``FENCES`` (one LINE per fence, what a shop
cuts, and the last fence's curved tail as one ARC tangent to it at its tip), ``EXIT`` (the
exit guide: one LINE from the last fence's tip, or its tail's end, at its small angle to
the belt), ``DIMENSIONS`` and ``TEXT``; ``$INSUNITS`` is the part's unit where DXF has one.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any
from xml.sax.saxutils import escape

from algrasp.geometry.angles import to_deg

if TYPE_CHECKING:
    from optimisation.fence_layout import FenceLayout

INSUNITS = {"in": 1, "ft": 2, "mm": 4, "cm": 5, "m": 6, "um": 13}
"""DXF $INSUNITS codes of the part units DXF names."""


def _extent(layout: FenceLayout) -> tuple[float, float]:
    """x range of the drawing: the first root to the last tip, plus a part's width each side."""
    last = max([layout.tip(len(layout.lengths) - 1)[0]] + [x for x, _ in layout.tail_points()]
               + [x for x, _ in layout.exit_points()])
    pad = 4.0 * layout.cover_radius
    return -pad, max(last, max(layout.positions)) + pad


def _fence_lines(layout: FenceLayout) -> list[tuple[tuple[float, float], tuple[float, float]]]:
    return [(layout.root(i), layout.tip(i)) for i in range(len(layout.lengths))]


def write_dxf(layout: FenceLayout, path: str | Path) -> Path:
    """The layout as a DXF R2010 file (one LINE per fence on layer FENCES)."""
    out = Path(path)
    _dxf_document(layout).saveas(out)
    return out


def dxf_text(layout: FenceLayout) -> str:
    """The layout as DXF R2010 text (what :func:`write_dxf` writes)."""
    import io

    buf = io.StringIO()
    _dxf_document(layout).write(buf)
    return buf.getvalue()


def _dxf_document(layout: FenceLayout) -> Any:
    """The ezdxf document of the layout: rails, fences, dimensions and notes."""
    import ezdxf

    doc = ezdxf.new("R2010", setup=True)
    doc.header["$INSUNITS"] = INSUNITS.get(layout.units, 0)
    for name, color in (("BELT", 8), ("FENCES", 1), ("EXIT", 6), ("DIMENSIONS", 3), ("TEXT", 7)):
        doc.layers.add(name, color=color)
    msp = doc.modelspace()
    x0, x1 = _extent(layout)
    W = layout.belt_width
    for y in (0.0, W):
        msp.add_line((x0, y), (x1, y), dxfattribs={"layer": "BELT"})
    text_h = max(layout.cover_radius * 0.6, W / 60.0)
    for i, (a, b) in enumerate(_fence_lines(layout)):
        msp.add_line(a, b, dxfattribs={"layer": "FENCES"})
        _dimension_fence(msp, layout, i, a, b, text_h)
    arc = layout.tail_arc()
    if arc is not None and layout.tail is not None:
        (cx, cy), R, lo, hi = arc
        msp.add_arc((cx, cy), R, to_deg(lo), to_deg(hi), dxfattribs={"layer": "FENCES"})
        end = layout.tail_points(1)[-1]
        msp.add_text(f"tail R {R:.4g} {layout.units}, {to_deg(layout.tail.sweep):.2f}° (tangent to fence "
                     f"{len(layout.lengths)} at its tip)", height=text_h,
                     dxfattribs={"layer": "TEXT"}).set_placement((end[0], end[1] + (text_h if end[1] < W / 2 else -2 * text_h)))
        msp.add_radius_dim(center=(cx, cy), radius=R, angle=to_deg(0.5 * (lo + hi)), dxfattribs={"layer": "DIMENSIONS"},
                           override={"dimtxt": text_h, "dimasz": text_h}).render()
    _dxf_exit(msp, layout, text_h)
    dim = msp.add_linear_dim(base=(x0 + text_h, W / 2), p1=(x0, 0.0), p2=(x0, W), angle=90,
                             dxfattribs={"layer": "DIMENSIONS"}, override={"dimtxt": text_h, "dimasz": text_h})
    dim.render()
    msp.add_text(f"belt width {W:.4g} {layout.units}; belt moves +x", height=text_h,
                 dxfattribs={"layer": "TEXT"}).set_placement((x0, -3.0 * text_h))
    return doc


def _dxf_exit(msp: Any, layout: FenceLayout, h: float) -> None:
    """The exit guide: a LINE on layer EXIT, its aligned length and an angle note."""
    pts = layout.exit_points()
    if not pts or layout.exit is None:
        return
    a, b = pts
    msp.add_line(a, b, dxfattribs={"layer": "EXIT"})
    off = -2.0 * h if layout.exit.side == 0 else 2.0 * h
    msp.add_aligned_dim(p1=a, p2=b, distance=off, dxfattribs={"layer": "DIMENSIONS"},
                        override={"dimtxt": h, "dimasz": h}).render()
    note = (f"exit guide: {to_deg(layout.exit.steepness):.2f}° to belt (α {to_deg(layout.exit.angle):.2f}°), "
            f"L {layout.exit_length:.4g} {layout.units}")
    msp.add_text(note, height=h, dxfattribs={"layer": "TEXT"}).set_placement((a[0], a[1] + (-3.0 * h if off < 0 else 3.0 * h)))


def _dimension_fence(msp: Any, layout: FenceLayout, i: int, a: tuple[float, float], b: tuple[float, float], h: float) -> None:
    """An aligned dimension of fence i's length, its root's position and an angle note."""
    side = layout.design.sides[i]
    off = -2.0 * h if side == 0 else 2.0 * h
    msp.add_aligned_dim(p1=a, p2=b, distance=off, dxfattribs={"layer": "DIMENSIONS"},
                        override={"dimtxt": h, "dimasz": h}).render()
    y_rail = a[1] + (-3.0 * h if side == 0 else 3.0 * h)
    if a[0] > 0.0:  # the root's position along the belt, from the first fence's root
        msp.add_linear_dim(base=(0.0, y_rail), p1=(0.0, a[1]), p2=a, dxfattribs={"layer": "DIMENSIONS"},
                           override={"dimtxt": h, "dimasz": h}).render()
    beta = to_deg(layout.steepness[i])
    note = f"fence {i + 1}: {beta:.2f}° to belt (α {to_deg(layout.design.angles[i]):.2f}°, ±{to_deg(layout.design.margins[i]):.2f}°)"
    msp.add_text(note, height=h, dxfattribs={"layer": "TEXT"}).set_placement((a[0], y_rail + (-h if side == 0 else h)))


def svg_text(layout: FenceLayout) -> str:
    """The layout as an SVG document (1 user unit = 1 part unit; y up as on the belt)."""
    x0, x1 = _extent(layout)
    W = layout.belt_width
    h = max(layout.cover_radius * 0.6, W / 60.0)
    top, bottom = W + 8.0 * h, -8.0 * h
    u = escape(layout.units)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{x1 - x0:.6g}{u if u in ("mm", "cm", "in") else ""}" '
           f'height="{top - bottom:.6g}{u if u in ("mm", "cm", "in") else ""}" '
           f'viewBox="{x0:.6g} {-top:.6g} {x1 - x0:.6g} {top - bottom:.6g}">',
           f'<g transform="scale(1,-1)" stroke-width="{h / 8:.4g}" font-size="{h:.4g}">']
    for y in (0.0, W):
        out.append(f'<line class="rail" x1="{x0:.6g}" y1="{y:.6g}" x2="{x1:.6g}" y2="{y:.6g}" stroke="#888"/>')
    out.append(_svg_label(x0 + h, W / 2, f"W = {W:.4g} {u}"))
    for i, (a, b) in enumerate(_fence_lines(layout)):
        out.append(f'<line class="fence" x1="{a[0]:.6g}" y1="{a[1]:.6g}" x2="{b[0]:.6g}" y2="{b[1]:.6g}" '
                   f'stroke="#c00" stroke-width="{h / 3:.4g}"/>')
        beta = to_deg(layout.steepness[i])
        mx, my = 0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])
        out.append(_svg_label(mx, my, f"{i + 1}: L {layout.lengths[i]:.4g} {u}, {beta:.2f}°"))
        y = a[1] - 3.0 * h if a[1] == 0.0 else a[1] + 2.0 * h
        out.append(_svg_label(a[0], y, f"x = {layout.positions[i]:.4g}"))
    arc = layout.tail_arc()
    if arc is not None and layout.tail is not None:
        (cx, cy), R, lo, hi = arc
        pts = layout.tail_points(1)
        sweep_flag = 0 if layout.tail_turn() < 0 else 1  # in the group's (belt) coordinates: 1 turns from +x to +y
        out.append(f'<path class="tail" d="M {pts[0][0]:.6g} {pts[0][1]:.6g} A {R:.6g} {R:.6g} 0 0 {sweep_flag} '
                   f'{pts[-1][0]:.6g} {pts[-1][1]:.6g}" fill="none" stroke="#c00" stroke-width="{h / 3:.4g}"/>')
        out.append(_svg_label(pts[-1][0], pts[-1][1] + 2.0 * h, f"tail R {R:.4g} {u}, {to_deg(layout.tail.sweep):.2f}°"))
    if layout.exit is not None:
        (ax, ay), (bx, by) = layout.exit_points()
        out.append(f'<line class="exit" x1="{ax:.6g}" y1="{ay:.6g}" x2="{bx:.6g}" y2="{by:.6g}" '
                   f'stroke="#c0c" stroke-width="{h / 3:.4g}"/>')
        out.append(_svg_label(0.5 * (ax + bx), 0.5 * (ay + by) + (2.0 if layout.exit.side == 0 else -3.0) * h,
                              f"exit guide: L {layout.exit_length:.4g} {u}, {to_deg(layout.exit.steepness):.2f}°"))
    out.append(_svg_label(x0, -6.0 * h, f"belt moves +x; lengths in {u}"))
    out.append("</g></svg>")
    return "\n".join(out) + "\n"


def _svg_label(x: float, y: float, text: str) -> str:
    """Text at (x, y) in belt coordinates, upright despite the y flip."""
    return f'<text x="{x:.6g}" y="{-y:.6g}" transform="scale(1,-1)">{escape(text)}</text>'


def write_svg(layout: FenceLayout, path: str | Path) -> Path:
    """The layout as an SVG file."""
    out = Path(path)
    out.write_text(svg_text(layout), encoding="utf-8")
    return out


def write_drawing(layout: FenceLayout, path: str | Path) -> Path:
    """SVG or DXF by the file's suffix."""
    p = Path(path)
    if p.suffix.lower() == ".dxf":
        return write_dxf(layout, p)
    if p.suffix.lower() == ".svg":
        return write_svg(layout, p)
    from algrasp.errors import ConfigError

    raise ConfigError("drawing", f"expected a .dxf or .svg file name, got {p.name!r}")
