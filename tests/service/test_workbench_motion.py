"""The Plan page's animation follows the plan's own images from the API (issue 35): one
uncertainty wedge per action, ending where the core's set-valued plan says the part ends
from that start, and the limits the plan carries shown. The page has no planner of its
own (``geom.js`` no longer predicts)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.service.test_workbench import browser, chromium, page, plan_in_page, server  # noqa: F401

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(chromium() is None, reason="browser tests skipped: no Chromium found"),
]

ROOT = Path(__file__).resolve().parents[2]
BRACKET = ROOT / "algrasp" / "examples" / "bracket.json"


def play_from(pg: Any, start: int) -> list[dict[str, Any]]:
    """Set φ₀, play, and collect every wedge the page drew (step, lo, hi) until the end."""
    pg.evaluate("""() => {
        window.__wedges = [];
        new MutationObserver(() => {
            const w = document.querySelector('#anim-view path.wedge');
            if (!w) return;
            const d = w.dataset;
            window.__wedges.push({step: +d.step, lo: +d.lo, hi: +d.hi, done: d.done === 'true'});
        }).observe(document.getElementById('anim-view'), {childList: true});
    }""")
    pg.fill("#start-deg", str(start))
    pg.dispatch_event("#start-deg", "input")
    pg.click("#anim-play")
    pg.wait_for_selector("#anim-final[data-final-range]", timeout=30_000)
    return pg.evaluate("window.__wedges")  # type: ignore[no-any-return]


def test_the_animation_follows_the_robust_plans_own_images(page: Any) -> None:  # noqa: F811
    from algrasp import plan as make_plan

    page.select_option("#example", "bracket")
    page.wait_for_selector("#plot-d canvas")
    with page.expect_request(lambda r: r.url.endswith("/v1/plans")) as req:
        doc = plan_in_page(page, "push_grasp", "robust")
    body = req.value.post_data_json
    assert doc["model"] == "robust" and doc["images"]["pieces"]
    assert all(s["image_deg"] for s in doc["steps"])  # the API says where each action can leave the part
    start = 200
    wedges = play_from(page, start)
    ends = {w["step"]: (w["lo"], w["hi"]) for w in wedges if w["done"]}
    assert sorted(ends) == list(range(1, len(doc["steps"]) + 1))  # one wedge per action
    # the core's robust plan, from the same start: the hull after each action
    core = make_plan(json.loads(BRACKET.read_text()), action="push_grasp", exact=False,
                     physics=body.get("physics") or None)
    assert core.to_dict()["final_orientations_deg"] == pytest.approx(doc["final_orientations_deg"])
    for k in range(1, len(core.steps) + 1):
        lo, hi = core.run_set(np.radians([start]), np.radians([start]), k)
        got = ends[k]
        assert (got[1] - got[0]) == pytest.approx(math.degrees(hi[0] - lo[0]), abs=1e-6)
        assert ((got[0] - math.degrees(lo[0]) + 180) % 360 - 180) == pytest.approx(0.0, abs=1e-6)
    assert page.get_attribute("#anim-final", "data-claimed") == "true"
    # the limits the plan carries, one row each (the headline: the largest jaw friction)
    rows = page.locator("#plan-limits-table tr[data-limit]")
    assert rows.count() == len([v for v in doc["limits"].values() if isinstance(v, dict) and "value" in v]) >= 1
    assert "largest jaw friction" in page.inner_text("#plan-limits-table")


def test_an_exact_plan_ends_at_the_cores_orientation_and_geom_has_no_planner(page: Any) -> None:  # noqa: F811
    from algrasp import plan as make_plan

    page.select_option("#example", "pie-20")
    page.wait_for_selector("#plot-d canvas")
    doc = plan_in_page(page, "squeeze", "exact")
    wedges = play_from(page, 77)
    final = [w for w in wedges if w["done"] and w["step"] == len(doc["steps"])][-1]
    assert final["hi"] - final["lo"] == pytest.approx(0.0, abs=1e-9)  # exact: a point, no wedge
    core = make_plan(json.loads((ROOT / "algrasp" / "examples" / "pie-20.json").read_text()), action="squeeze", exact=True)
    want = math.degrees(float(core.run(np.radians([77.0]))[0])) % 360
    assert float(page.get_attribute("#anim-final", "data-final-deg")) == pytest.approx(want, abs=1e-6)
    geom = (ROOT / "service" / "static" / "geom.js").read_text()
    assert "function predict" not in geom and "function transfer" not in geom
