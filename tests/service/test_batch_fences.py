"""``algrasp batch --fences`` and the job option ``fences``: every part's conveyor fence
design (or why none exists) in the results and a section of the report."""

from __future__ import annotations

import json
from pathlib import Path

from algrasp.cli import main
from algrasp.testing.shapes import rectangle
from service.models import JobOptions


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
