"""Request bounds (issue 18): the JSON guard against values checked by hand, retention
against a directory of dated files, and a Hypothesis fuzz of non-standard JSON (what
Python, JavaScript and hand-written clients send) on the live server: never a 5xx."""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from algrasp.errors import LimitExceededError, PartDocumentError
from algrasp.io.jsonguard import JsonBounds, parse_json
from service.retention import clean_partials, sweep
from tests.service.conftest import Server


@pytest.mark.parametrize("text, field", [
    ('{"a": NaN}', "body"), ('{"a": [Infinity]}', "body"), ('[-Infinity]', "body"), ('{"a": 1e400}', "body"),
    ('{"a": "\\ud800"}', "body.a"), ('{"\\udc00": 1}', "body (a key)"), ('{"a": ' + "1" * 30 + "}", "body"),
    ("{'a': 1}", "body"), ("", "body"),
])
def test_non_json_values_are_refused_naming_the_field(text: str, field: str) -> None:
    with pytest.raises(PartDocumentError) as err:
        parse_json(text.encode())
    assert err.value.field == field


def test_depth_and_size_bounds() -> None:
    bounds = JsonBounds(max_depth=4, max_string_chars=10, max_nodes=100)
    assert parse_json("[[[1]]]", bounds=bounds) == [[[1]]]
    for text in ("[[[[[1]]]]]", '"' + "x" * 11 + '"', json.dumps(list(range(200))), "[" * 50_000 + "]" * 50_000):
        with pytest.raises(LimitExceededError):
            parse_json(text, bounds=bounds)


def test_retention_deletes_old_then_oldest_and_all_partials(tmp_path: Path) -> None:
    now = time.time()
    for k in range(6):  # one record a day, 1000 bytes each
        p = tmp_path / f"r{k}.mcap"
        p.write_bytes(b"x" * 1000)
        os.utime(p, (now - 86400 * k - 1, now - 86400 * k - 1))
    (tmp_path / "r9.mcap.partial").write_bytes(b"x")
    assert clean_partials(tmp_path) == 1 and not list(tmp_path.glob("*.partial"))
    assert sorted(sweep(tmp_path, 3.5 * 86400, 0, now)) == ["r4", "r5"]  # older than 3.5 days
    assert sweep(tmp_path, 0, 2500, now) == ["r3", "r2"]  # the oldest go until ≤ 2500 bytes
    assert sorted(p.stem for p in tmp_path.glob("*.mcap")) == ["r0", "r1"]
    assert sweep(tmp_path, 0, 0, now) == []  # no limits: nothing goes


_LEAF = st.sampled_from(["NaN", "Infinity", "-Infinity", "1e400", "-1e999", "9" * 400, '"\\ud800"', '"\\udfff x"', "null",
                         "true", "0", "-0.0", "1e-400", '"x"', '""', "1.5", "[]", "{}", '"\\u0000"'])


def _value(depth: int) -> st.SearchStrategy[str]:
    if depth == 0:
        return _LEAF
    inner = _value(depth - 1)
    return st.one_of(_LEAF, st.lists(inner, max_size=4).map(lambda xs: "[" + ",".join(xs) + "]"),
                     st.dictionaries(st.sampled_from(['"boundary"', '"name"', '"part"', '"type"', '"\\ud800"', '"holes"',
                                                      '"radius"', '"gripper"', '"optimise"', '"physics"']),
                                     inner, max_size=4).map(lambda d: "{" + ",".join(f"{k}:{v}" for k, v in d.items()) + "}"))


@given(body=_value(5), path=st.sampled_from(["/v1/analyses", "/v1/plans", "/v1/jobs"]))
@settings(max_examples=150, deadline=None, suppress_health_check=list(HealthCheck), database=None)
def test_fuzz_non_standard_json_is_never_a_5xx(server: Server, body: str, path: str) -> None:
    import httpx

    r = httpx.post(server.url + path, content=body.encode("utf-8", "surrogatepass"),
                   headers={"content-type": "application/json"}, timeout=60)
    assert r.status_code < 500, (body[:300], r.status_code, r.text[:300])
