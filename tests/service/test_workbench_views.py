"""The workbench's pictures and state in headless Chromium (issue 35): wrapped periodic
regions and images, labelled Θᵢ bars, titles that fit, stale responses never drawn,
panels cleared when their inputs change, playback framing and what a validation says.
Expected values come from the public API called here (or from the paper), and are
compared with the pixels of the plots' canvases (uPlot) and the scenes' SVG geometry."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from tests.service.test_workbench import browser, chromium, page, plan_in_page, server  # noqa: F401
from tests.service.test_workbench_plots import GREY, ORANGE, ORANGE_ON_GREY, canvas, column_share

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(chromium() is None, reason="browser tests skipped: no Chromium found"),
]

def wrapped(a: float, b: float, period: float) -> list[tuple[float, float]]:
    """[a, b] on a periodic axis [0, period]: the pieces of it and its shifted copies."""
    if b - a >= period:
        return [(0.0, period)]
    out = []
    for k in range(-3, 4):
        lo, hi = max(a + k * period, 0.0), min(b + k * period, period)
        if hi - lo > 1e-6:
            out.append((lo, hi))
    return sorted(out)


def union(spans: list[tuple[float, float]]) -> list[tuple[float, float]]:
    out: list[tuple[float, float]] = []
    for a, b in sorted(spans):
        if out and a <= out[-1][1] + 1e-9:
            out[-1] = (out[-1][0], max(out[-1][1], b))
        else:
            out.append((a, b))
    return out


def inside(theta: float, spans: list[tuple[float, float]], margin: float) -> bool | None:
    """θ in one of the spans (True), away from all (False), or within `margin` of an edge (None)."""
    if any(abs(theta - e) < margin for span in spans for e in span):
        return None
    return any(a < theta < b for a, b in spans)


def regions_drawn(pg: Any, host: str, period: float, ramps: list[tuple[float, float]],
                  dead: list[tuple[float, float]]) -> list[str]:
    """Every θ (0.5° apart, 1° clear of an edge) coloured as its regions say: orange on a
    constant region or ramp (over grey where a dead zone is under it too), grey on a dead
    zone only, neither elsewhere. Returns the θ where the colour is wrong."""
    img, area = canvas(pg, host)
    assert (area["x0"], area["x1"]) == (0, period)
    wrong = []
    for theta in np.arange(0.25, period, 0.5):
        r, d = inside(theta, ramps, 1.0), inside(theta, dead, 1.0)
        if r is None or d is None:
            continue
        want = ORANGE_ON_GREY if r and d else ORANGE if r else GREY if d else None
        shares = {c: column_share(img, area, theta, c) for c in (ORANGE, GREY, ORANGE_ON_GREY)}
        ok = all((v >= 0.4) if c == want else (v <= 0.02) for c, v in shares.items())
        if not ok:
            wrong.append(f"{theta:.2f}° wants {want}: {shares}")
    return wrong


def analysis_of(server: Any, name: str) -> dict[str, Any]:  # noqa: F811
    with server.client() as c:
        ex = {e["name"]: e["part"] for e in c.get("/v1/examples").json()["examples"]}
        return c.post("/v1/analyses?samples=720&exact=false", json=ex[name]).json()  # type: ignore[no-any-return]


def test_periodic_regions_and_images_wrap_on_every_plot(page: Any, server: Any) -> None:  # noqa: F811
    """pie-20: d's constant region [160°, 200°) and the squeeze ramp are orange at 160–180°
    and 0–20°; every dead zone grey in all its pieces (the push's zone about 0° at both ends
    of 0–360°); the set images of the squeeze cover the whole axis."""
    a = analysis_of(server, "pie-20")
    page.select_option("#example", "pie-20")
    page.wait_for_selector("#plot-push_grasp canvas")
    sq_dead = union([p for lo, hi in a["robust"]["squeeze"]["dead_zones_deg"] for p in wrapped(lo, hi, 180.0)])
    ramps = union([p for lo, hi in a["diameter"]["constant_intervals_deg"] for p in wrapped(lo, hi, 180.0)])
    assert ramps[0][0] == pytest.approx(0.0) and ramps[-1][1] == pytest.approx(180.0)  # both sides
    assert regions_drawn(page, "plot-d", 180.0, ramps, sq_dead) == []
    push_dead = union([p for lo, hi in a["robust"]["push"]["dead_zones_deg"] for p in wrapped(lo, hi, 360.0)])
    assert push_dead[0][0] == pytest.approx(0.0) and push_dead[-1][1] == pytest.approx(360.0)
    r_const = union([p for lo, hi in a["radius"]["constant_intervals_deg"] for p in wrapped(lo, hi, 360.0)])
    assert regions_drawn(page, "plot-r", 360.0, r_const, push_dead) == []
    # the squeeze's ramps, orange in every column of theirs (images may cover part of it)
    img, area = canvas(page, "plot-squeeze")
    ramp = union([p for s in a["squeeze"]["ramps"] for p in wrapped(s["start_deg"], s["end_deg"], 180.0)])
    assert ramp[0][0] == pytest.approx(0.0) and ramp[-1][1] == pytest.approx(180.0)
    for theta in np.arange(0.25, 180.0, 0.5):
        where = inside(theta, ramp, 1.0)
        if where is not None:
            share = max(column_share(img, area, theta, c) for c in (ORANGE, ORANGE_ON_GREY))
            assert (share >= 0.2) if where else (share <= 0.02), (theta, share)
    # the images as drawn (in θ), clipped to the axis, leave no θ without an image
    polys = page.evaluate("document.getElementById('plot-squeeze').plot.drawn.images")
    spans = sorted((max(min(x for x, _ in q), 0.0), min(max(x for x, _ in q), 180.0)) for q in polys)
    reach = 0.0
    for lo, hi in spans:
        if hi <= 0:
            continue
        assert lo <= reach + 0.05, f"no image drawn on [{reach:.2f}, {lo:.2f}]"
        reach = max(reach, hi)
    assert reach == pytest.approx(180.0, abs=0.05)


def test_intervals_are_labelled_non_overlapping_rows(page: Any) -> None:  # noqa: F811
    """The plan's Θᵢ: one green row each under the θ axis, labelled (text left of each row,
    and Θ1…Θn said to screen readers), rows apart by more than a bar's width, an interval
    past the period drawn in two pieces as long as the interval together."""
    page.select_option("#example", "pie-20")
    page.wait_for_selector("#plot-d canvas")
    plan = plan_in_page(page, "squeeze")
    img, area = canvas(page, "plot-intervals")
    P = 180.0
    bottom = int(area["top"] + area["height"])
    green = np.abs(img[bottom:] - (46, 125, 50)).max(axis=2) <= 12
    rows = np.nonzero(green.any(axis=1))[0]
    bars = np.split(rows, np.nonzero(np.diff(rows) > 1)[0] + 1)  # runs of adjacent rows: one bar each
    assert len(bars) == len(plan["intervals_deg"])
    centres = [bottom + float(np.mean(b)) for b in bars]
    assert all(b - a >= 8 for a, b in zip(centres, centres[1:]))  # bars are 4 px: never touch
    f = P / area["width"]
    crossing = 0
    for (lo, hi), bar, y in zip(plan["intervals_deg"], bars, centres):
        cols = np.nonzero(green[int(np.median(bar))])[0]
        pieces = np.split(cols, np.nonzero(np.diff(cols) > 1)[0] + 1)
        got = [((c[0] - area["left"]) * f, (c[-1] + 1 - area["left"]) * f) for c in pieces]
        want = wrapped(lo, hi, P)
        assert len(got) == len(want) and all(abs(g[0] - w[0]) <= 2 * f and abs(g[1] - w[1]) <= 2 * f
                                             for g, w in zip(got, want)), (got, want)
        label = img[int(y) - 4:int(y) + 5, int(area["left"]) - 30:int(area["left"]) - 4]
        assert (label.max(axis=2) < 160).sum() >= 8, "no label left of the bar"
        crossing += hi > P + 1e-6
    assert crossing  # the pie's 180° Θ₃ crosses the period
    said = page.eval_on_selector_all("#plot-intervals .plot-lanes li", "els => els.map(e => e.textContent)")
    assert [t.split(":")[0] for t in said] == [f"Θ{i + 1}" for i in range(len(plan["intervals_deg"]))]


def until_routed(pg: Any, held: list[Any]) -> None:
    """Until the held request reached its route handler (Playwright hands a route over
    after the request event: round trips to the page let it through; no sleep)."""
    for _ in range(10_000):
        if held:
            return
        pg.evaluate("0")
    raise AssertionError("the request never reached its route")


def two_runs(server: Any, pie: dict[str, Any]) -> tuple[str, str]:  # noqa: F811
    with server.client() as c:
        a = c.post("/v1/plans", json={"part": pie, "action": "squeeze", "exact": True}).json()["run_id"]
        b = c.post("/v1/plans", json={"part": pie, "action": "push_grasp", "exact": True}).json()["run_id"]
    return a, b


def test_a_late_figure_of_an_earlier_run_is_not_drawn(page: Any, server: Any, pie: dict[str, Any]) -> None:  # noqa: F811
    """Click run A, then run B while A's figure is still on its way: only B's figure shows,
    under B's title, also once A's answer has arrived."""
    run_a, run_b = two_runs(server, pie)
    held: list[Any] = []
    page.route(f"**/v1/runs/{run_a}/figure.svg", lambda route: held.append(route))  # A's figure waits
    page.click("button[data-page=runs]")
    with page.expect_request(lambda r: r.url.endswith(f"/v1/runs/{run_a}/figure.svg")):
        page.locator("#runs-table tbody tr", has_text=run_a).click()
    until_routed(page, held)
    page.locator("#runs-table tbody tr", has_text=run_b).click()
    page.wait_for_selector(f"#run-figure img[alt='plan figure of run {run_b}']")
    with page.expect_event("requestfinished", predicate=lambda r: r.url.endswith(f"/v1/runs/{run_a}/figure.svg")):
        held[0].continue_()
    # A's answer is in: either dropped (counted) or drawn (the defect)
    page.wait_for_selector("#run-figure[data-dropped], #run-figure img:nth-of-type(2)")
    alts = page.eval_on_selector_all("#run-figure img", "els => els.map(e => e.alt)")
    assert alts == [f"plan figure of run {run_b}"]
    assert run_b in page.inner_text("#run-title") and run_a not in page.inner_text("#run-title")


def test_a_new_plan_clears_the_old_end_and_a_failed_plan_clears_the_plan(page: Any) -> None:  # noqa: F811
    """After a played push-grasp plan, a new plan shows no "ends at φ = …" of the old one;
    a plan that fails leaves no old plan under its error; changed inputs mark the plan stale."""
    page.select_option("#example", "pie-20")
    page.wait_for_selector("#plot-d canvas")
    plan_in_page(page, "push_grasp")
    page.click("#anim-play")
    page.wait_for_selector("#anim-final[data-final-deg]", timeout=30_000)
    assert "ends at φ" in page.inner_text("#anim-final")
    plan_in_page(page, "squeeze")
    assert page.get_attribute("#anim-final", "data-final-deg") is None
    assert "ends at" not in page.inner_text("#anim-final")
    page.fill("#min-margin", "1")  # an input changed: the plan shown is no longer the form's
    assert page.get_attribute("#plan-out", "data-stale") == "true"
    assert "inputs changed" in page.inner_text("#plan-stale")
    page.fill("#gripper", "{not json")  # this plan fails before it is sent
    page.click("#plan-btn")
    page.wait_for_selector("#message.error")
    assert "gripper profile: not valid JSON" in page.inner_text("#message")
    assert page.locator("#plan-out").is_hidden()
    assert page.locator("#plan-steps tbody tr").count() == 0
    assert page.get_attribute("#plan-summary", "data-steps") is None


def test_a_plan_opened_from_runs_names_its_run(page: Any, server: Any, pie: dict[str, Any]) -> None:  # noqa: F811
    """...and the Part page shows the run's part, not the part chosen before."""
    run_a, _ = two_runs(server, pie)
    page.select_option("#example", "bracket")
    page.wait_for_selector("#plot-d canvas")
    page.click("button[data-page=runs]")
    page.locator("#runs-table tbody tr", has_text=run_a).click()
    page.wait_for_selector("#run-figure img")
    page.click("#run-open")
    page.wait_for_selector("#page-plan:not([hidden]) #plan-summary[data-steps]")
    summary = page.inner_text("#plan-summary")
    assert "undefined" not in summary and f"run {run_a}" in summary
    facts = page.evaluate("document.getElementById('part-facts').textContent")
    assert facts.startswith(pie["name"]) and "bracket" not in facts


