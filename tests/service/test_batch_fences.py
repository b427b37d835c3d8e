"""``algrasp batch --fences`` and the job option ``fences``: every part's conveyor fence
design (or why none exists) in the results and a section of the report."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from pydantic import ValidationError

import algrasp
from algrasp.cli import main
from algrasp.errors import NotOrientableError
from algrasp.testing.shapes import rectangle
from service.models import JobOptions
from tests.service.conftest import Server, wait_job


def test_batch_designs_fences_per_part(tmp_path: Path) -> None:
    cat = tmp_path / "cat"
    cat.mkdir()
    (cat / "rect.json").write_text(json.dumps(dict(rectangle(30.0, 10.0), name="rect")))
    (cat / "disk.json").write_text(json.dumps({"name": "disk", "boundary": [
        {"type": "arc", "center": [0, 0], "radius": 5, "start_deg": 0, "end_deg": 360}]}))
    out = tmp_path / "out"
    assert main(["batch", str(cat), "--out", str(out), "--workers", "1", "--record-dir", str(tmp_path / "rec"),
                 "--exact", "--fences", "--fence-friction", "0.1,0.2"]) == 0
    rows = {r["name"]: r["result"] for r in map(json.loads, (out / "results.jsonl").read_text().splitlines())}
    rect, disk = rows["rect"]["fences"], rows["disk"]["fences"]
    assert rect["orientable"] and len(rect["fences"]) == 2 and rect["fence_friction"] == [0.1, 0.2]
    assert not disk["orientable"] and disk["reason"] == "no_step"
    section = (out / "report.md").read_text().split("## Conveyor fences", 1)[1]
    rect_row = next(line for line in section.splitlines() if "| rect |" in line)
    assert rect_row.split("|")[3].strip() == "2" and f"{rect['belt_width']:.4g} mm" in rect_row
    assert "no step" in next(line for line in section.splitlines() if "| disk |" in line)


def test_job_options_carry_fences() -> None:
    opts = JobOptions.model_validate({"fences": True, "fence_friction": 0.2}).design()
    assert opts["fences"] is True and opts["fence_friction"] == [0.2]
    try:
        JobOptions.model_validate({"fences": True, "fence_friction": [0.3, 0.1]})
    except ValueError as e:
        assert "fence_friction" in str(e)
    else:
        raise AssertionError("a bad fence friction was accepted")


ROOT = Path(__file__).resolve().parents[2]
PARTS = {"pie-20": json.loads((ROOT / "algrasp" / "examples" / "pie-20.json").read_text()),
         "tri": json.loads((ROOT / "tests" / "data" / "fences" / "triangle.json").read_text()),
         "rect": dict(rectangle(30.0, 10.0), name="rect")}
"""Pie-20 and the triangle are refused with alternating fences (tip turns modelled) and
designed with ``same_rail``: a batch that dropped the option would not match."""


def _catalogue(d: Path, names: list[str]) -> Path:
    d.mkdir()
    for n in names:
        (d / f"{n}.json").write_text(json.dumps(PARTS[n]))
    return d


def _fences(out: Path) -> dict[str, dict[str, Any]]:
    return {r["name"]: r["result"]["fences"] for r in map(json.loads, (out / "results.jsonl").read_text().splitlines())}


def _document(result: dict[str, Any]) -> dict[str, Any]:
    """A part's fence result less what the batch adds: ``orientable`` and ``options``."""
    return {k: v for k, v in result.items() if k not in ("orientable", "options")}


FRICTION = [0.0, 0.03]
"""The fence friction of the same-rail jobs: over 0.1–0.3 pie-20 and the triangle have no
design (pie-20's rest on its arc moves; conventions §9)."""


def _api(name: str, **options: Any) -> dict[str, Any]:
    return json.loads(json.dumps(algrasp.fences(PARTS[name], exact=True, **options).to_dict(follow=False)))  # type: ignore[no-any-return]


