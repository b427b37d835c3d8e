"""``algrasp batch``: a catalogue directory or archive → reports and a gripper
specification; re-running resumes; the Dask engine gives the same results."""

from __future__ import annotations

import json
import math
import tarfile
from pathlib import Path
from typing import Any

import pytest

from algrasp.cli import main
from algrasp.testing.shapes import rectangle, regular_polygon
from service.catalogue import read_archive, read_catalogue
from service.store import Store


def _catalogue(d: Path) -> Path:
    d.mkdir()
    for i, (w, h) in enumerate([(30.0, 10.0), (20.0, 12.0)]):
        (d / f"rect{i}.json").write_text(json.dumps(dict(rectangle(w, h), name=f"rect{i}")))
    (d / "tri.json").write_text(json.dumps(dict(regular_polygon(3, 10.0), name="tri")))
    (d / "notes.txt").write_text("ignored")
    return d


def _spec(out: Path) -> dict[str, object]:
    return json.loads((out / "gripper_spec.json").read_text())  # type: ignore[no-any-return]


def test_batch_directory_reports_and_resumes(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    cat = _catalogue(tmp_path / "cat")
    out = tmp_path / "out"
    args = ["batch", str(cat), "--out", str(out), "--workers", "1", "--record-dir", str(tmp_path / "records")]
    assert main(args) == 0
    assert {p.name for p in out.iterdir()} >= {"report.md", "results.jsonl", "summary.csv", "gripper_spec.json", "batch.db"}
    spec = _spec(out)
    assert spec["oriented"] == 3 and spec["not_oriented"] == []
    assert spec["jaw_opening_mm"] == pytest.approx(math.hypot(30, 10) + 4.0, rel=1e-9)  # widest part's diagonal + 2×2 mm
    lines = [json.loads(x) for x in (out / "results.jsonl").read_text().splitlines()]
    assert [r["name"] for r in lines] == ["rect0", "rect1", "tri"]
    steps = [s for r in lines for s in r["result"]["plan"]["steps"]]
    # The 100 Hz trajectories stay in the run records; results keep the plan's figures.
    assert steps and all("trajectory" not in s and s["duration_s"] > 0 for s in steps)
    capsys.readouterr()
    assert main(args) == 0  # the same catalogue again: nothing recomputed
    assert "3 of 3 parts already finished" in capsys.readouterr().out
    rows = Store(f"sqlite:///{out / 'batch.db'}").results(_job(out))
    assert [r["attempts"] for r in rows] == [1, 1, 1]
    record = next(iter(sorted((tmp_path / "records").glob("*.mcap"))))
    assert main(["replay", str(record), "--json"]) == 0  # a batch design run replays without differences
    assert json.loads(capsys.readouterr().out)["differences"] == []


def _job(out: Path) -> str:
    store = Store(f"sqlite:///{out / 'batch.db'}")
    jobs = store.jobs(10, 0)
    assert len(jobs) == 1
    return str(jobs[0]["id"])


def test_batch_on_dask_matches_the_local_pool(tmp_path: Path) -> None:
    distributed = pytest.importorskip("distributed")
    cat = _catalogue(tmp_path / "cat")
    archive = tmp_path / "cat.tar.gz"
    with tarfile.open(archive, "w:gz") as tf:
        tf.add(cat, arcname="catalogue")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        assert main(["batch", str(archive), "--out", str(tmp_path / "dask"), "--scheduler", cluster.scheduler_address]) == 0
    assert main(["batch", str(cat), "--out", str(tmp_path / "local"), "--workers", "1"]) == 0
    a, b = _spec(tmp_path / "dask"), _spec(tmp_path / "local")
    assert a == b


def test_catalogue_reading_is_safe(tmp_path: Path) -> None:
    import io
    import zipfile

    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as zf:
        zf.writestr("../../evil.json", json.dumps(rectangle(3, 1)))
        zf.writestr("big.json", " " * 5000)
    entries = read_archive(buf.getvalue(), max_parts=10, max_bytes=10_000)
    assert [n for n, _, _ in entries] == ["rect-3x1", "big"]  # read in memory; "../../" never reaches a path
    assert entries[0][2] is None and "JSON" in str(entries[1][2])
    from algrasp.errors import LimitExceededError, PartDocumentError

    with pytest.raises(LimitExceededError, match="bytes"):
        read_archive(buf.getvalue(), max_parts=10, max_bytes=1000)
    with pytest.raises(LimitExceededError, match="part files"):
        read_archive(buf.getvalue(), max_parts=1, max_bytes=10_000)
    with pytest.raises(PartDocumentError, match="not a zip or tar"):
        read_archive(b"hello", 10, 1000)
    with pytest.raises(PartDocumentError, match="no such directory"):
        read_catalogue(tmp_path / "missing", 10, 1000)
    assert not (tmp_path.parent / "evil.json").exists()


def test_a_batch_part_is_analysed_once_and_each_action_planned_once(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Issue 19/21: the fixture design of one part parses and analyses it once and plans
    each action once (it used to analyse twice and plan three times)."""
    import algrasp.pipeline
    import algrasp.planning.analysis
    import algrasp.planning.plans
    import service.fixture
    import service.work
    from algrasp.testing.shapes import rectangle
    from service.work import design_task

    calls = {"analyse": 0, "plan": 0}

    def counting(name: str, fn: Any) -> Any:
        def wrapped(*a: Any, **k: Any) -> Any:
            calls[name] += 1
            return fn(*a, **k)
        return wrapped

    analyse = counting("analyse", algrasp.planning.analysis.analyse_document)
    plan = counting("plan", algrasp.planning.plans.make_plan)
    for module in (algrasp.planning.analysis, service.work, algrasp.pipeline):
        monkeypatch.setattr(module, "analyse_document", analyse, raising=False)
    for module in (algrasp.planning.plans, service.fixture, algrasp.pipeline):
        monkeypatch.setattr(module, "make_plan", plan, raising=False)
    response, _, err = design_task(dict(rectangle(10.0, 4.0), name="r"), {"min_margin_deg": 0.0}, str(tmp_path), 1)
    assert err is None and response is not None and response["orientable"]
    assert calls == {"analyse": 1, "plan": 2}


def test_batch_limits_none_says_the_jaw_limit_was_not_searched(tmp_path: Path) -> None:
    cat = _catalogue(tmp_path / "cat")
    out = tmp_path / "out"
    assert main(["batch", str(cat), "--out", str(out), "--workers", "1", "--limits", "none",
                 "--record-dir", str(tmp_path / "records")]) == 0
    spec = _spec(out)
    assert spec["oriented"] == 3 and spec["jaw_friction_max"] is None
    assert "not searched for 3 oriented part(s)" in str(spec["jaw_advice"])
    lines = [json.loads(x) for x in (out / "results.jsonl").read_text().splitlines()]
    assert all(not r["result"]["limits"] for r in lines)