def test_a_late_analysis_of_an_earlier_part_is_not_drawn(page: Any) -> None:  # noqa: F811
    """Choose pie-20, then bracket while the pie's analysis is on its way: the bracket's
    analysis is what the page shows, also once the pie's answer arrived."""
    held: list[Any] = []

    def hold_pie(route: Any) -> None:
        if '"pie' in (route.request.post_data or ""):
            held.append(route)
        else:
            route.continue_()

    page.route("**/v1/analyses*", hold_pie)
    with page.expect_request(lambda r: "/v1/analyses" in r.url):
        page.select_option("#example", "pie-20")
    until_routed(page, held)
    page.select_option("#example", "bracket")
    page.wait_for_selector("#plot-d canvas")
    assert "bracket" in page.inner_text("#part-facts")
    with page.expect_event("requestfinished", predicate=lambda r: '"pie' in (r.post_data or "")):
        held[0].continue_()
    page.wait_for_selector("#analysis[data-dropped]")
    assert "bracket" in page.inner_text("#part-facts")


def view_box(pg: Any) -> tuple[float, float, float, float]:
    x, y, w, h = (float(v) for v in pg.get_attribute("#playback-view svg", "viewBox").split())
    return x, y, w, h


@pytest.mark.sim
def test_playback_is_framed_and_validation_says_what_it_validated(page: Any, server: Any, pie: dict[str, Any]) -> None:  # noqa: F811
    """Random placement, seed 5: at every simulated frame the part (its outline at the
    simulated pose) and both jaws' faces lie inside the view, which is no more than needed;
    the page names the action, model, placement and seed, and the Plan page shows the plan."""
    import numpy as np

    with server.client() as c:
        geo = c.post("/v1/analyses?samples=720", json=pie).json()["geometry"]
    outline, com = np.array(geo["outline"]), np.array(geo["center_of_mass"])
    R = float(np.max(np.hypot(*(outline - com).T)))
    page.select_option("#example", "pie-20")
    page.wait_for_selector("#plot-d canvas")
    page.click("button[data-page=validation]")
    page.fill("#samples", "2")
    page.fill("#val-seed", "5")
    page.select_option("#val-placement", "random")
    with (page.expect_request(lambda r: r.url.endswith("/v1/plans")) as req,
          page.expect_response(lambda r: "/playback" in r.url, timeout=180_000) as resp):
        page.click("#validate-btn")
    sent = req.value.post_data_json["validate"]
    assert sent["seed"] == 5 and sent["placement"] == "random"
    pb = resp.value.json()
    page.wait_for_selector("#validation-table tbody tr")
    what = page.inner_text("#validation-what")
    for text in ("squeeze plan", "robust model", "pie-20", "placement random", "seed 5", "2 samples"):
        assert text in what, (text, what)
    assert page.get_attribute("#plan-summary", "data-steps") == str(len(pb["plan"]["steps"]))
    assert pb["run_id"] in page.inner_text("#plan-summary")
    page.click("#playback-play")
    page.wait_for_selector("#playback-status[data-ended=true]", timeout=60_000)
    x0, y0, w, h = view_box(page)
    tr = pb["trajectories"][0]
    need = []
    for i in range(len(tr["t_s"])):
        phi, alpha = np.radians(tr["phi_deg"][i]), np.radians(tr["gripper_angle_deg"][i])
        rot = np.array([[np.cos(phi), -np.sin(phi)], [np.sin(phi), np.cos(phi)]])
        pts = (outline - com) @ rot.T + [tr["x"][i], tr["y"][i]]
        t, n = np.array([np.cos(alpha), np.sin(alpha)]), np.array([-np.sin(alpha), np.cos(alpha)])
        for off in (tr["lower_jaw"][i], tr["higher_jaw"][i]):  # each jaw's face, R either side of the gripper
            if off is not None:
                pts = np.vstack([pts, off * n - R * t, off * n + R * t])
        need.append(pts)
    allpts = np.vstack(need)
    sx, sy = allpts[:, 0], -allpts[:, 1]  # SVG y is down
    assert sx.min() >= x0 - 1e-6 and sx.max() <= x0 + w + 1e-6, "the view crops the part or a jaw"
    assert sy.min() >= y0 - 1e-6 and sy.max() <= y0 + h + 1e-6, "the view crops the part or a jaw"
    assert max(w, h) <= 1.6 * max(np.ptp(sx), np.ptp(sy)), "the view is far larger than what it shows"


