"""The uPlot plots zoom (wheel, drag-select, buttons), pan (Shift+drag, buttons), read
out θ and the value under the pointer, move the page's θ cursor, reset, and export PNG and
CSV (issue 35). Expected values: the API's sampled curves and the pointer's position on
the plot area, never the page's own numbers."""

from __future__ import annotations

import base64
import csv
import io
import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.service.test_workbench import browser, chromium, page, server  # noqa: F401

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(chromium() is None, reason="browser tests skipped: no Chromium found"),
]

ORANGE = (255, 204, 128)  # rgba(255, 152, 0, .5) over white: a constant region or a ramp
GREY = (226, 226, 226)  # rgba(158, 158, 158, .3) over white: a dead zone
ORANGE_ON_GREY = (240, 189, 113)  # the two together: one orange, still


def domain(pg: Any, host: str = "plot-d") -> list[float]:
    return json.loads(pg.get_attribute(f"#{host}", "data-domain"))  # type: ignore[no-any-return]


def canvas(pg: Any, host: str) -> tuple[np.ndarray, dict[str, float]]:
    """The plot's canvas as RGB on white (H×W×3) and its plot area in canvas px with the
    x range shown: {left, top, width, height, x0, x1}."""
    from PIL import Image

    got = pg.evaluate("""(host) => { const u = document.getElementById(host).plot.uplot;
        return {png: u.ctx.canvas.toDataURL('image/png'), left: u.bbox.left, top: u.bbox.top,
                width: u.bbox.width, height: u.bbox.height, x0: u.scales.x.min, x1: u.scales.x.max}; }""", host)
    rgba = Image.open(io.BytesIO(base64.b64decode(got.pop("png").split(",", 1)[1]))).convert("RGBA")
    white = Image.new("RGBA", rgba.size, (255, 255, 255, 255))
    return np.asarray(Image.alpha_composite(white, rgba).convert("RGB")).astype(int), got


def column_share(img: np.ndarray, area: dict[str, float], theta: float, colour: tuple[int, int, int]) -> float:
    """The fraction of the plot area's pixels at θ that have `colour` (±10 per channel)."""
    x = int(area["left"] + (theta - area["x0"]) / (area["x1"] - area["x0"]) * area["width"])
    col = img[int(area["top"]) + 1:int(area["top"] + area["height"]) - 1, x]
    return float((np.abs(col - colour).max(axis=1) <= 10).mean())


def over_box(pg: Any, host: str) -> dict[str, float]:
    return pg.locator(f"#{host} .u-over").bounding_box()  # type: ignore[no-any-return]


def theta_at(box: dict[str, float], dom: list[float], px: float) -> float:
    """θ under the page x coordinate px: the plot area's left edge is dom[0], its right dom[1]."""
    return dom[0] + (px - box["x"]) / box["width"] * (dom[1] - dom[0])


