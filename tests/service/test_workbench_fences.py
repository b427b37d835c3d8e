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
PLATE = json.loads((ROOT / "algrasp" / "examples" / "real" / "battery-plate.json").read_text())
PIE20 = json.loads((ROOT / "algrasp" / "examples" / "pie-20.json").read_text())


def _design(pg: Any, model: str = "exact", example: str = "bracket", tip_turns: bool = False,
            same_rail: bool = False, friction: tuple[float, float] | None = None) -> dict[str, Any]:
    """Design on the page; the bracket has a design only in Berretty et al.'s model (no turn
    over the tips), the battery plate in the default one."""
    pg.select_option("#example", example)
    pg.wait_for_selector("#analysis:not([hidden])")
    pg.click("button[data-page=fences]")
    pg.select_option("#fence-model", model)
    pg.set_checked("#fence-tip-turns", tip_turns)
    pg.set_checked("#fence-same-rail", same_rail)
    if friction is not None:
        pg.fill("#fence-mu-lo", str(friction[0]))
        pg.fill("#fence-mu-hi", str(friction[1]))
    with pg.expect_response(lambda r: r.url.endswith("/v1/fences") and "svg" not in (r.request.post_data or "")) as resp:
        pg.click("#fence-btn")
    pg.wait_for_selector("#fence-summary[data-fences]")
    return resp.value.json()  # type: ignore[no-any-return]


def _off(phi: float, finals: list[float], period: float) -> float:
    return min(abs((phi - f + period / 2) % period - period / 2) for f in finals)


def test_design_shows_the_apis_layout_and_table(page: Any) -> None:  # noqa: F811
    doc = _design(page)
    want: dict[str, Any] = dict(algrasp.fences(BRACKET, exact=True, fence_friction=[0.1, 0.3], min_margin_deg=1.0,
                                               exit_turns=False).to_dict())
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
    assert "Berretty" in page.inner_text("#fence-summary")


def _expected_final(part: dict[str, Any], exact: bool, tip_turns: bool, start_deg: float) -> tuple[float, float]:
    """[lo, hi] (deg) past the exit guide from ``start_deg``, composed here from the core's
    push: each fence's push at its angle, the turn over each tip (in the design's model),
    the last tip's turn, the guide's push at its angle (tilted by the fence friction, as
    every fence's) and its own tip's turn."""
    from algrasp.planning.fence_model import exit_turn, push_of

    layout = algrasp.fences(part, exact=exact, exit_turns=tip_turns)
    assert layout.exit is not None
    analysis = algrasp.analyse(part, exact=exact)
    push = push_of(analysis)
    lo, hi = layout.design.run(push, np.array([math.radians(start_deg)]))
    lo, hi = exit_turn(lo, hi, layout.design.angles[-1])
    g = layout.exit.angle
    lo, hi = push.image(lo - g, hi - g, g)  # the guide is a fence too: tilted by its friction
    lo, hi = exit_turn(lo + g, hi + g, g)
    return math.degrees(lo[0]), math.degrees(hi[0])


@pytest.mark.parametrize(("example", "model", "tip_turns"), [("bracket", "exact", False), ("battery-plate", "robust", True)])
def test_animation_ends_where_the_designs_push_puts_the_part(page: Any, example: str, model: str,  # noqa: F811
                                                            tip_turns: bool) -> None:
    part = BRACKET if example == "bracket" else PLATE
    doc = _design(page, model, example, tip_turns)
    assert doc["exit_turns"] is tip_turns and doc["exit"]
    for start in (200, 47):
        page.fill("#fence-start", str(start))
        page.dispatch_event("#fence-start", "input")
        page.evaluate("document.getElementById('fence-final').removeAttribute('data-final-range')")
        page.click("#fence-play")
        page.wait_for_selector("#fence-final[data-final-range]")
        lo, hi = _expected_final(part, model == "exact", tip_turns, start)
        got_lo, got_hi = json.loads(page.get_attribute("#fence-final", "data-final-range") or "[]")
        T = doc["symmetry_period_deg"]  # the push is periodic with it: the core's image lands in one period
        shift = T * round((got_lo - lo) / T)
        assert (got_lo - shift, got_hi - shift) == pytest.approx((lo, hi), abs=1e-6)
        assert page.get_attribute("#fence-final", "data-claimed") == "true"
        got = float(page.get_attribute("#fence-final", "data-final-deg") or "nan")
        assert _off(got, doc["final_orientations_deg"], doc["symmetry_period_deg"]) <= doc["final_uncertainty_deg"] + 1e-6
    assert page.locator("#fence-anim svg line[id^=fence-line-]").count() == len(doc["fences"])
    assert page.locator("#fence-anim svg #fence-exit-line").count() == 1


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