def test_plot_titles_fit_their_plots(page: Any) -> None:  # noqa: F811
    """At 1280 px, where titles were cut off: every plot title lies inside its plot, whole."""
    page.set_viewport_size({"width": 1280, "height": 900})
    page.select_option("#example", "pie-20")
    page.wait_for_selector("#plot-push_grasp canvas")
    out = page.evaluate("""() => [...document.querySelectorAll('#analysis .plot-host')].map((host) => {
        const t = host.querySelector('.u-title'), r = t.getBoundingClientRect(), s = host.getBoundingClientRect();
        return [r.left >= s.left - 0.5 && r.right <= s.right + 0.5 && t.scrollWidth <= t.clientWidth, t.textContent]; })""")
    assert len(out) == 5 and all(ok for ok, _ in out), out


def test_the_constant_region_is_one_orange_at_both_ends(page: Any) -> None:  # noqa: F811
    """pie-20's d(θ) is constant on [160°, 200°): the pixels at θ = 10° and 170° (inside both
    pieces, near the bottom of the plot, under the curve's line) are the same orange, over
    the grey dead zone too."""
    page.select_option("#example", "pie-20")
    page.wait_for_selector("#plot-d canvas")
    img, area = canvas(page, "plot-d")
    colours = []
    for theta in (10.0, 170.0):
        x = area["left"] + theta / 180.0 * area["width"]
        y = area["top"] + area["height"] * 0.9
        colours.append(img[int(y), int(x)])
    for r, g, b in colours:
        assert r > 220 and 150 < g < 225 and b < 140, colours  # orange, not tan or grey
    assert max(abs(a - b) for a, b in zip(*colours)) <= 6  # one colour at both ends
