"""``make run``: ``algrasp serve`` on its embedded defaults plans the example part at
start-up, as a client's request would be planned, then serves. Every other test server
starts with ``--no-example``; this start-up path once failed (the warm-up handed the plan
task a dict where the route hands it a checked request) and no test saw it."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from service.commands import example_part
from service.launch import start_example_server


def test_make_run_plans_the_example_part_then_serves(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from algrasp.planning.analysis import analyse_document
    from algrasp.planning.plans import make_plan

    monkeypatch.delenv("ALGRASP_CELL", raising=False)  # the embedded default cell, as `make run` has it
    # Start-up ends once the warm-up plan is made: a liveness bound, not a figure.
    server = start_example_server(tmp_path, 600.0)
    try:
        log = "".join(p.read_text() for p in tmp_path.glob("server-*.log"))
        assert "Traceback" not in log, log
        said = re.search(r"planned the example part '(\w+)': (\d+)-step push-grasp plan, cycle ([\d.]+) s, run (\S+)", log)
        assert said is not None, log
        name, steps, cycle_s, run_id = said.group(1), int(said.group(2)), float(said.group(3)), said.group(4)
        doc = example_part()
        assert name == doc["name"] and cycle_s > 0.0
        assert steps == len(make_plan(analyse_document(doc), "push_grasp").steps)  # the core's plan in the default cell
        assert "algrasp service ready" in log
        with server.client() as c:
            run = c.get(f"/v1/runs/{run_id}")
            assert run.status_code == 200, run.text
            row = run.json()
            assert (row["action"], row["part_name"], row["steps"], row["status"]) == ("push_grasp", name, steps, "ok")
            assert row["cycle_time_s"] == pytest.approx(cycle_s, abs=0.01) and row["record"] is not None
            r = c.post("/v1/plans", json={"part": doc, "action": "push_grasp"})  # and it serves: the same plan
            assert r.status_code == 200, r.text
            assert len(r.json()["steps"]) == steps
    finally:
        server.kill()
