"""Consecutive fences on one rail (``same_rail``, conventions §9): the designs the exit
model refuses with alternating fences — pie-20, the triangle, the bracket — held to the
brute force of ``test_fence_exit`` (the push of ``tests.algrasp.brute``, nothing of
algrasp, from 3,600 starts, each fence's tip turning the part by a sampled t ∈ [0, β],
then the exit guide), and their layout's geometry checked from the fence document."""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np
import pytest

from algrasp.errors import NotOrientableError
from algrasp.planning.analysis import EXACT, analyse_document
from algrasp.planning.fence_model import fence_rules
from algrasp.planning.fences import design_fences
from algrasp.planning.physics import DEFAULT_PHYSICS
from optimisation.fence_layout import FenceLayout, plan_fences
from tests.algrasp import brute
from tests.algrasp.planning.test_fence_exit import _fracs, _miss_deg, _run, _steep
from tests.algrasp.planning.test_fences import STARTS, _cases, fence_flow, mus

PARTS = ["pie", "triangle", "bracket"]
FRICTION = (0.0, 0.03)
"""The fence friction range of these designs: with the default 0.1–0.3 pie-20's rest on
its arc moves by up to 18.4° and the bracket gains a rest (conventions §9), and neither
has a design; below 0.03 both do."""


@pytest.fixture(scope="module")
def layouts() -> dict[str, tuple[FenceLayout, brute.ExactPart]]:
    out = {}
    for name in PARTS:
        doc, model = _cases()[name]
        analysis = analyse_document(doc, EXACT)
        out[name] = (plan_fences(analysis, fence_rules(list(FRICTION)), same_rail=True),
                     model(analysis.part.center_of_mass))  # type: ignore[operator]
    return out


@pytest.mark.parametrize("name", PARTS)
def test_same_rail_designs_hold_by_brute_force(name: str, layouts: dict[str, tuple[FenceLayout, brute.ExactPart]]) -> None:
    """From 3,600 starts, every sampled tip turn (none, the full β, seeded random) and wall
    friction over the range:
    on the last fence at the design's finals, and past the exit guide within its claim;
    at least two consecutive fences share a rail (the alternating model has no design)."""
    out, part = layouts[name]
    design, guide = out.design, out.exit
    assert len(STARTS) >= 3000 and guide is not None
    assert any(a == b for a, b in zip(design.sides, design.sides[1:]))
    beta_n, sign_n = _steep(design.angles[-1])
    beta_e, sign_e = _steep(guide.angle)
    for frac, mu in ((f, float(m)) for f in _fracs(len(design.angles), 11) for m in mus(design.rules)):
        phi = _run(part, design.angles, frac, mu)
        assert _miss_deg(phi, design.final_orientations, design.symmetry) < 0.01
        push = fence_flow(part, guide.angle, mu)
        off = push(phi + sign_n * frac[0] * beta_n - guide.angle) + guide.angle + sign_e * frac[-1][::-1] * beta_e
        assert _miss_deg(np.mod(off, 2 * np.pi), guide.final_orientations, design.symmetry) \
            <= math.degrees(guide.final_uncertainty) + 0.01


@pytest.mark.parametrize("name", PARTS)
def test_same_rail_layout_catches_the_part_off_each_tip(name: str,
                                                        layouts: dict[str, tuple[FenceLayout, brute.ExactPart]]) -> None:
    """From the document: a fence on the rail of the one before reaches past that one's tip
    by at least 2a + s_i cos β_i (so past the part's covering radius); every fence's tip
    leaves 2a + c to the far rail; each fence's x-extent lies past the one before (no
    crossing); each length is its reach over sin β."""
    out, _ = layouts[name]
    doc: dict[str, Any] = dict(out.to_dict())
    a, W, fences = doc["cover_radius"], doc["belt_width"], doc["fences"]
    for prev, f in zip(fences, fences[1:]):
        x_tip = prev["position"] + prev["reach"] / math.tan(math.radians(prev["steepness_deg"]))
        assert f["position"] >= x_tip + 2.0 * a - 1e-9
        if f["side"] == prev["side"]:
            lateral = f["push_distance_bound"] * math.cos(math.radians(f["steepness_deg"]))
            assert f["reach"] >= prev["reach"] + 2.0 * a + lateral - 1e-9
            assert f["reach"] - prev["reach"] > a
        else:
            assert prev["reach"] + f["reach"] >= W + 2.0 * a - 1e-9
    for f in fences:
        assert f["reach"] <= W - 2.5 * a + 1e-9
        assert f["length"] == pytest.approx(f["reach"] / math.sin(math.radians(f["steepness_deg"])))


