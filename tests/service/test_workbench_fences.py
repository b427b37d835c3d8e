"""The workbench's Fences page in headless Chromium (issue 36): the design shown is the
API's (table and drawing), the animation ends where the design's own push composition in
Python puts the part, the downloaded DXF re-imports to the table's fences, bad options are
said by field, and a belt validation in Drake shows what was validated and each sample.
Expected values are computed here (the core's push, the importer), not read off the page."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import algrasp
from tests.service.test_workbench import browser, chromium, open_page, page, server  # noqa: F401

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(chromium() is None, reason="browser tests skipped: no Chromium found"),
]

ROOT = Path(__file__).resolve().parents[2]
BRACKET = json.loads((ROOT / "algrasp" / "examples" / "bracket.json").read_text())


def _design(pg: Any, model: str = "exact") -> dict[str, Any]:
    pg.select_option("#example", "bracket")
    pg.wait_for_selector("#analysis:not([hidden])")
    pg.click("button[data-page=fences]")
    pg.select_option("#fence-model", model)
    with pg.expect_response(lambda r: r.url.endswith("/v1/fences") and "svg" not in (r.request.post_data or "")) as resp:
        pg.click("#fence-btn")
    pg.wait_for_selector("#fence-summary[data-fences]")
    return resp.value.json()  # type: ignore[no-any-return]


def _off(phi: float, finals: list[float], period: float) -> float:
    return min(abs((phi - f + period / 2) % period - period / 2) for f in finals)


def test_design_shows_the_apis_layout_and_table(page: Any) -> None:  # noqa: F811
    doc = _design(page)
    want: dict[str, Any] = dict(algrasp.fences(BRACKET, exact=True, fence_friction=[0.1, 0.3], min_margin_deg=1.0).to_dict())
    assert [f["angle_deg"] for f in doc["fences"]] == pytest.approx([f["angle_deg"] for f in want["fences"]])
    rows = page.locator("#fence-table tbody tr")
    assert rows.count() == len(want["fences"]) == int(page.get_attribute("#fence-summary", "data-fences") or 0)
    for i, f in enumerate(want["fences"]):
        cells = rows.nth(i).locator("td").all_inner_texts()
        assert cells[1] == f["side"] and float(cells[2]) == pytest.approx(f["angle_deg"], abs=0.005)
        assert float(cells[4].lstrip("±")) == pytest.approx(f["margin_deg"], abs=0.005)
        assert float(cells[6].split()[0]) == pytest.approx(f["length"], rel=1e-3)
    # the drawing is the API's SVG: one red line per fence
    assert page.locator("#fence-drawing svg line.fence").count() == len(want["fences"])


def test_animation_ends_where_the_designs_push_puts_the_part(page: Any) -> None:  # noqa: F811
    from algrasp.planning.analysis import EXACT, analyse_document
    from algrasp.planning.fence_model import push_of

    doc = _design(page)
    analysis = analyse_document(BRACKET, EXACT)
    design = algrasp.fences(BRACKET, exact=True).design  # the layout's (ties broken by length)
    assert [math.degrees(a) for a in design.angles] == pytest.approx([f["angle_deg"] for f in doc["fences"]])
    for start in (200, 47):
        page.fill("#fence-start", str(start))
        page.dispatch_event("#fence-start", "input")
        page.evaluate("document.getElementById('fence-final').removeAttribute('data-final-range')")
        page.click("#fence-play")
        page.wait_for_selector("#fence-final[data-final-range]")
        lo, hi = design.run(push_of(analysis), np.array([math.radians(start)]))
        want = math.degrees(0.5 * (lo[0] + hi[0])) % 360.0
        got = float(page.get_attribute("#fence-final", "data-final-deg") or "nan")
        assert abs((got - want + 180.0) % 360.0 - 180.0) < 1e-6
        assert page.get_attribute("#fence-final", "data-claimed") == "true"
        assert _off(got, doc["final_orientations_deg"], doc["symmetry_period_deg"]) < 1e-6
    assert page.locator("#fence-anim svg line[id^=fence-line-]").count() == len(doc["fences"])


def test_downloaded_dxf_reimports_to_the_tables_fences(page: Any, tmp_path: Path) -> None:  # noqa: F811
    from algrasp.io.cad import import_file

    doc = _design(page)
    with page.expect_download() as dl:
        page.click("#fence-dxf")
    path = tmp_path / "belt.dxf"
    dl.value.save_as(path)
    assert dl.value.suggested_filename == "bracket-fences.dxf"
    got = import_file(str(path))
    assert got["kind"] == "fence_layout"
    for mine, want in zip(got["fences"], doc["fences"], strict=True):
        assert mine["side"] == want["side"]
        assert mine["angle_deg"] == pytest.approx(want["angle_deg"], abs=1e-9)
        assert mine["length"] == pytest.approx(want["length"], rel=1e-9)


@pytest.fixture()
def page_422(browser: Any, server: Any) -> Any:  # noqa: F811
    """A page on which the 422 the test provokes is the one console error allowed."""
    yield from open_page(browser, server, allowed="422")


def test_bad_friction_is_said_by_field_and_a_changed_option_marks_stale(page_422: Any) -> None:
    pg = page_422
    _design(pg)
    pg.fill("#fence-mu-lo", "0.5")
    pg.dispatch_event("#fence-mu-lo", "input")
    assert "options changed" in pg.inner_text("#fence-stale")
    pg.click("#fence-btn")
    pg.wait_for_selector("#message.error")
    assert "fence_friction" in pg.inner_text("#message")


@pytest.mark.sim
def test_validate_on_the_belt_says_what_and_each_sample(page: Any) -> None:  # noqa: F811
    pytest.importorskip("pydrake")
    doc = _design(page)
    page.fill("#fence-samples", "1")
    page.fill("#fence-seed", "2")
    with page.expect_response(lambda r: r.url.endswith("/v1/fences") and "validate" in (r.request.post_data or ""),
                              timeout=300_000) as resp:
        page.click("#fence-validate-btn")
    page.wait_for_selector("#fence-validation-summary[data-agreement]", timeout=300_000)
    v = resp.value.json()["validation"]
    what = page.inner_text("#fence-validation-what")
    assert "1 start of seed 2" in what and "Drake" in what and f"{len(doc['fences'])}-fence design" in what
    (sample,) = v["samples"]
    mine = _off(sample["simulated_deg"], doc["final_orientations_deg"], doc["symmetry_period_deg"])
    agrees = mine <= doc["final_uncertainty_deg"] + v["tolerance_deg"]
    cells = page.locator("#fence-validation-table tbody tr").nth(0).locator("td").all_inner_texts()
    assert cells[-1] == ("yes" if agrees else "NO")
    assert float(cells[4].rstrip("°")) == pytest.approx(sample["simulated_deg"], abs=0.005)
    assert float(page.get_attribute("#fence-validation-summary", "data-agreement") or -1) == float(agrees)
