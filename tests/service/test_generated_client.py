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