def test_same_rail_checkbox_asks_for_the_same_rail_design(page: Any) -> None:  # noqa: F811
    """Ticked, the page's request carries ``same_rail`` and shows the API's same-rail design
    of pie-20 (tip turns modelled, fence friction 0–0.03 set on the page; it has no
    alternating design), two consecutive fences on one rail."""
    doc = _design(page, "robust", "pie-20", tip_turns=True, same_rail=True, friction=(0.0, 0.03))
    want: dict[str, Any] = dict(algrasp.fences(PIE20, fence_friction=[0.0, 0.03], min_margin_deg=1.0,
                                               same_rail=True).to_dict())
    assert any(a["side"] == b["side"] for a, b in zip(want["fences"], want["fences"][1:]))
    assert doc["same_rail"] is True
    assert [f["angle_deg"] for f in doc["fences"]] == pytest.approx([f["angle_deg"] for f in want["fences"]])
    assert [f["side"] for f in doc["fences"]] == [f["side"] for f in want["fences"]]
    assert page.locator("#fence-table tbody tr").count() == len(want["fences"])


TRIANGLE = json.loads((ROOT / "tests" / "data" / "fences" / "triangle.json").read_text())
LOW_FRICTION = [0.0, 0.03]
"""Fence friction under which pie-20 and the triangle have same-rail designs (none above ~0.035)."""


def _count(part: dict[str, Any], **options: Any) -> int | str:
    """The API's fence count for the part, or "refused" when it has no design."""
    try:
        return len(algrasp.fences(part, **options).to_dict()["fences"])
    except algrasp.NotOrientableError:
        return "refused"


def test_jobs_page_sends_fence_options_and_shows_each_parts_fences(page: Any, server: Any,  # noqa: F811
                                                                   tmp_path: Path) -> None:
    """The Catalogue page with "design conveyor fences", same rail and exit steepness 3°: the
    job's per-part fence results echo those options, and each part's fences cell says the count of
    ``algrasp.fences(part, same_rail=True)`` at fence friction 0–0.03, set on the page (pie-20
    and the triangle have no design with alternating rails, so a job that dropped same_rail
    would differ)."""
    import zipfile

    parts = {"pie-20": PIE20, "tri": dict(TRIANGLE, name="tri")}
    archive = tmp_path / "catalogue.zip"
    with zipfile.ZipFile(archive, "w") as z:
        for name, part in parts.items():
            z.writestr(f"{name}.json", json.dumps(part))
    page.click("button[data-page=catalogue]")
    assert page.is_disabled("#job-fence-same-rail")  # the fence options wait for the checkbox
    page.set_input_files("#job-archive", str(archive))
    page.check("#job-fences")
    page.check("#job-fence-same-rail")
    page.fill("#job-fence-mu-lo", str(LOW_FRICTION[0]))
    page.fill("#job-fence-mu-hi", str(LOW_FRICTION[1]))
    page.fill("#job-exit-steepness", "3")
    page.click("#job-submit")
    page.wait_for_selector("#job-out[data-state=done]", timeout=180_000)
    job_id = page.get_attribute("#job-out", "data-job")
    with server.client() as c:  # what the job stored: each part's fence result echoes its options
        lines = [json.loads(x) for x in c.get(f"/v1/jobs/{job_id}/results").text.splitlines()]
    for line in lines:
        assert line["result"]["fences"]["options"] == {"fence_friction": LOW_FRICTION, "belt_width": None,
                                                      "min_margin_deg": 1.0, "exit_steepness_deg": 3.0,
                                                      "exit_turns": True, "same_rail": True}
    rows = page.locator("#job-parts tbody tr")
    assert rows.count() == len(parts) == len(lines)
    for i in range(rows.count()):
        name = rows.nth(i).locator("td").nth(1).inner_text()
        want = _count(parts[name], same_rail=True, exit_steepness_deg=3.0, fence_friction=LOW_FRICTION)
        assert want != "refused"
        assert rows.nth(i).locator("td[data-fences]").get_attribute("data-fences") == str(want)
        assert rows.nth(i).locator("td").last.inner_text().startswith(f"{want} fence")
        assert _count(parts[name], exit_steepness_deg=3.0, fence_friction=LOW_FRICTION) == "refused"  # same rail did


