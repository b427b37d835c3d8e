"""The workbench's pages in headless Chromium (issue 35): the key form only when needed and
a rejected key said; a sheet uploaded once with its warnings once; the jobs list with
progress and Cancel; a part drawn in the editor, saved, analysed and planned. Expected
values come from the public API called here or are computed here."""

from __future__ import annotations

from typing import Any

import pytest

from tests.service.test_workbench import browser, chromium, page, plan_in_page, server  # noqa: F401

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(chromium() is None, reason="browser tests skipped: no Chromium found"),
]


def test_hidden_means_hidden_without_a_key(page: Any) -> None:  # noqa: F811
    """No key needed: the key form is not shown nor in the Tab order; before any part, no
    empty plot frames show."""
    assert page.locator("#key-form").is_hidden()
    assert page.locator("#analysis").is_hidden() and page.locator("#plot-d").is_hidden()
    for _ in range(12):  # Tab through the header: the key input is never reached
        page.keyboard.press("Tab")
        assert page.evaluate("document.activeElement.id") != "apikey"


@pytest.fixture(scope="module")
def keyed_server(tmp_path_factory: pytest.TempPathFactory) -> Any:
    from tests.service.conftest import start_server

    s = start_server(tmp_path_factory.mktemp("keyed"), ALGRASP_API_KEYS="right-key")
    yield s
    s.kill()


def test_the_key_form_shows_when_needed_and_says_a_rejected_key(browser: Any, keyed_server: Any) -> None:  # noqa: F811
    ctx = browser.new_context(base_url=keyed_server.url)
    pg = ctx.new_page()
    errors: list[str] = []
    # the 401s themselves are logged by Chromium as failed loads; anything else is a defect
    pg.on("console", lambda m: errors.append(m.text) if m.type == "error" and "401" not in m.text else None)
    pg.on("pageerror", lambda e: errors.append(str(e)))
    try:
        pg.goto("/")
        pg.wait_for_selector("body[data-ready=true]")
        assert pg.locator("#key-form").is_visible()
        pg.fill("#apikey", "wrong-key")
        with pg.expect_response(lambda r: r.url.endswith("/v1/examples")) as resp:
            pg.click("#key-form button")
        assert resp.value.status == 401
        pg.wait_for_selector("#message.error")
        assert "key rejected" in pg.inner_text("#message")
        assert pg.evaluate("sessionStorage.length") == 0  # a wrong key is not kept
        pg.fill("#apikey", "right-key")
        pg.click("#key-form button")
        pg.wait_for_selector("#key-form[data-accepted=true]")
        assert "pie-20" in pg.inner_text("#example")
        assert pg.evaluate("document.querySelectorAll('#example option').length") == 6  # no repeats: —, 3 paper parts, 2 real
    finally:
        ctx.close()
    assert errors == []


def test_a_sheet_is_uploaded_once_and_its_warnings_said_once(page: Any, server: Any) -> None:  # noqa: F811
    """The 10-gear sheet: one upload; every warning once, none telling the user about a CLI
    flag; each thumbnail's #K index fully visible; the page's own units control re-reads it."""
    from pathlib import Path

    drawing = Path(__file__).resolve().parents[2] / "tests" / "data" / "real" / "koppi-involute-teeth-20-multiple.dxf"
    with server.client() as c:
        sheet = c.post("/v1/imports", files={"file": (drawing.name, drawing.read_bytes())}, data={"list": "true"}).json()
    assert len(sheet["parts"]) == 10 and any("INSUNITS" in w for w in sheet["warnings"])
    uploads: list[Any] = []
    page.on("request", lambda r: uploads.append(r) if r.url.endswith("/v1/imports") else None)
    page.set_input_files("#file", str(drawing))
    page.wait_for_selector("#plot-d canvas", timeout=60_000)
    assert len(uploads) == 1
    items = page.eval_on_selector_all("#warnings li", "els => els.map(e => e.textContent)")
    assert len(items) == len(set(items)) and items
    assert not any("--units" in w for w in items)
    assert any("assumed millimetres" in w and "drawing units" in w for w in items)
    thumbs = page.locator("#thumbs .thumb")
    assert thumbs.count() == 10
    for k in range(10):
        box = page.evaluate("""(k) => { const b = document.querySelectorAll('#thumbs .thumb')[k];
            const i = b.querySelector('.thumb-index');
            const r = i.getBoundingClientRect(), o = b.getBoundingClientRect();
            return {text: i.textContent, inside: r.left >= o.left && r.right <= o.right,
                    cut: i.scrollWidth > i.clientWidth + 0.5}; }""", k)
        assert box == {"text": f"#{k}", "inside": True, "cut": False}
    with page.expect_response(lambda r: r.url.endswith("/v1/imports")) as resp:
        page.select_option("#units", "in")
    assert {d["units"] for d in resp.value.json()["documents"]} == {"in"}  # the server read it in inches
    page.wait_for_selector("#part-facts:has-text('in²')")
    items = page.eval_on_selector_all("#warnings li", "els => els.map(e => e.textContent)")
    assert not any("assumed millimetres" in w for w in items)