def test_alternating_refusal_names_the_same_rail_design() -> None:
    """The alternating model refuses pie-20 and says a same-rail design exists (fence
    friction up to 0.03: with the default range pie-20 has no design at all)."""
    doc, _ = _cases()["pie"]
    analysis = analyse_document(doc, EXACT)
    rules = fence_rules(list(FRICTION))
    with pytest.raises(NotOrientableError, match=r"consecutive fences on one rail \(same_rail true, --same-rail\)$") as err:
        design_fences(analysis, rules)
    assert (err.value.limits or {})["same_rail_design"] is True
    assert design_fences(analysis, replace(rules, same_rail=True)).angles
    assert "the next fence, on the other rail, sees its outcomes shifted by 180° − β only" in err.value.message


ROUNDED = {"name": "rounded-40x20-r4", "units": "mm", "boundary": [
    {"type": "line", "start": [4, 0], "end": [36, 0]},
    {"type": "arc", "center": [36, 4], "radius": 4, "start_deg": -90, "end_deg": 0},
    {"type": "line", "start": [40, 4], "end": [40, 16]},
    {"type": "arc", "center": [36, 16], "radius": 4, "start_deg": 0, "end_deg": 90},
    {"type": "line", "start": [36, 20], "end": [4, 20]},
    {"type": "arc", "center": [4, 16], "radius": 4, "start_deg": 90, "end_deg": 180},
    {"type": "line", "start": [0, 16], "end": [0, 4]},
    {"type": "arc", "center": [4, 4], "radius": 4, "start_deg": 180, "end_deg": 270}]}
"""The bench's 40 × 20 mm rectangle with R 4 corners: refused in the real cell's robust
model with tip turns and the fence friction whether or not fences may share a rail (its
short ends stop being rests at μ_f ≈ 0.3), designed in Berretty et al.'s model either way."""
REAL = DEFAULT_PHYSICS.to_dict()
"""The real cell's physics (conventions §8), not the suite's ideal one."""


@pytest.mark.parametrize("same_rail", [False, True])
def test_tip_turn_refusal_says_what_the_next_fence_sees(same_rail: bool) -> None:
    """The rounded rectangle's refusal describes the mode it was searched in: alternating fences
    (the next on the other rail) or, with ``same_rail``, fences on either rail (the next on
    the same rail shifted by its own steepness); it never offers ``--same-rail`` when on,
    nor (no same-rail design either) when off."""
    import algrasp

    with pytest.raises(NotOrientableError) as err:
        algrasp.fences(ROUNDED, physics=REAL, same_rail=same_rail)
    msg, limits = err.value.message, err.value.limits or {}
    assert err.value.reason == "no_fence_design" and limits["berretty_design"] is True
    assert limits["same_rail_design"] is False
    assert algrasp.fences(ROUNDED, physics=REAL, same_rail=same_rail, exit_turns=False).design.angles  # Berretty's model has one
    assert "a design exists (exit_turns false, --no-exit-turns)" in msg
    assert "--same-rail" not in msg and "same_rail" not in msg
    if same_rail:
        assert msg.startswith("no sequence of at most 12 fences orients the part")
        assert ("the next fence sees its outcomes shifted by 180° − β only on the other rail, and by its own "
                "steepness β only on the same rail") in msg
        assert "alternating" not in msg and "the next fence, on the other rail," not in msg
    else:
        assert msg.startswith("no sequence of at most 12 alternating fences orients the part")
        assert "the next fence, on the other rail, sees its outcomes shifted by 180° − β only" in msg
        assert "on the same rail" not in msg


def test_tail_keeps_the_same_rail_reach() -> None:
    """Pie-20's last two fences share a rail: a tail may shorten the last one only while it
    still reaches 2a + s_N cos β_N past the one before, which a wider belt does not change
    (so the refusal does not offer one); a small tail that keeps it is accepted."""
    from algrasp.errors import ConfigError
    from optimisation.fence_layout import with_tail

    doc, _ = _cases()["pie"]  # with the fence friction up to 0.15 its last two fences share a rail
    out = plan_fences(analyse_document(doc, EXACT), fence_rules([0.0, 0.15]), same_rail=True)
    assert out.design.sides[-1] == out.design.sides[-2]
    with pytest.raises(ConfigError, match="smaller radius or sweep$"):
        with_tail(out, 5.0)
    tailed = with_tail(out, 1.0)
    a, n = tailed.cover_radius, len(tailed.lengths)
    lateral = tailed.push_bounds[-1] * math.cos(tailed.steepness[-1])
    assert tailed.reach_of(n - 1) >= tailed.reach_of(n - 2) + 2.0 * a + lateral - 1e-9
