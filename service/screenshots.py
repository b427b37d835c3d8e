"""Screenshots of every workbench page, rendered in headless Chromium at a fixed viewport,
compared with reviewed references so a broken picture fails a test.

``python -m service.screenshots`` renders each page (Part, Plan, Validation, Catalogue,
Runs, Editor, Fences) on a service of its own and compares it with ``tests/service/screenshots/``;
``--update`` writes the renders as the new references *and* as the README's pictures in
``docs/screenshots/`` (review the diff before committing them). What changes from run to
run (run ids, times) is masked. A render differs from its reference when more than
``MAX_CHANGED`` of its pixels differ by more than ``PIXEL_TOLERANCE`` in some channel (or
the sizes differ); the difference image is written beside the render.
"""

from __future__ import annotations

import argparse
import io
import shutil
import sys
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
REFERENCES = ROOT / "tests" / "service" / "screenshots"
README_SHOTS = ROOT / "docs" / "screenshots"
ARTIFACTS = ROOT / "tests" / "artifacts" / "screenshots"
VIEWPORT = {"width": 1280, "height": 900}
PIXEL_TOLERANCE = 40
"""Channel difference (0–255) below which a pixel counts as unchanged (antialiasing)."""
MAX_CHANGED = 0.0015
"""Fraction of changed pixels a render may have and still match its reference (a missing
pair of jaws in the animation changes 0.37 % of the Plan page)."""
SERVER_ENV = {"ALGRASP_WORKERS": "1", "ALGRASP_CELL": "default"}
"""The service the pages are rendered on: the default cell, so the robust images show."""
PIE = "pie-20"


def _part(pg: Any) -> list[Any]:
    pg.click("button[data-page=part]")
    pg.select_option("#example", PIE)
    pg.wait_for_selector("#plot-d canvas")
    return []


def _plan(pg: Any) -> list[Any]:
    """The bracket's robust push-grasp plan (its limits shown), played from 200°."""
    pg.click("button[data-page=part]")
    pg.select_option("#example", "bracket")
    pg.wait_for_selector("#plot-d canvas")
    pg.click("button[data-page=plan]")
    pg.select_option("#action", "push_grasp")
    pg.select_option("#model", "robust")
    pg.click("#plan-btn")
    pg.wait_for_selector("#plan-summary[data-steps]", timeout=120_000)
    pg.fill("#start-deg", "200")
    pg.dispatch_event("#start-deg", "input")
    pg.click("#anim-play")
    pg.wait_for_selector("#anim-final[data-final-range]", timeout=30_000)
    return [pg.locator("#plan-summary .run-id")]


def _validation(pg: Any) -> list[Any]:
    _part(pg)
    pg.click("button[data-page=validation]")
    pg.wait_for_selector("#validate-btn")
    return []


def _catalogue(pg: Any) -> list[Any]:
    pg.click("button[data-page=catalogue]")
    pg.wait_for_selector("#job-submit")
    pg.check("#job-fences")  # the fence options shown enabled
    # The jobs the service holds (ids, times, how many) are not the picture's.
    pg.evaluate("document.querySelectorAll('#jobs-table tbody tr').forEach(r => r.remove())")
    return [pg.locator("#jobs-table tbody")]


def _runs(pg: Any) -> list[Any]:
    _part(pg)  # one run at least
    pg.click("button[data-page=runs]")
    pg.wait_for_selector("#runs-table tbody tr")
    # One row of fixed text: how many runs the service holds, their ids and times are not
    # the picture's (and their widths would move the table's columns).
    pg.evaluate("document.querySelectorAll('#runs-table tbody tr').forEach((r, i) => { if (i > 0) r.remove(); "
                "else r.querySelectorAll('td').forEach(c => { c.textContent = 'x'; }); })")
    return [pg.locator("#runs-table tbody")]


def _editor(pg: Any) -> list[Any]:
    pg.click("button[data-page=part]")
    pg.click("#editor-open")
    box = pg.locator("#editor-canvas").bounding_box()

    def click(x: float, y: float) -> None:
        pg.mouse.click(box["x"] + x / 60 * box["width"], box["y"] + (60 - y) / 60 * box["height"])

    for x, y in [(10, 10), (40, 10), (40, 30), (10, 30)]:
        click(x, y)
    bulge = pg.get_by_label("vertex 2 bulge of the edge to the next vertex", exact=True)
    bulge.fill("1")
    bulge.dispatch_event("change")
    pg.click("#editor-hole")
    for x, y in [(20, 15), (25, 15), (25, 25)]:
        click(x, y)
    pg.mouse.move(0, 0)
    return []


def _fences(pg: Any) -> list[Any]:
    """The battery plate's robust fence design (the tips' turns modelled, an exit guide;
    consecutive fences on one rail: with the fence friction it has no alternating design):
    the API's drawing, the table, the part played along the belt from 200°."""
    pg.click("button[data-page=part]")
    pg.select_option("#example", "battery-plate")
    pg.wait_for_selector("#plot-d canvas")
    pg.click("button[data-page=fences]")
    pg.check("#fence-same-rail")
    pg.click("#fence-btn")
    pg.wait_for_selector("#fence-summary[data-fences]", timeout=120_000)
    pg.wait_for_selector("#fence-final[data-final-range]", timeout=30_000)
    pg.fill("#fence-start", "200")
    pg.dispatch_event("#fence-start", "input")
    pg.evaluate("document.getElementById('fence-final').removeAttribute('data-final-range')")
    pg.click("#fence-play")
    pg.wait_for_selector("#fence-final[data-final-range]", timeout=30_000)
    return []