def test_a_plot_zooms_pans_reads_out_and_exports(page: Any) -> None:  # noqa: F811
    from PIL import Image

    with page.expect_response(lambda r: "/v1/analyses" in r.url) as resp:
        page.select_option("#example", "pie-20")
    page.wait_for_selector("#plot-d canvas")
    curves = resp.value.json()["curves"]
    assert domain(page) == [0, 180]
    box = over_box(page, "plot-d")
    cx, cy = box["x"] + box["width"] * 0.55, box["y"] + box["height"] * 0.45
    page.mouse.move(cx, cy)
    page.mouse.wheel(0, -300)  # zoom in about the pointer: θ under it stays there
    page.wait_for_function("JSON.parse(document.getElementById('plot-d').dataset.domain)[1] < 180")
    a, b = domain(page)
    assert 0 <= a < b <= 180 and b - a < 180 * 0.9
    assert theta_at(box, [a, b], cx) == pytest.approx(theta_at(box, [0, 180], cx), abs=0.5)
    # the read-out under the pointer: θ where the pointer is, and d(θ) as the API sampled it
    page.mouse.move(cx + 3, cy)
    out = page.locator("#plot-d .plot-readout")
    theta, value = float(out.get_attribute("data-x")), float(out.get_attribute("data-y"))
    assert theta == pytest.approx(theta_at(box, [a, b], cx + 3), abs=(b - a) / box["width"] * 1.5)
    assert value == pytest.approx(float(np.interp(theta, curves["theta_deg"], curves["diameter"])), rel=1e-3)
    assert out.inner_text().startswith(f"θ = {theta:.2f}°")
    # hovering moves the page's θ: the slider, and the θ cursor of another plot (r, 0–360°)
    assert page.inner_text("#theta-out") == f"{theta % 360:.1f}°"
    rbox, line = over_box(page, "plot-r"), page.locator("#plot-r .plot-theta").bounding_box()
    assert theta_at(rbox, [0, 360], line["x"] + line["width"] / 2) == pytest.approx(float(page.input_value("#theta")), abs=1.0)
    # Shift+drag to the right: the view moves left by what the pointer moved
    page.keyboard.down("Shift")
    page.mouse.move(cx, cy)
    page.mouse.down()
    page.mouse.move(cx + 40, cy, steps=4)
    page.mouse.up()
    page.keyboard.up("Shift")
    a2, b2 = domain(page)
    assert a2 == pytest.approx(a - 40 / box["width"] * (b - a), abs=0.05) and b2 - a2 == pytest.approx(b - a)
    page.get_by_role("button", name="reset zoom: diameter", exact=False).click()
    assert domain(page) == [0, 180]
    # drag-select: the view becomes the θ range selected
    x1, x2 = box["x"] + box["width"] * 0.25, box["x"] + box["width"] * 0.75
    page.mouse.move(x1, cy)
    page.mouse.down()
    page.mouse.move(x2, cy, steps=5)
    page.mouse.up()
    a3, b3 = domain(page)
    px = 180 / box["width"]
    assert a3 == pytest.approx(theta_at(box, [0, 180], x1), abs=2 * px)
    assert b3 == pytest.approx(theta_at(box, [0, 180], x2), abs=2 * px)
    page.mouse.dblclick(cx, cy)  # a double click shows the whole period again
    assert domain(page) == [0, 180]
    page.get_by_role("button", name="zoom in: diameter", exact=False).click()
    assert domain(page) == [45, 135]
    with page.expect_download() as dl:
        page.get_by_role("button", name="export CSV: diameter", exact=False).click()
    rows = list(csv.DictReader(io.StringIO(Path(dl.value.path()).read_text())))
    n = round(len(curves["theta_deg"]) * 180 / 360)
    assert len(rows) == n + 1 and float(rows[7]["y"]) == pytest.approx(curves["diameter"][7])
    assert float(rows[n]["x"]) == pytest.approx(curves["theta_deg"][n])
    page.get_by_role("button", name="reset zoom: diameter", exact=False).click()
    with page.expect_download() as dl:
        page.get_by_role("button", name="export PNG: diameter", exact=False).click()
    img = np.asarray(Image.open(dl.value.path()).convert("RGB")).astype(int)
    assert img.shape[1] >= 2 * box["width"]  # at least 2 px per CSS px
    assert (img.max(axis=2) < 100).any() and (img.min(axis=2) > 250).any()  # drawn lines on white
    # the constant region [160°, 200°) in orange at both ends of the exported picture
    orange = (np.abs(img - ORANGE).max(axis=2) <= 10) | (np.abs(img - ORANGE_ON_GREY).max(axis=2) <= 10)
    cols = np.nonzero(orange.sum(axis=0) > 50)[0]
    assert cols.size and cols.max() - cols.min() > 0.8 * img.shape[1]


def test_a_jump_is_a_gap_not_a_vertical_line(page: Any) -> None:  # noqa: F811
    """Γ of the pie jumps at its step boundaries (20°, 90°, 160° in the exact model): the
    plot draws nothing between the two levels there."""
    with page.expect_response(lambda r: "/v1/analyses" in r.url) as resp:
        page.check("#exact")
        page.select_option("#example", "pie-20")
    page.wait_for_selector("#plot-squeeze canvas")
    steps = resp.value.json()["squeeze"]["steps"]
    img, area = canvas(page, "plot-squeeze")
    line = (np.abs(img - (21, 101, 192)).max(axis=2) <= 60)  # the accent line, antialiased
    for s in steps:
        theta = s["start_deg"] % 180
        if not 1 < theta < 179:
            continue
        x = int(area["left"] + theta / 180 * area["width"])
        rows = np.nonzero(line[int(area["top"]):int(area["top"] + area["height"]), x - 5:x + 6].any(axis=1))[0]
        assert rows.size and np.diff(rows).max() > 10, f"a vertical line at θ = {theta:.2f}°"
