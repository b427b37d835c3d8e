"""The plots zoom (wheel, buttons), pan (drag), read out θ and the value under the pointer,
reset, and export PNG and CSV (issue 35). Expected values: the API's sampled curves."""

from __future__ import annotations

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


def domain(pg: Any) -> list[float]:
    return json.loads(pg.get_attribute("#plot-d svg.plot", "data-domain"))  # type: ignore[no-any-return]


def test_a_plot_zooms_pans_reads_out_and_exports(page: Any) -> None:  # noqa: F811
    from PIL import Image

    with page.expect_response(lambda r: "/v1/analyses" in r.url) as resp:
        page.select_option("#example", "pie-20")
    page.wait_for_selector("#plot-d svg")
    curves = resp.value.json()["curves"]
    assert domain(page) == [0, 180]
    box = page.locator("#plot-d svg.plot").bounding_box()
    cx, cy = box["x"] + box["width"] * 0.55, box["y"] + box["height"] * 0.45
    page.mouse.move(cx, cy)
    page.mouse.wheel(0, -300)  # zoom in about the pointer
    page.wait_for_function("JSON.parse(document.querySelector('#plot-d svg.plot').dataset.domain)[1] < 180")
    a, b = domain(page)
    assert 0 <= a < b <= 180 and b - a < 180 * 0.9
    # the read-out under the pointer: θ, and d(θ) as the API sampled it
    page.mouse.move(cx + 3, cy)
    out = page.locator("#plot-d .plot-readout")
    theta, value = float(out.get_attribute("data-x")), float(out.get_attribute("data-y"))
    assert a <= theta <= b
    assert value == pytest.approx(float(np.interp(theta, curves["theta_deg"], curves["diameter"])), rel=1e-3)
    assert out.inner_text().startswith(f"θ = {theta:.2f}°")
    # drag to the right: the view moves left by the same width
    page.mouse.move(cx, cy)
    page.mouse.down()
    page.mouse.move(cx + 40, cy, steps=4)
    page.mouse.up()
    a2, b2 = domain(page)
    assert a2 < a and b2 - a2 == pytest.approx(b - a)
    page.get_by_role("button", name="reset zoom: diameter", exact=False).click()
    assert domain(page) == [0, 180]
    page.get_by_role("button", name="zoom in: diameter", exact=False).click()
    assert domain(page) == [45, 135]
    with page.expect_download() as dl:
        page.get_by_role("button", name="export CSV: diameter", exact=False).click()
    rows = list(csv.DictReader(io.StringIO(Path(dl.value.path()).read_text())))
    n = round(len(curves["theta_deg"]) * 180 / 360)
    assert len(rows) == n + 1 and float(rows[7]["y"]) == pytest.approx(curves["diameter"][7])
    with page.expect_download() as dl:
        page.get_by_role("button", name="export PNG: diameter", exact=False).click()
    img = np.asarray(Image.open(dl.value.path()).convert("RGB"))
    assert img.shape[1] >= 1000 and (img < 100).any() and (img > 200).any()  # drawn lines on white
