"""``algrasp validate PART --fences``: the belt validation of ``algrasp fences --validate N``
(one code path), its MCAP record, and flags of the other mode refused by name."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from algrasp.cli import main

SQUARE = {"name": "square", "units": "mm", "boundary": [[0, 0], [30, 0], [30, 30], [0, 30]]}


@pytest.fixture
def square_file(tmp_path: Path) -> Path:
    p = tmp_path / "square.json"
    p.write_text(json.dumps(SQUARE))
    return p


@pytest.mark.parametrize(("argv", "flag", "says"), [
    (["--belt-width", "200"], "--belt-width", "needs --fences"),
    (["--fence-friction", "0.2"], "--fence-friction", "needs --fences"),
    (["--tail", "20"], "--tail", "needs --fences"),
    (["--fences", "--optimise"], "--optimise", "does not apply with --fences"),
    (["--fences", "--action", "push-grasp"], "--action", "does not apply with --fences"),
    (["--fences", "--sim-physics", "corners"], "--sim-physics", "does not apply with --fences"),
    (["--fences", "--tail-sweep", "5"], "--tail", "--tail-sweep needs --tail R"),
    (["--fences", "--belt-width", "1"], "--belt-width", "this design needs a belt at least"),
    (["--fences", "--samples", "0"], "--samples", "must be in [1, 10000]"),
])
def test_bad_options_name_the_flag(square_file: Path, argv: list[str], flag: str, says: str,
                                   capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["validate", str(square_file), "--no-record", *argv]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"algrasp: error: {flag}: ") and says in err


def _off(phi_deg: float, finals: list[float], period: float) -> float:
    return min(abs((phi_deg - f + period / 2) % period - period / 2) for f in finals)


@pytest.mark.sim
def test_validate_fences_is_the_belt_validation(square_file: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Same seed, same starts, same simulated finals as ``fences --validate``; the verdict
    recomputed here from the simulated orientations; one MCAP record with the scene."""
    pytest.importorskip("pydrake")
    runs = tmp_path / "runs"
    argv = ["--samples", "2", "--seed", "3", "--record-dir", str(runs), "--json"]
    assert main(["validate", str(square_file), "--fences", *argv]) == 0
    out = json.loads(capsys.readouterr().out)
    assert main(["fences", str(square_file), "--validate", "2", "--seed", "3", "--no-record", "--json"]) == 0
    ref = json.loads(capsys.readouterr().out)
    v, w = out["validation"], ref["validation"]
    assert out["fences"] == ref["fences"] and len(v["samples"]) == 2 and v["seed"] == 3
    for a, b in zip(v["samples"], w["samples"]):
        assert (a["initial_deg"], a["lateral"]) == (b["initial_deg"], b["lateral"])
        assert a["simulated_deg"] == pytest.approx(b["simulated_deg"], abs=1e-6)
        mine = _off(a["simulated_deg"], out["final_orientations_deg"], out["symmetry_period_deg"])
        assert a["agrees"] == (mine <= out["final_uncertainty_deg"] + 0.25)
    assert v["tolerance_deg"] == 0.25  # the fence default, not the gripper's 1°
    from mcap.reader import make_reader

    (path,) = runs.glob("*.mcap")
    assert v["run_id"] and v["run_id"] in path.name
    with path.open("rb") as f:
        summary = make_reader(f).get_summary()
    assert summary is not None
    topics = {c.topic for c in summary.channels.values()}
    assert {"/tf", "/scene", "/fences", "/fence_validation"} <= topics