def test_jobs_are_listed_with_progress_and_can_be_cancelled(page: Any, server: Any, pie: dict[str, Any]) -> None:  # noqa: F811
    """A long job started through the API: the Catalogue page lists it with its state and
    progress; Cancel cancels it (the API says so); after a reload the list and the job are
    still there."""
    with server.client() as c:
        job_id = c.post("/v1/jobs", json={"parts": [pie] * 30, "options": {"validate": {"samples": 1}}}).json()["id"]
    page.click("button[data-page=catalogue]")
    row = f"#jobs-table tr[data-job='{job_id}']"
    page.wait_for_selector(row)
    assert page.get_attribute(row, "data-state") in ("queued", "running")
    assert page.locator(f"{row} progress").count() == 1
    with page.expect_response(lambda r: r.url.endswith(f"/v1/jobs/{job_id}") and r.request.method == "DELETE") as resp:
        page.click(f"{row} button.job-cancel")
    assert resp.value.status == 200
    page.wait_for_selector(f"{row}[data-state=cancelled]")
    with server.client() as c:
        assert c.get(f"/v1/jobs/{job_id}").json()["state"] == "cancelled"
    page.click(f"{row} button.job-show")
    page.wait_for_selector("#job-out[data-state=cancelled]")
    assert page.locator("#job-cancel").is_hidden()
    page.reload()
    page.wait_for_selector("body[data-ready=true]")
    page.click("button[data-page=catalogue]")
    page.wait_for_selector(f"#job-out[data-job='{job_id}'][data-state=cancelled]")
    assert page.locator(row).count() == 1


def test_a_part_drawn_by_clicks_is_saved_analysed_and_planned(page: Any) -> None:  # noqa: F811
    """Four clicks on the editor's 60 mm grid draw a 30 × 20 mm rectangle; dragging a vertex
    moves it; the saved document is the polygon; its analysis has the shoelace area; it plans."""
    import json as _json
    from pathlib import Path

    def shoelace(pts: list[tuple[float, float]]) -> float:
        return abs(sum(x * v - u * y for (x, y), (u, v) in zip(pts, pts[1:] + pts[:1]))) / 2

    page.click("#editor-open")
    box = page.locator("#editor-canvas").bounding_box()

    def at(x: float, y: float) -> tuple[float, float]:  # mm → screen (y up, 0..60 mm)
        return box["x"] + x / 60 * box["width"], box["y"] + (60 - y) / 60 * box["height"]

    pts = [(10.0, 10.0), (40.0, 10.0), (40.0, 30.0), (10.0, 30.0)]
    for x, y in pts:
        page.mouse.click(*at(x, y))
    assert f"area {shoelace(pts):.2f} mm²" in page.inner_text("#editor-facts")
    page.mouse.move(*at(40, 30))  # drag the third vertex up 10 mm
    page.mouse.down()
    page.mouse.move(*at(40, 35))
    page.mouse.move(*at(40, 40))
    page.mouse.up()
    pts[2] = (40.0, 40.0)
    assert f"area {shoelace(pts):.2f} mm²" in page.inner_text("#editor-facts")
    with page.expect_download() as dl:
        page.click("#editor-save")
    doc = _json.loads(Path(dl.value.path()).read_text())
    assert doc["units"] == "mm" and shoelace([tuple(p) for p in doc["polygon"]]) == pytest.approx(shoelace(pts))
    assert sorted(map(tuple, doc["polygon"])) == sorted(pts)
    with page.expect_response(lambda r: "/v1/analyses" in r.url) as resp:
        page.click("#editor-use")
    page.wait_for_selector("#plot-d canvas")
    assert resp.value.json()["part"]["area"] == pytest.approx(shoelace(pts), rel=1e-9)
    assert page.inner_text("#part-facts").startswith("drawn part")
    plan = plan_in_page(page, "squeeze")
    assert page.locator("#plan-steps tbody tr").count() == len(plan["steps"]) >= 1
