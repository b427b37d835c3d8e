"""The HTTP ``physics`` object (conventions §8): ranges in, limits out, bad ranges a 422
naming the field, a part the ranges cannot orient refused with its limits."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.service.conftest import Server, start_server

ROOT = Path(__file__).resolve().parents[2]
BRACKET = json.loads((ROOT / "algrasp" / "examples" / "bracket.json").read_text())


@pytest.fixture(scope="module")
def real(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    """A service in the default (real) cell: the suite's own server runs in the ideal one."""
    s = start_server(tmp_path_factory.mktemp("real-cell"), ALGRASP_CELL="default")
    yield s
    s.kill()


def test_ranges_in_limits_out(real: Server) -> None:
    body = {"part": BRACKET, "action": "push_grasp", "physics": {"jaw_friction": [0, 0.2]}, "limits": True}
    with real.client() as c:
        r = c.post("/v1/plans", json=body)
    assert r.status_code == 200, r.text
    plan = r.json()
    band = plan["dead_band"]
    assert band["jaw_friction"] == [0, 0.2] and band["placement"] == "any"
    assert band["stall_per_rad"][0] < band["stall_per_rad"][1]  # a range of stall thresholds
    limits = plan["limits"]
    assert {"jaw_friction_max", "support_friction_min", "part_mass_kg_max", "profile_tolerance_max"} <= set(limits)
    jaw = limits["jaw_friction_max"]
    assert jaw["value"] is None or jaw["value"] >= 0.2  # the plan holds at the given range's top
    assert plan["final_uncertainty_deg"] >= 0.1  # never below the simulator's resolution


@pytest.mark.parametrize(("physics", "field"), [
    ({"support_friction": 50}, "support_friction"),
    ({"jaw_friction": [0.3, 0.1]}, "jaw_friction"),
    ({"part_mass_kg": [0.1, 0.2, 0.3]}, "part_mass_kg"),
    ({"placement": "sideways"}, "placement"),
    ({"wobble": 1}, "wobble"),
])
def test_bad_ranges_are_422_naming_the_field(server: Server, physics: dict[str, Any], field: str) -> None:
    with server.client() as c:
        r = c.post("/v1/plans", json={"part": BRACKET, "physics": physics})
    assert r.status_code == 422, r.text
    assert field in json.dumps(r.json())


def test_unorientable_under_the_ranges_is_refused_with_limits(real: Server) -> None:
    """The bracket cannot be squeezed into an orientation lying anywhere between the jaws:
    the refusal says centred placement or a push-grasp would do."""
    with real.client() as c:
        r = c.post("/v1/plans", json={"part": BRACKET, "action": "squeeze"})
    assert r.status_code == 422, r.text
    err = r.json()["error"]
    assert err["type"] == "not_orientable"
    assert err["limits"]["placement_centred"] is True and err["limits"]["push_grasp_orients"] is True
    assert "centred placement" in err["message"] and "push-grasp plan exists" in err["message"]
