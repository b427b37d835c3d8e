"""The workbench on loopback in headless Chromium: first paint of the part page, time
until it is usable (examples loaded), time until an example's analysis is drawn, and the
page's weight (every byte the browser fetched for the page, API answers excluded).

Targets (issue 20): first paint ≤ 1 s, weight ≤ 1 MB. Needs a Chromium (``chromium`` on
the PATH or ``ALGRASP_CHROMIUM``)."""

from __future__ import annotations

import os
import shutil
import statistics
import sys
import tempfile
from pathlib import Path

from service.launch import start_server

RUNS = 5


def main() -> None:
    exe = os.environ.get("ALGRASP_CHROMIUM") or shutil.which("chromium") or shutil.which("chromium-browser")
    if exe is None:
        sys.exit("no Chromium: apt-get install chromium (or set ALGRASP_CHROMIUM)")
    from playwright.sync_api import sync_playwright

    server = start_server(Path(tempfile.mkdtemp(prefix="algrasp-bench-web-")))
    paint, ready, drawn, weight = [], [], [], 0
    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=exe, args=["--no-sandbox"])
            for _ in range(RUNS):
                ctx = browser.new_context()
                page = ctx.new_page()
                sizes: dict[str, int] = {}
                page.on("response", lambda r, s=sizes: s.__setitem__(r.url, len(r.body())) if "/v1/" not in r.url
                        and r.request.method == "GET" and r.ok else None)
                page.goto(server.url + "/")
                page.wait_for_selector("body[data-ready=true]")
                paint.append(page.evaluate("performance.getEntriesByName('first-contentful-paint')[0].startTime"))
                ready.append(page.evaluate("performance.now()"))
                page.select_option("#example", "pie-20")
                page.wait_for_selector("#plot-d canvas")
                drawn.append(page.evaluate("performance.now()"))
                weight = sum(sizes.values())
                ctx.close()
            browser.close()
    finally:
        server.kill()
    print(f"workbench on loopback, {RUNS} cold page loads (new browser context each):")
    print(f"  first contentful paint  p50 {statistics.median(paint):6.0f} ms  max {max(paint):6.0f} ms  (target ≤ 1000 ms)")
    print(f"  usable (examples)       p50 {statistics.median(ready):6.0f} ms")
    print(f"  pie analysed and drawn  p50 {statistics.median(drawn):6.0f} ms")
    print(f"  page weight             {weight / 1024:8.1f} KiB  (target ≤ 1024 KiB; {len(sizes)} files)")


if __name__ == "__main__":
    main()
