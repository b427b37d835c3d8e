"""A plan-only record (no validation) carries a Foxglove scene: ``/scene`` (the part's
outline and the jaws) and ``/tf`` with one frame per action, the part at the plan's own
outcome of that action between touching jaws (issue 35). Read back with ``mcap``."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from foxglove_schemas_protobuf.FrameTransforms_pb2 import FrameTransforms
from foxglove_schemas_protobuf.SceneUpdate_pb2 import SceneUpdate
from mcap.reader import make_reader

from algrasp.cli import main

EXAMPLES = Path(__file__).resolve().parents[4] / "algrasp" / "examples"


def _yaw(q: object) -> float:
    return 2.0 * math.atan2(q.z, q.w)  # type: ignore[attr-defined]


@pytest.mark.parametrize(("name", "action", "model"), [("pie-20", "squeeze", ["--exact"]), ("bracket", "push_grasp", [])])
def test_a_plan_record_shows_the_part_at_each_outcome(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                      name: str, action: str, model: list[str]) -> None:
    from algrasp import plan as make_plan

    part = EXAMPLES / f"{name}.json"
    assert main(["plan", str(part), "--action", action, *model, "--json", "--record-dir", str(tmp_path)]) == 0
    out = json.loads(capsys.readouterr().out)
    with open(out["record_path"], "rb") as f:
        msgs = [(c.topic, m) for _, c, m in make_reader(f).iter_messages()]
    topics = {t for t, _ in msgs}
    assert {"/scene", "/tf", "/plan"} <= topics and "/sim/state" not in topics and "/validation" not in topics
    scenes = [SceneUpdate.FromString(m.data) for t, m in msgs if t == "/scene"]
    assert len(scenes) == 1 and {e.id for e in scenes[0].entities} == {"part", "jaw_lower", "jaw_higher"}
    assert len(scenes[0].entities[0].lines[0].points) >= 3
    frames = [FrameTransforms.FromString(m.data) for t, m in msgs if t == "/tf"]
    times = [m.log_time for t, m in msgs if t == "/tf"]
    plan_doc = next(json.loads(m.data) for t, m in msgs if t == "/plan")
    assert len(frames) == len(plan_doc["steps"]) + 1  # the start, then each action's outcome
    assert all(b - a == 1_000_000_000 for a, b in zip(times, times[1:]))
    core = make_plan(json.loads(part.read_text()), action=action, exact=bool(model))
    want = core.trace(0.0)
    for k, tf in enumerate(frames):
        by = {t.child_frame_id: t for t in tf.transforms}
        phi = _yaw(by["part"].rotation)
        assert abs((phi - want[k] + math.pi) % (2 * math.pi) - math.pi) < 1e-9
        if k:
            alpha = math.radians(plan_doc["steps"][k - 1]["gripper_angle_deg"])
            assert abs((_yaw(by["gripper"].rotation) - alpha + math.pi) % (2 * math.pi) - math.pi) < 1e-9
            lo, hi = by["jaw_lower"].translation.y, by["jaw_higher"].translation.y
            assert lo < 0.0 < hi  # both jaws touch the part, one each side of its centre
    final = np.mod(want[-1], 2 * np.pi)
    assert min(abs((final - math.radians(f) + math.pi) % (2 * math.pi) - math.pi)
               for f in plan_doc["final_orientations_deg"]) <= math.radians(plan_doc["final_uncertainty_deg"]) + 1e-9
