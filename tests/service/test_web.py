"""What the workbench needs from the public API: drawing samples, examples, playback of a
validated run, the Foxglove layout, a job's gripper specification, and the page itself
(small, no CDN)."""

from __future__ import annotations

import hashlib
import json
import math
import re
from typing import Any

import pytest

from service.web import STATIC
from tests.service.conftest import Server, wait_job

pytestmark = pytest.mark.filterwarnings("ignore::DeprecationWarning")


def test_page_and_scripts_are_served_small_and_offline(server: Server) -> None:
    with server.client() as c:
        page = c.get("/")
        assert page.status_code == 200 and "text/html" in page.headers["content-type"]
        assets = re.findall(r'(?:src|href)="(/ui/[^"]+)"', page.text)
        js = [f"/ui/{p.name}" for p in STATIC.glob("*.js")]
        total = len(page.content)
        for path in {*assets, *js}:
            r = c.get(path)
            assert r.status_code == 200, path
            total += len(r.content)
            # no CDN: nothing is fetched from another host
            assert not re.search(r"""(?:src|href|import|from)\s*[=(]?\s*["']https?://""", r.text), path
        assert total <= 1_000_000, f"the page weighs {total} bytes"


def test_the_vendored_plotting_library_is_served_as_its_source_says(server: Server) -> None:
    """uPlot's files are linked from the page, served by the app (no CDN) and are the
    npm package's bytes: their sha256 are the ones SOURCE.md lists."""
    source = (STATIC / "vendor" / "uplot" / "SOURCE.md").read_text()
    with server.client() as c:
        page = c.get("/").text
        for name in ("uPlot.iife.min.js", "uPlot.min.css"):
            assert f'"/ui/vendor/uplot/{name}"' in page
            r = c.get(f"/ui/vendor/uplot/{name}")
            assert r.status_code == 200
            assert f"`{hashlib.sha256(r.content).hexdigest()}`" in source, name
    assert "1.6.32" in source and "MIT" in (STATIC / "vendor" / "uplot" / "LICENSE").read_text()


def test_analysis_samples_are_the_closed_form(server: Server) -> None:
    rect = {"name": "rect", "polygon": [[0, 0], [4, 0], [4, 2], [0, 2]]}
    with server.client() as c:
        plain = c.post("/v1/analyses", json=rect).json()
        out = c.post("/v1/analyses?samples=36", json=rect).json()
        assert "curves" not in plain and "geometry" not in plain  # asked for only
        assert c.post("/v1/analyses?samples=100000", json=rect).status_code == 422
    th = [math.radians(t) for t in out["curves"]["theta_deg"]]
    assert len(th) == 36
    for t, d in zip(th, out["curves"]["diameter"]):
        assert math.isclose(d, 4 * abs(math.sin(t)) + 2 * abs(math.cos(t)), rel_tol=1e-6)
    assert sorted(map(tuple, out["geometry"]["hull"])) == [(0, 0), (0, 2), (4, 0), (4, 2)]
    assert out["geometry"]["center_of_mass"] == [2, 1]


def test_examples_layout_and_health(server: Server, pie: dict[str, Any]) -> None:
    with server.client() as c:
        examples = c.get("/v1/examples").json()["examples"]
        assert {"name": "pie-20", "kind": "paper", "part": pie} in examples
        layout = c.get("/v1/layouts/foxglove.json").json()
        assert c.get("/healthz").json()["auth_required"] is False
    # the layout's panels read the topics the recorder writes, and every panel is placed
    topics = {cfg.get("topicPath") for cfg in layout["configById"].values()} - {None}
    paths = {p["value"].split(".")[0] for cfg in layout["configById"].values() for p in cfg.get("paths", [])}
    assert topics | paths == {"/plan", "/validation", "/run", "/sim/state"}
    placed = set(re.findall(r'"([A-Za-z0-9 ]+![a-z]+)"', json.dumps(layout["layout"])))
    assert placed == set(layout["configById"])


@pytest.mark.sim
def test_playback_of_a_validated_run(server: Server, pie: dict[str, Any]) -> None:
    with server.client() as c:
        plan = c.post("/v1/plans", json={"part": pie, "validate": {"samples": 2}}).json()
        pb = c.get(f"/v1/runs/{plan['run_id']}/playback?points=50").json()
        assert c.get("/v1/runs/20000101T000000Z-00000000/playback").status_code == 404
    assert pb["part"] == pie and pb["plan"]["steps"] == [{k: s[k] for k in s} for s in plan["steps"]]
    assert len(pb["trajectories"]) == 2
    for tr, sample in zip(pb["trajectories"], pb["validation"]["samples"]):
        n = len(tr["t_s"])
        assert 2 <= n <= 50 and all(len(tr[k]) == n for k in ("phi_deg", "x", "y", "lower_jaw", "higher_jaw"))
        assert tr["t_s"] == sorted(tr["t_s"])
        # the sample starts where the validation says and ends where it says (deg, mod 360)
        assert math.isclose(tr["phi_deg"][0] % 360, sample["initial_deg"] % 360, abs_tol=0.5)
        end = (tr["phi_deg"][-1] - sample["simulated_deg"] + 180) % 360 - 180
        assert abs(end) < 0.5
        # the jaws close on the part: their tightest gap is one of the pie's widths, d ∈ [3.2, 5] mm
        gap = min(h - lo for h, lo in zip(tr["higher_jaw"], tr["lower_jaw"]))
        assert 3.0 < gap <= 5.0 + 0.05


