"""A recorded validation carries every simulated state, as JSON and as Foxglove scene
and transforms whose log times follow simulation time (marked ``sim``)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from mcap.reader import make_reader

pytest.importorskip("pydrake")

from algrasp.cli import main  # noqa: E402
from algrasp.testing import shapes  # noqa: E402
from tests.algrasp.io.record.test_records import check_record  # noqa: E402

pytestmark = pytest.mark.sim


def test_validation_record_replays_in_foxglove(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    part = tmp_path / "rect.json"
    part.write_text(json.dumps(shapes.rectangle(10.0, 4.0)))
    assert main(["validate", str(part), "--samples", "2", "--json", "--record-dir", str(tmp_path)]) == 0
    out = json.loads(capsys.readouterr().out)
    path = Path(out["record_path"])
    counts = check_record(path)
    assert counts["/scene"] == 2 and counts["/validation"] == 1 and counts["/run"] == 1
    assert counts["/tf"] == counts["/sim/state"] > 2 * 50  # 50 Hz over seconds of simulation per sample
    with open(path, "rb") as f:
        times = [m.log_time for _, c, m in make_reader(f).iter_messages(topics=["/sim/state"])]
        f.seek(0)
        states = [json.loads(m.data) for _, _, m in make_reader(f).iter_messages(topics=["/sim/state"])]
    first = [s for s in states if s["sample"] == 0]
    span_s = (times[len(first) - 1] - times[0]) / 1e9
    assert span_s == pytest.approx(first[-1]["t_s"] - first[0]["t_s"], abs=1e-6)
    assert abs((first[-1]["phi_deg"] - out["samples"][0]["simulated_deg"] + 180) % 360 - 180) < 1e-6