def test_batch_same_rail_gives_the_apis_design_per_part(tmp_path: Path) -> None:
    """``--same-rail``: every part's fence document is ``algrasp.fences(part, same_rail=True)``'s
    (fence margin 1°: the batch's default margin 0 raised to the fences' 1°), the options
    are echoed per part, and the report says "same rail"."""
    out = tmp_path / "out"
    assert main(["batch", str(_catalogue(tmp_path / "cat", ["pie-20", "tri", "rect"])), "--out", str(out), "--workers",
                 "1", "--record-dir", str(tmp_path / "rec"), "--exact", "--fences", "--same-rail", "--fence-friction", "0,0.03"]) == 0
    rows = _fences(out)
    for name in ("pie-20", "tri", "rect"):
        assert rows[name]["orientable"] is True
        assert _document(rows[name]) == _api(name, same_rail=True, fence_friction=FRICTION)
        assert rows[name]["options"] == {"fence_friction": FRICTION, "belt_width": None, "min_margin_deg": 1.0,
                                         "exit_steepness_deg": 2.0, "exit_turns": True, "same_rail": True}
    for name in ("pie-20", "tri"):  # refused with alternating rails: the option made the design
        with pytest.raises(NotOrientableError):
            algrasp.fences(PARTS[name], exact=True, fence_friction=FRICTION)
        sides = [f["side"] for f in rows[name]["fences"]]
        assert any(a == b for a, b in zip(sides, sides[1:]))
    section = (out / "report.md").read_text().split("## Conveyor fences", 1)[1]
    assert "consecutive fences on either rail (same rail)" in section and "tip modelled" in section


def test_batch_berretty_model_and_belt_options_per_part(tmp_path: Path) -> None:
    """``--no-exit-turns --exit-steepness-deg 3 --fence-min-margin-deg 2 --belt-width 80``: the
    API's design with those keywords per part; the rectangle's design needs a wider belt
    (the API's least width, > 80 mm), so its fences are refused by ``belt_width`` and its
    gripper plan stands."""
    out = tmp_path / "out"
    opts = {"exit_turns": False, "exit_steepness_deg": 3.0, "min_margin_deg": 2.0, "fence_friction": [0.0, 0.1]}
    assert main(["batch", str(_catalogue(tmp_path / "cat", ["pie-20", "rect"])), "--out", str(out), "--workers", "1",
                 "--record-dir", str(tmp_path / "rec"), "--exact", "--fences", "--no-exit-turns",
                 "--exit-steepness-deg", "3", "--fence-min-margin-deg", "2", "--belt-width", "80", "--fence-friction", "0,0.1"]) == 0
    rows = _fences(out)
    assert _document(rows["pie-20"]) == _api("pie-20", belt_width=80.0, **opts)
    least = _api("rect", **opts)["belt_width"]
    assert least > 80.0
    rect = rows["rect"]
    assert (rect["orientable"], rect["reason"]) == (False, "belt_width") and f"at least {least:.4g} mm" in rect["message"]
    assert rect["options"] == {"fence_friction": [0.0, 0.1], "belt_width": 80.0, "min_margin_deg": 2.0,
                               "exit_steepness_deg": 3.0, "exit_turns": False, "same_rail": False}
    results = {r["name"]: r["result"] for r in map(json.loads, (out / "results.jsonl").read_text().splitlines())}
    assert results["rect"]["orientable"] is True  # the gripper plan
    section = (out / "report.md").read_text().split("## Conveyor fences", 1)[1]
    assert "fences alternating rails; Berretty model" in section and "exit guide at 3° to the belt" in section
    assert "fence margins ≥ 2°" in section and "belt width 80 (each part's unit)" in section


@pytest.mark.parametrize(("flags", "named"), [
    (["--same-rail"], "--same-rail: needs --fences"),
    (["--no-exit-turns"], "--no-exit-turns: needs --fences"),
    (["--belt-width", "50"], "--belt-width: needs --fences"),
    (["--fences", "--exit-steepness-deg", "20"], "--exit-steepness-deg: expected 0 < β_e ≤ 10°"),
    (["--fences", "--exit-steepness-deg", "0"], "--exit-steepness-deg: expected 0 < β_e ≤ 10°"),
    (["--fences", "--belt-width", "-1"], "--belt-width: expected a width > 0"),
    (["--fences", "--fence-min-margin-deg", "45"], "--fence-min-margin-deg: must be in [0, 45)"),
    (["--fences", "--fence-friction", "0.3,0.1"], "--fence-friction: expected 0 ≤ lo ≤ hi")])