def test_gripper_specification_of_a_job(server: Server, pie: dict[str, Any]) -> None:
    disk = {"name": "disk", "boundary": [{"type": "arc", "center": [0, 0], "radius": 3, "start_deg": 0, "end_deg": 360}]}
    with server.client() as c:
        job = c.post("/v1/jobs", json={"parts": [pie, disk]}).json()
        wait_job(c, job["id"])
        spec = c.get(f"/v1/jobs/{job['id']}/gripper").json()
        assert c.get("/v1/jobs/0123456789abcdef0123456789abcdef/gripper").status_code == 404
    assert spec["parts"] == 2 and spec["oriented"] == 1
    assert [f["name"] for f in spec["not_oriented"]] == ["disk"]
    assert spec["jaw_opening_mm"] >= 5.0  # wider than the pie's largest width (its radius, 5 mm)


def test_the_gripper_profile_example_on_the_page_is_a_valid_profile() -> None:
    """The plan page's placeholder is what a new user copies: it must be accepted
    (it once named a key that does not exist)."""
    import html
    import re

    from optimisation.profile import profile_from_dict
    from service.web import STATIC

    page = (STATIC / "index.html").read_text()
    m = re.search(r"id=\"gripper\"[^>]*placeholder='([^']*)'", page)
    assert m is not None
    profile = profile_from_dict(json.loads(html.unescape(m.group(1))))
    assert profile.jaw_max_jerk_m_s3 == 20.0


def test_a_sheet_and_its_documents_in_one_upload(server: Server) -> None:
    """``list=true&documents=N``: the listing and the first N parts' documents, each the
    document ``part=K`` gives; ``units`` names the drawing's unit (no unit warning then)."""
    from pathlib import Path

    drawing = Path(__file__).resolve().parents[1] / "data" / "real" / "koppi-involute-teeth-20-multiple.dxf"
    files = {"file": (drawing.name, drawing.read_bytes())}
    with server.client() as c:
        sheet = c.post("/v1/imports", files=files, data={"list": "true", "documents": "3"}).json()
        assert len(sheet["parts"]) == 10 and len(sheet["documents"]) == 3
        one = c.post("/v1/imports", files=files, data={"part": "2"}).json()
        assert sheet["documents"][2] == one
        inches = c.post("/v1/imports", files=files, data={"list": "true", "documents": "1", "units": "in"}).json()
        assert inches["documents"][0]["units"] == "in" and not any("INSUNITS" in w for w in inches["warnings"])
        assert c.post("/v1/imports", files=files, data={"list": "true", "units": "furlong"}).status_code == 422


def test_engrave_colours_go_with_an_upload(server: Server) -> None:
    """``engrave_colours``: a panel cut in blue with a red rectangle on its corner is one
    part as the drawing says (red judged engraving), two with ``none``; a bad colour is a
    422 naming the field (as a bad unit is)."""
    svg = (b'<svg xmlns="http://www.w3.org/2000/svg" width="300" height="300" viewBox="0 0 300 300">'
           b'<rect x="0" y="0" width="200" height="100" fill="none" stroke="#0000ff"/>'
           b'<rect x="0" y="0" width="50" height="40" fill="none" stroke="#ff0000"/></svg>')
    files = {"file": ("etch.svg", svg)}
    with server.client() as c:
        assert len(c.post("/v1/imports", files=files, data={"list": "true"}).json()["parts"]) == 1
        two = c.post("/v1/imports", files=files, data={"list": "true", "engrave_colours": "none"}).json()
        assert len(two["parts"]) == 2
        bad = c.post("/v1/imports", files=files, data={"list": "true", "engrave_colours": "red"})
        assert bad.status_code == 422 and "engrave_colours" in bad.text


def test_a_job_says_the_archive_files_it_does_not_read(server: Server, pie: dict[str, Any]) -> None:
    import io
    import zipfile

    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        z.writestr("pie.json", json.dumps(pie))
        z.writestr("notes/README.txt", "not a part")
        z.writestr(".hidden.json", "{}")
    with server.client() as c:
        job = c.post("/v1/jobs", files={"archive": ("c.zip", buf.getvalue())}).json()
        assert job["total"] == 1
        assert any(w.startswith("notes/README.txt: not a part file") for w in job["ignored"])
        assert any(w.startswith(".hidden.json: a hidden file") for w in job["ignored"])
        wait_job(c, job["id"])
