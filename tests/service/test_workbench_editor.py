"""The part editor's arcs, holes, centre of mass and numeric entry; the API's validation
errors marked on the drawing where the field it names is; the gallery of example parts
(the paper's and real drawings') (issue 35). Expected values: closed-form areas and the
public API's analysis."""

from __future__ import annotations

import json
import math
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.service.test_workbench import browser, chromium, open_page, page, plan_in_page, server  # noqa: F401

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(chromium() is None, reason="browser tests skipped: no Chromium found"),
]


@pytest.fixture()
def refused_page(browser: Any, server: Any) -> Iterator[Any]:  # noqa: F811
    """A page whose only console errors may be Chromium's note of the 422 the test provokes."""
    yield from open_page(browser, server, allowed="status of 422")


def canvas(pg: Any) -> Any:
    pg.click("#editor-open")
    box = pg.locator("#editor-canvas").bounding_box()

    def click(x: float, y: float) -> None:  # mm → screen (y up, 0..60 mm)
        pg.mouse.click(box["x"] + x / 60 * box["width"], box["y"] + (60 - y) / 60 * box["height"])

    return click


def enter(pg: Any, label: str, value: float) -> None:
    field = pg.get_by_label(label, exact=True)
    field.fill(str(value))
    field.dispatch_event("change")


def test_an_arc_a_hole_and_a_centre_of_mass_are_drawn_saved_and_analysed(page: Any) -> None:  # noqa: F811
    click = canvas(page)
    for x, y in [(10, 10), (40, 10), (40, 30), (10, 30)]:
        click(x, y)
    enter(page, "vertex 2 bulge of the edge to the next vertex", 1.0)  # a half circle of radius 10 outwards
    page.click("#editor-hole")
    for x, y in [(20, 15), (25, 15), (25, 20)]:
        click(x, y)
    enter(page, "hole 1 vertex 3 y (mm)", 25.0)  # numeric entry moves the hole's third vertex
    page.check("#editor-com-mode")
    click(30, 20)
    area = 30 * 20 + math.pi * 10**2 / 2 - 0.5 * 5 * 10
    with page.expect_download() as dl:
        page.click("#editor-save")
    doc = json.loads(Path(dl.value.path()).read_text())
    arc = doc["boundary"][1]
    assert arc["type"] == "arc" and arc["radius"] == pytest.approx(10.0) and arc["center"] == pytest.approx([40.0, 20.0])
    assert abs(arc["end_deg"] - arc["start_deg"]) == pytest.approx(180.0)
    assert doc["holes"] == [[[20.0, 15.0], [25.0, 15.0], [25.0, 25.0]]]
    assert doc["center_of_mass"] == [30.0, 20.0]
    with page.expect_response(lambda r: "/v1/analyses" in r.url) as resp:
        page.click("#editor-use")
    page.wait_for_selector("#plot-d canvas")
    part = resp.value.json()["part"]
    assert part["area"] == pytest.approx(area, rel=1e-6)  # the API's exact arc area
    assert part["center_of_mass"] == pytest.approx([30.0, 20.0])
    plan = plan_in_page(page, "squeeze", "exact")
    assert len(plan["steps"]) >= 1


def test_the_apis_validation_errors_are_marked_on_the_drawing(refused_page: Any) -> None:
    pg = refused_page
    click = canvas(pg)
    for x, y in [(10, 10), (40, 10), (40, 30), (10, 30)]:
        click(x, y)
    enter(pg, "vertex 3 x (mm)", 40.0)
    enter(pg, "vertex 3 y (mm)", 10.0)  # vertex 3 on vertex 2: edge 1 has no length
    pg.click("#editor-use")
    mark = pg.wait_for_selector("#editor-canvas [data-error-field^='polygon[1]']", state="attached")
    assert mark.get_attribute("class") == "editor-error"
    assert "polygon[1]" in pg.inner_text("#editor-error") and "zero-length" in pg.inner_text("#editor-error")
    enter(pg, "vertex 3 y (mm)", 30.0)  # fixed: the mark goes
    assert pg.locator("#editor-canvas [data-error-field]").count() == 0
    pg.check("#editor-com-mode")
    click(58, 58)  # outside the part's hull
    pg.click("#editor-use")
    pg.wait_for_selector("#editor-canvas circle.editor-com[data-error-field=center_of_mass]", state="attached")
    assert "center_of_mass" in pg.inner_text("#editor-error")


def test_the_gallery_holds_the_papers_parts_and_real_drawings(page: Any, server: Any) -> None:  # noqa: F811
    with server.client() as c:
        examples = c.get("/v1/examples").json()["examples"]
    real = [e for e in examples if e["kind"] == "real"]
    assert {e["name"] for e in examples if e["kind"] == "paper"} >= {"pie-20", "bracket"} and len(real) >= 2
    assert all(e["part"]["source"]["licence"] for e in real)  # each says its licence
    assert page.locator("#gallery .thumb").count() == len(examples)
    with page.expect_response(lambda r: "/v1/analyses" in r.url) as resp:
        page.click("#gallery .thumb[data-example=gear-12]")
    page.wait_for_selector("#gallery .thumb[data-example=gear-12][aria-pressed=true]")
    assert resp.value.ok and page.input_value("#example") == "gear-12"
    assert "CC0" in (page.get_attribute("#gallery .thumb[data-example=gear-12]", "title") or "")
