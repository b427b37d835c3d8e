"""Drake on a belt (conventions §9): one small real case, the square's two-fence design
with its exit guide from two seeded starts, with the agreement computed here from the
simulated poses, not taken from the validator's verdict: past the guide the part is within
the document's claim, on the last fence within the design's."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("pydrake")

import algrasp  # noqa: E402

pytestmark = pytest.mark.sim

SQUARE = {"name": "square", "units": "mm", "boundary": [[0, 0], [30, 0], [30, 30], [0, 30]]}


def _off(phi_deg: float, finals: list[float], period: float) -> float:
    return min(abs((phi_deg - f + period / 2) % period - period / 2) for f in finals)


def test_square_on_a_belt(tmp_path: Path) -> None:
    layout = algrasp.fences(SQUARE)
    doc = layout.to_dict()
    v = algrasp.validate_fences(SQUARE, samples=2, seed=3, record=True, record_dir=tmp_path)
    finals, T = doc["final_orientations_deg"], doc["symmetry_period_deg"]
    allowed = doc["final_uncertainty_deg"] + 0.25
    on_fence, allowed_on = doc["last_fence_orientations_deg"], doc["last_fence_uncertainty_deg"] + 0.25
    guide_end = np.array(doc["exit"]["end"]) * 1e-3
    (wall,) = [w for w in v.walls if w.name == "exit_guide"]  # the simulated guide is the document's
    assert math.degrees(wall.alpha) == pytest.approx(doc["exit"]["angle_deg"])
    assert wall.length == pytest.approx(doc["exit"]["length"] * 1e-3)
    s = 1e-3  # mm → m
    k = len(doc["fences"]) - 1
    root, tip = np.array(layout.root(k)) * s, np.array(layout.tip(k)) * s
    along = (tip - root) / np.linalg.norm(tip - root)
    normal = np.array([-math.sin(layout.design.angles[k]), math.cos(layout.design.angles[k])])
    a = layout.cover_radius * s
    for sample, traj in zip(v.samples, v.trajectories):
        poses = np.array(traj)  # (t, x, y, φ) in SI units
        # The final pose, read from the trajectory: past the layout, and the verdict is ours.
        t, x, y, phi = poses[-1]
        assert x >= guide_end[0] + a
        mine = _off(math.degrees(phi), finals, T)
        assert sample.agrees == (mine <= allowed) and sample.error_deg == pytest.approx(mine, abs=1e-9)
        assert mine <= allowed  # the claim holds after the part has left every fence and the guide
        # Over the second half of the last fence (its centre within a of the wall, a short
        # of its tip: the turn is over, the part not yet coming off) it is at the design's
        # final orientation.
        rel = poses[:, 1:3] - root
        u, w = rel @ along, rel @ normal
        L = np.linalg.norm(tip - root)
        on = (u > L / 2) & (u < L - a) & (w > 0) & (w < a)
        assert on.sum() >= 5
        assert max(_off(math.degrees(p), on_fence, T) for p in poses[on, 3]) <= allowed_on
    # One MCAP record: the part's pose on /tf, the walls in /scene, the documents.
    from mcap.reader import make_reader

    from tests.algrasp.io.record.test_records import check_record

    (path,) = tmp_path.glob("*.mcap")
    assert check_record(path)["/tf"] > 0  # every JSON message valid against its channel's schema
    with path.open("rb") as f:
        topics = {c.topic for c in make_reader(f).get_summary().channels.values()}
    assert {"/tf", "/scene", "/fences", "/fence_validation", "/request", "/run"} <= topics
    # The scene has the exit guide as a red box of the document's length, along its angle.
    from foxglove_schemas_protobuf.SceneUpdate_pb2 import SceneUpdate

    with path.open("rb") as f:
        _, _, message = next(iter(make_reader(f).iter_messages(topics=["/scene"])))
    cubes = [c for e in SceneUpdate.FromString(message.data).entities for c in e.cubes]
    guide = [c for c in cubes if c.size.x == pytest.approx(doc["exit"]["length"] * 1e-3)]
    assert len(guide) == 1 and guide[0].color.r > 0.5 > guide[0].color.g
    assert 2 * math.degrees(math.atan2(guide[0].pose.orientation.z, guide[0].pose.orientation.w)) \
        == pytest.approx(doc["exit"]["angle_deg"])