def test_jobs_page_says_a_bad_fence_option_by_its_control(page_422: Any, tmp_path: Path) -> None:
    import zipfile

    archive = tmp_path / "catalogue.zip"
    with zipfile.ZipFile(archive, "w") as z:
        z.writestr("tri.json", json.dumps(TRIANGLE))
    pg = page_422
    pg.click("button[data-page=catalogue]")
    pg.set_input_files("#job-archive", str(archive))
    pg.check("#job-fences")
    pg.fill("#job-exit-steepness", "0")  # the form allows it, the API does not (0 < β_e ≤ 10°): its 422
    pg.click("#job-submit")
    pg.wait_for_selector("#job-form .field-error[data-field=exit_steepness_deg]")
    assert pg.get_attribute("#job-exit-steepness", "aria-invalid") == "true"
    assert "exit_steepness_deg" in pg.inner_text("#message")


def test_exit_steepness_reaches_the_design_and_its_drawings(page_422: Any) -> None:
    """Exit steepness 3°: the page's design is the API's for ``exit_steepness_deg=3`` (the
    exit guide at 3° to the belt), and the SVG and DXF drawings are asked with it too; 0° is
    refused by the API and said next to the control."""
    pg = page_422
    pg.select_option("#example", "battery-plate")
    pg.wait_for_selector("#analysis:not([hidden])")
    pg.click("button[data-page=fences]")
    pg.fill("#fence-exit-steepness", "3")
    with (pg.expect_request(lambda r: r.url.endswith("/v1/fences") and "svg" in (r.post_data or "")) as svg_req,
          pg.expect_response(lambda r: r.url.endswith("/v1/fences") and "svg" not in (r.request.post_data or "")) as resp):
        pg.click("#fence-btn")
    pg.wait_for_selector("#fence-summary[data-fences]")
    doc = resp.value.json()
    want: dict[str, Any] = json.loads(json.dumps(algrasp.fences(PLATE, fence_friction=[0.1, 0.3], min_margin_deg=1.0,
                                                                exit_steepness_deg=3.0).to_dict()))
    assert doc["exit"]["steepness_deg"] == pytest.approx(3.0) == pytest.approx(want["exit"]["steepness_deg"])
    assert doc["exit"]["length"] == pytest.approx(want["exit"]["length"])
    assert [f["angle_deg"] for f in doc["fences"]] == pytest.approx([f["angle_deg"] for f in want["fences"]])
    assert svg_req.value.post_data_json["exit_steepness_deg"] == 3
    assert "exit guide at 3° to the belt" in pg.inner_text("#fence-summary")
    with (pg.expect_request(lambda r: r.url.endswith("/v1/fences") and "dxf" in (r.post_data or "")) as dxf_req,
          pg.expect_download()):
        pg.click("#fence-dxf")
    assert dxf_req.value.post_data_json["exit_steepness_deg"] == 3
    pg.fill("#fence-exit-steepness", "0")
    pg.click("#fence-btn")
    pg.wait_for_selector("#fence-form .field-error[data-field=exit_steepness_deg]")
    assert pg.get_attribute("#fence-exit-steepness", "aria-invalid") == "true"
