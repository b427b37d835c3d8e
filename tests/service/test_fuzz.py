"""Schemathesis fuzzes every operation of the OpenAPI schema (bodies, paths, queries,
both job content types): no request may get a 5xx, and every error body conforms to the
documented ``ErrorBody``; every response conforms to its documented schema.

Cases are drawn from schemathesis' per-operation Hypothesis strategies and sent to the
real server (its pytest plugin does not support this pytest yet)."""

from __future__ import annotations

from typing import Any

import pytest
import schemathesis
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from schemathesis.specs.openapi.checks import response_schema_conformance

from service.contract import ErrorBody
from tests.service.conftest import Server

EXAMPLES = 40


@pytest.fixture(scope="session")
def operations(server: Server) -> list[Any]:
    schema = schemathesis.openapi.from_url(f"{server.url}/openapi.json")
    return [r.ok() for r in schema.get_all_operations()]


def test_schema_covers_every_endpoint(operations: list[Any]) -> None:
    paths = {op.path for op in operations}
    assert {"/v1/analyses", "/v1/plans", "/v1/runs", "/v1/runs/{run_id}", "/v1/runs/{run_id}/record",
            "/v1/runs/{run_id}/figure.svg", "/v1/jobs", "/v1/jobs/{job_id}", "/v1/jobs/{job_id}/results",
            "/healthz", "/metrics"} <= paths


def test_no_server_errors(operations: list[Any], server: Server) -> None:
    strategy = st.one_of([op.as_strategy() for op in operations])

    @given(case=strategy)
    @settings(max_examples=EXAMPLES * len(operations), deadline=None, suppress_health_check=list(HealthCheck), database=None)
    def check(case: Any) -> None:
        response = case.call(base_url=server.url, timeout=120)
        assert response.status_code < 500, f"{case.method} {case.formatted_path}: {response.status_code} {response.text[:500]}"
        if response.status_code >= 400:  # every error body is the documented ErrorBody
            ErrorBody.model_validate(response.json())
        case.validate_response(response, checks=[response_schema_conformance])  # and every body its schema

    check()
