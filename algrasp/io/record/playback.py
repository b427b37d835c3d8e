"""A run record read back for playback (``GET /v1/runs/{id}/playback``, the workbench):
the recorded part, plan and validation, and every simulated sample's trajectory thinned
to at most ``points`` states, in the part's unit and degrees (conventions §1).

The simulator records SI units (``/sim/state``: metres); this converts them back with the
part's own unit, so the page draws trajectory and outline in one frame.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from algrasp.errors import RecordError
from algrasp.geometry.units import meters_per_unit
from algrasp.io.record.replay import checked, read_record

MAX_POINTS = 2000
_LENGTHS = {"x_m": "x", "y_m": "y", "lower_jaw_m": "lower_jaw", "higher_jaw_m": "higher_jaw"}
_ANGLES = ("t_s", "phi_deg", "gripper_angle_deg")


def _thin(states: list[dict[str, Any]], points: int) -> list[dict[str, Any]]:
    """Every k-th state and the last (where the sample ended): at most ``points``. O(n)."""
    if len(states) <= points:
        return states
    k = -(-len(states) // (points - 1))
    return [*states[::k], states[-1]] if (len(states) - 1) % k else states[::k]


def _series(states: list[dict[str, Any]], scale: float) -> dict[str, list[float]]:
    out = {name: [s[name] for s in states] for name in _ANGLES}
    out.update({short: [s[name] / scale for s in states] for name, short in _LENGTHS.items()})
    return out


def trajectories(rec: dict[str, list[dict[str, Any]]], units: str, points: int) -> list[dict[str, Any]]:
    """Per sample ``{"sample", "t_s", "phi_deg", "gripper_angle_deg", "x", "y",
    "lower_jaw", "higher_jaw"}`` (lists of equal length; lengths in ``units``)."""
    by_sample: dict[int, list[dict[str, Any]]] = {}
    for state in rec.get("/sim/state", []):
        by_sample.setdefault(int(state["sample"]), []).append(state)
    if not by_sample:
        return []  # nothing simulated: the part's unit need not be one the simulator knows
    scale = meters_per_unit(units)
    return [{"sample": k, **_series(_thin(states, points), scale)} for k, states in sorted(by_sample.items())]


def playback(path: Path, points: int = 400) -> dict[str, Any]:
    """``{"run_id", "part", "options", "plan", "validation", "trajectories"}`` of a record;
    ``plan``/``validation`` are None when the run had none, ``trajectories`` empty when
    nothing was simulated. Raises RecordError for a damaged record. O(messages)."""
    rec = read_record(path, {"/request", "/plan", "/validation", "/sim/state"})
    if "/request" not in rec:
        raise RecordError(path.name, f"RUN: {path.name} has no /request: nothing to play back")
    request = checked(rec["/request"][0], "/request", path.name)
    for topic in ("/plan", "/validation"):  # the states are checked as they are read
        for message in rec.get(topic, [])[:1]:
            checked(message, topic, path.name)
    try:
        units = str(request["part"].get("units", "mm")) if isinstance(request["part"], dict) else "mm"
        return {"run_id": request["run_id"], "part": request["part"], "options": request["options"],
                "plan": rec.get("/plan", [None])[0], "validation": rec.get("/validation", [None])[0],
                "trajectories": trajectories(rec, units, points)}
    except (KeyError, TypeError, ValueError) as exc:
        raise RecordError(path.name, f"RUN: {path.name} is damaged: its messages lack {exc!s:.100}") from None