def test_batch_refuses_bad_fence_flags_by_name(flags: list[str], named: str, tmp_path: Path,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "out"
    assert main(["batch", str(_catalogue(tmp_path / "cat", ["rect"])), "--out", str(out), "--workers", "1",
                 *flags]) == 2
    assert capsys.readouterr().err.startswith(f"algrasp: error: {named}")
    assert not (out / "batch.db").exists()  # refused before any job was made


@pytest.mark.parametrize(("options", "field"), [
    ({"same_rail": True}, "same_rail"), ({"exit_turns": False}, "exit_turns"), ({"belt_width": 50}, "belt_width"),
    ({"fences": True, "exit_steepness_deg": 20}, "exit_steepness_deg"),
    ({"fences": True, "same_rail": "sometimes"}, "same_rail"), ({"fences": True, "belt_width": 0}, "belt_width"),
    ({"fences": True, "fence_min_margin_deg": -1}, "fence_min_margin_deg"),
    ({"fences": True, "fence_friction": [0.3, 0.1]}, "fence_friction")])
def test_job_options_name_a_bad_fence_option(options: dict[str, Any], field: str) -> None:
    with pytest.raises(ValidationError) as err:
        JobOptions.model_validate(options)
    assert err.value.errors()[0]["loc"] == (field,)


def test_http_job_same_rail_per_part_and_bad_options_422(server: Server) -> None:
    """``POST /v1/jobs`` with ``fences`` and ``same_rail``: each part's fence document is the
    API's; a bad fence option is a 422 naming ``options.<field>`` (JSON and archive bodies)."""
    with server.client() as c:
        r = c.post("/v1/jobs", json={"parts": [PARTS["pie-20"], PARTS["tri"]],
                                     "options": {"exact": True, "fences": True, "same_rail": True,
                                                 "fence_friction": FRICTION}})
        assert r.status_code == 202, r.text
        job = wait_job(c, r.json()["id"])
        lines = [json.loads(x) for x in c.get(f"/v1/jobs/{job['id']}/results").text.splitlines()]
        bad = [c.post("/v1/jobs", json={"parts": [PARTS["tri"]], "options": o}) for o in
               ({"fences": True, "exit_steepness_deg": 11}, {"same_rail": True}, {"fences": True, "belt_width": -3})]
        archive = c.post("/v1/jobs/archives", files={"archive": ("c.zip", b"PK", "application/zip")},
                         data={"options": json.dumps({"fences": True, "fence_min_margin_deg": 90})})
    assert job["state"] == "done" and [r["name"] for r in lines] == ["pie-20", "tri"]
    for r in lines:
        assert _document(r["result"]["fences"]) == _api(r["name"], same_rail=True, fence_friction=FRICTION)
        assert r["result"]["fences"]["options"]["same_rail"] is True
    for resp, field in zip(bad, ("exit_steepness_deg", "same_rail", "belt_width")):
        assert resp.status_code == 422 and resp.json()["error"]["field"] == f"body.options.{field}", resp.text
    assert archive.status_code == 422, archive.text
    assert archive.json()["error"]["field"] == "options.fence_min_margin_deg"


def test_dask_batch_passes_the_fence_options(tmp_path: Path) -> None:
    """The Dask engine designs with the job's fence options as the local pool does."""
    distributed = pytest.importorskip("distributed")
    cat = _catalogue(tmp_path / "cat", ["pie-20", "tri"])
    flags = ["--exact", "--fences", "--same-rail", "--exit-steepness-deg", "4", "--fence-friction", "0,0.03"]
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        assert main(["batch", str(cat), "--out", str(tmp_path / "dask"), "--scheduler", cluster.scheduler_address,
                     "--record-dir", str(tmp_path / "rec"), *flags]) == 0
    rows = _fences(tmp_path / "dask")
    for name in ("pie-20", "tri"):
        assert _document(rows[name]) == _api(name, same_rail=True, exit_steepness_deg=4.0, fence_friction=FRICTION)
        assert rows[name]["options"]["exit_steepness_deg"] == 4.0
