"""A controller team's view (issue 19): a client generated from the live OpenAPI by
openapi-python-client plans the pie and reads typed fields; errors come back typed."""

from __future__ import annotations

import importlib
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.service.conftest import EXAMPLE, Server


@pytest.fixture(scope="module")
def client_pkg(server: Server, tmp_path_factory: pytest.TempPathFactory) -> object:
    import httpx

    d = tmp_path_factory.mktemp("client")
    (d / "openapi.json").write_text(httpx.get(f"{server.url}/openapi.json").text)
    bindir = str(Path(sys.executable).parent)  # the generator formats its output with ruff
    out = subprocess.run([os.path.join(bindir, "openapi-python-client"), "generate", "--path", str(d / "openapi.json"),
                          "--output-path", str(d / "algrasp_client"), "--meta", "none"],
                         capture_output=True, text=True, env={**os.environ, "PATH": bindir + os.pathsep + os.environ["PATH"]},
                         timeout=300)
    assert out.returncode == 0, out.stdout + out.stderr
    assert "plans_v1_plans_post" in out.stdout or (d / "algrasp_client" / "api" / "plans" / "plans_v1_plans_post.py").is_file()
    sys.path.insert(0, str(d))
    try:
        return importlib.import_module("algrasp_client")
    finally:
        sys.path.remove(str(d))


def test_generated_client_plans_the_pie(server: Server, client_pkg: object) -> None:
    from algrasp_client import Client  # type: ignore[import-not-found]
    from algrasp_client.api.plans import plans_v1_plans_post  # type: ignore[import-not-found]
    from algrasp_client.models import ErrorBody, PlanBody, PlanOut  # type: ignore[import-not-found]

    pie = json.loads(EXAMPLE.read_text())
    client = Client(base_url=server.url, timeout=60)
    out = plans_v1_plans_post.sync(client=client, body=PlanBody.from_dict({"part": pie, "action": "push_grasp"}))
    assert isinstance(out, PlanOut)
    assert out.action.value == "push_grasp" and out.verified and len(out.steps) == len(out.to_dict()["steps"]) >= 1
    assert all(isinstance(s.gripper_angle_deg, float) for s in out.steps) and len(out.final_orientations_deg) == 1
    bad = plans_v1_plans_post.sync(client=client, body=PlanBody.from_dict({"part": {"boundary": [[0, 0], [1, 0]]}}))
    assert isinstance(bad, ErrorBody) and bad.error.type_ == "part_document_error" and bad.error.field == "boundary"


def _wait(get: object, job_id: str, client: object) -> object:
    """The job once it is no longer queued or running (its status is the event)."""
    while True:
        job = get.sync(job_id, client=client)  # type: ignore[attr-defined]
        if job.state not in ("queued", "running"):
            return job


def test_generated_client_imports_plans_validates_and_runs_a_job(server: Server, client_pkg: object) -> None:
    """The whole controller flow through the generated client only (issue 33): upload a real
    drawing (a binary file field), plan and validate the part it gives, run a job over it
    and download the job's results and a run's figure (files)."""
    import io

    from algrasp_client import AuthenticatedClient
    from algrasp_client.api.jobs import create_job_v1_jobs_post, job_v1_jobs_job_id_get, results_v1_jobs_job_id_results_get
    from algrasp_client.api.plans import imports_v1_imports_post, plans_v1_plans_post
    from algrasp_client.api.runs import figure_v1_runs_run_id_figure_svg_get
    from algrasp_client.models import BodyImportsV1ImportsPost, JobCreatedOut, PartDocument, PlanBody, PlanOut
    from algrasp_client.models import CreateJobV1JobsPostJobBody as JobBody
    from algrasp_client.types import File

    plate = Path(__file__).parents[1] / "data" / "real" / "landrs-battery-plate.dxf"
    client = AuthenticatedClient(base_url=server.url, token="any", timeout=300)  # keys are off: the token is ignored
    upload = BodyImportsV1ImportsPost(file=File(payload=io.BytesIO(plate.read_bytes()), file_name=plate.name))
    part = imports_v1_imports_post.sync(client=client, body=upload)
    assert isinstance(part, PartDocument), part
    doc = part.to_dict()
    assert len(doc["holes"]) == 12  # the plate's 12 holes (tests/data/real/SOURCES.md)

    body = {"part": doc, "action": "push_grasp", "validate": {"samples": 2, "seed": 1}}
    planned = plans_v1_plans_post.sync(client=client, body=PlanBody.from_dict(body))
    assert isinstance(planned, PlanOut), planned
    assert planned.action.value == "push_grasp" and planned.verified
    validation = planned.to_dict()["validation"]
    assert len(validation["samples"]) == 2 and 0.0 <= validation["agreement"] <= 1.0
    figure = figure_v1_runs_run_id_figure_svg_get.sync(planned.run_id, client=client)
    assert isinstance(figure, File) and figure.payload.read().lstrip().startswith(b"<")

    pie = json.loads(EXAMPLE.read_text())
    created = create_job_v1_jobs_post.sync(client=client, body=JobBody.from_dict({"parts": [pie, doc]}))
    assert isinstance(created, JobCreatedOut), created
    job = _wait(job_v1_jobs_job_id_get, created.id, client)
    assert job.state == "done" and job.progress.finished == 2  # type: ignore[attr-defined]
    results = results_v1_jobs_job_id_results_get.sync(created.id, client=client)
    assert isinstance(results, File)
    rows = [json.loads(line) for line in results.payload.read().decode().splitlines() if line.strip()]
    assert sorted(r["name"] for r in rows) == sorted([pie["name"], doc["name"]])
