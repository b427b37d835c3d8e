"""Every record the service writes — analyses, plans (optimised), batch designs, failed
runs — validates against its channel's schema, which is derived from the typed documents
(issue 33: a ``design`` run's ``/request`` once failed its own schema)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from mcap.reader import make_reader

from algrasp.io.record.schemas import TOPICS
from tests.algrasp.io.record.test_records import check_record
from tests.service.conftest import ROOT, Server, wait_job

FIG11 = json.loads((ROOT / "algrasp" / "examples" / "fig11-cubic.json").read_text())


def _commands(path: Path) -> set[str]:
    with open(path, "rb") as f:
        return {json.loads(m.data)["command"] for _, c, m in make_reader(f).iter_messages(topics=["/request"])}


def test_every_service_record_validates(server: Server, pie: dict[str, Any]) -> None:
    exact = {"exact": True}  # the paper's model: the Fig. 11 part is orientable there by either action
    with server.client() as c:
        assert c.post("/v1/analyses", json=pie).status_code == 200
        r = c.post("/v1/plans", json={"part": pie, "action": "push-grasp", "optimise": True, **exact})
        assert r.status_code == 200, r.text
        assert c.post("/v1/plans", json={"part": {"polygon": [[0, 0], [1, 0], [2, 0]]}}).status_code == 422
        job = c.post("/v1/jobs", json={"parts": [FIG11, dict(pie, name="pie")], "options": exact})
        assert job.status_code == 202, job.text
        assert wait_job(c, job.json()["id"])["state"] == "done"
    records = sorted(server.log_dir.rglob("*.mcap"))
    topics: set[str] = set()
    commands: set[str] = set()
    for path in records:
        topics |= set(check_record(path))
        commands |= _commands(path)
    assert {"analyze", "plan", "design"} <= commands
    # /validation, /sim/state: tests/algrasp/io/record/test_sim_record.py; the fence ones: tests/algrasp/sim/test_belt.py
    assert set(TOPICS) - {"/validation", "/sim/state", "/fences", "/fence_validation"} <= topics