PAGES: dict[str, Callable[[Any], list[Any]]] = {
    "part": _part, "plan": _plan, "validation": _validation, "catalogue": _catalogue, "runs": _runs, "editor": _editor,
    "fences": _fences,
}


def render(browser: Any, base_url: str, name: str, css: str | None = None) -> bytes:
    """The PNG of one page after its scene (fixed viewport, whole page, masks applied);
    ``css``: a style added to the page (how a test breaks a picture on purpose)."""
    ctx = browser.new_context(viewport=VIEWPORT, base_url=base_url, device_scale_factor=1, reduced_motion="reduce")
    try:
        pg = ctx.new_page()
        pg.goto("/")
        pg.wait_for_selector("body[data-ready=true]")
        if css:
            pg.add_style_tag(content=css)
        masks = PAGES[name](pg)
        pg.mouse.move(0, 0)
        return pg.screenshot(full_page=True, mask=masks, animations="disabled", caret="hide")  # type: ignore[no-any-return]
    finally:
        ctx.close()


@dataclass(frozen=True)
class Comparison:
    name: str
    changed: float  # fraction of pixels changed (1.0 when the sizes differ)
    size: tuple[int, int]
    reference_size: tuple[int, int] | None

    @property
    def ok(self) -> bool:
        return self.reference_size == self.size and self.changed <= MAX_CHANGED

    def __str__(self) -> str:
        if self.reference_size is None:
            return f"{self.name}: no reference (run python -m service.screenshots --update)"
        if self.reference_size != self.size:
            return f"{self.name}: size {self.size} differs from the reference's {self.reference_size}"
        return f"{self.name}: {100 * self.changed:.3f}% of pixels changed (at most {100 * MAX_CHANGED:.2f}%)"


def compare(name: str, png: bytes, reference: Path = REFERENCES, artifacts: Path = ARTIFACTS) -> Comparison:
    """Compare a render with its reference; on a mismatch write the render and a
    difference image (changed pixels red) to ``artifacts``."""
    import numpy as np
    from PIL import Image

    got = np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(np.int16)
    size = (got.shape[1], got.shape[0])
    ref_path = reference / f"{name}.png"
    if not ref_path.exists():
        return Comparison(name, 1.0, size, None)
    want = np.asarray(Image.open(ref_path).convert("RGB")).astype(np.int16)
    ref_size = (want.shape[1], want.shape[0])
    if ref_size != size:
        result = Comparison(name, 1.0, size, ref_size)
    else:
        changed = np.abs(got - want).max(axis=2) > PIXEL_TOLERANCE
        result = Comparison(name, float(changed.mean()), size, ref_size)
        if not result.ok:
            diff = (want // 3).astype(np.uint8)
            diff[changed] = (255, 0, 0)
            artifacts.mkdir(parents=True, exist_ok=True)
            Image.fromarray(diff).save(artifacts / f"{name}-diff.png")
    if not result.ok:
        artifacts.mkdir(parents=True, exist_ok=True)
        (artifacts / f"{name}.png").write_bytes(png)
    return result


def chromium() -> str | None:
    import os

    return os.environ.get("ALGRASP_CHROMIUM") or next(
        (p for p in map(shutil.which, ("chromium", "chromium-browser", "google-chrome")) if p), None)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m service.screenshots", description=__doc__.split("\n\n")[0])
    parser.add_argument("--update", action="store_true", help="write the renders as references and README pictures")
    parser.add_argument("pages", nargs="*", help=f"pages (default: all): {', '.join(PAGES)}")
    args = parser.parse_args(argv)
    unknown = sorted(set(args.pages) - set(PAGES))
    if unknown:
        parser.error(f"unknown page {unknown[0]!r}: choose from {', '.join(PAGES)}")
    from playwright.sync_api import sync_playwright

    from service.launch import start_server

    exe = chromium()
    if exe is None:
        print("no Chromium found (apt-get install chromium, or set ALGRASP_CHROMIUM)", file=sys.stderr)
        return 2
    failed = 0
    with tempfile.TemporaryDirectory() as tmp, sync_playwright() as p:
        server = start_server(Path(tmp), 60.0, **SERVER_ENV)
        browser = p.chromium.launch(executable_path=exe, args=["--no-sandbox", "--disable-gpu"])
        try:
            for name in args.pages or list(PAGES):
                png = render(browser, server.url, name)
                if args.update:
                    for folder in (REFERENCES, README_SHOTS):
                        folder.mkdir(parents=True, exist_ok=True)
                        (folder / f"{name}.png").write_bytes(png)
                    print(f"{name}: written to {REFERENCES.relative_to(ROOT)} and {README_SHOTS.relative_to(ROOT)}")
                else:
                    result = compare(name, png)
                    failed += not result.ok
                    print(("ok   " if result.ok else "FAIL ") + str(result))
        finally:
            browser.close()
            server.kill()
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
