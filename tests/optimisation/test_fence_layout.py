"""Fence layout (conventions §9): the belt width, reach, lengths and positions obey the
stated geometry, recomputed here from the document alone; a too narrow belt is refused."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from algrasp.errors import ConfigError
from algrasp.planning.analysis import EXACT, analyse_document
from algrasp.planning.fences import FenceRules, design_fences
from optimisation.fence_layout import CLEARANCE, SPACING, layout, plan_fences

ROOT = Path(__file__).resolve().parents[2]
BRACKET = json.loads((ROOT / "algrasp" / "examples" / "bracket.json").read_text())


@pytest.fixture(scope="module")
def doc() -> dict[str, object]:
    return plan_fences(analyse_document(BRACKET, EXACT), exit_turns=False).to_dict()  # Berretty's model, with the guide


def test_the_belt_is_wide_enough_for_every_turn(doc: dict[str, object]) -> None:
    """h = W − 2a − c; consecutive reaches overlap by the part and its turn,
    h_{i−1} + h_i ≥ W + 2a + s_i cos β_i; the first fence catches parts entering within
    2a of its rail and lets them turn, h ≥ 4a + s_1 cos β_1; one of these is tight."""
    a, W, h = doc["cover_radius"], doc["belt_width"], doc["reach"]
    fences = doc["fences"]
    assert isinstance(a, float) and isinstance(W, float) and isinstance(h, float) and isinstance(fences, list)
    c = CLEARANCE * a
    assert h == pytest.approx(W - 2 * a - c)
    turn = [f["push_distance_bound"] * math.cos(math.radians(f["steepness_deg"])) for f in fences]
    ex = doc["exit"]
    assert isinstance(ex, dict)
    turn[-1] += ex["push_distance_bound"] * math.cos(math.radians(ex["steepness_deg"]))  # the guide's rise
    slack = [h - 4 * a - turn[0]] + [2 * h - W - 2 * a - t for t in turn[1:]]
    assert min(slack) >= -1e-9 and min(slack) == pytest.approx(0.0, abs=1e-9)


def test_lengths_positions_and_sides(doc: dict[str, object]) -> None:
    a, h = doc["cover_radius"], doc["reach"]
    fences = doc["fences"]
    assert isinstance(fences, list) and isinstance(a, float) and isinstance(h, float)
    ex = doc["exit"]
    assert isinstance(ex, dict)
    be = math.radians(ex["steepness_deg"])
    rise = ex["push_distance_bound"] * math.cos(be)
    x = 0.0
    for i, f in enumerate(fences):
        beta = math.radians(f["steepness_deg"])
        last = i == len(fences) - 1
        assert f["length"] == pytest.approx((h - rise if last else h) / math.sin(beta))
        assert f["position"] == pytest.approx(x)
        x = f["position"] + h / math.tan(beta) + SPACING * a  # the next root: 2a past this tip
        assert f["angle_deg"] == pytest.approx(f["steepness_deg"] if f["side"] == "right" else 180 - f["steepness_deg"])
        if i:
            assert f["side"] != fences[i - 1]["side"]
    assert doc["total_length"] == pytest.approx(sum(f["length"] for f in fences))
    # The guide: from the last tip along β_e towards the far rail, push bound · cot β_e long.
    assert ex["length"] == pytest.approx(ex["push_distance_bound"] / math.tan(be))
    (x0, y0), (x1, y1) = ex["start"], ex["end"]
    assert math.hypot(x1 - x0, y1 - y0) == pytest.approx(ex["length"])
    assert abs(y1 - y0) == pytest.approx(rise) and ex["side"] == fences[-1]["side"]


def test_a_given_belt_width_is_kept_or_refused() -> None:
    analysis = analyse_document(BRACKET, EXACT)
    design = design_fences(analysis, FenceRules(exit_steepness=None, exit_turns=False))
    least = layout(analysis, design).belt_width
    wide = layout(analysis, design, 1.5 * least)
    assert wide.belt_width == 1.5 * least and wide.reach > layout(analysis, design).reach
    with pytest.raises(ConfigError) as e:
        layout(analysis, design, 0.9 * least)
    assert e.value.field == "belt_width"
