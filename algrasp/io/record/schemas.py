"""JSON schemas of algrasp's own MCAP channels (draft 2020-12).

Every message on a JSON channel is validated against these in the tests; payloads use
degrees and the part's unit, as every interface does (conventions §1).
"""

from __future__ import annotations

from typing import Any

_NUM = {"type": "number"}
_NUM_OR_NULL = {"type": ["number", "null"]}
_OBJ = {"type": "object"}

REQUEST: dict[str, Any] = {
    "title": "algrasp.Request", "type": "object",
    "required": ["run_id", "command", "part", "options"],
    "properties": {
        "run_id": {"type": "string"},
        "command": {"enum": ["analyze", "plan", "validate", "service", "batch", "design"]},
        "part": _OBJ,
        "options": _OBJ,
    },
}

ANALYSIS: dict[str, Any] = {
    "title": "algrasp.Analysis", "type": "object",
    "required": ["part", "diameter", "radius", "squeeze", "push", "push_grasp"],
    "properties": {k: _OBJ for k in ("part", "diameter", "radius", "squeeze", "push", "push_grasp")},
}

PLAN: dict[str, Any] = {
    "title": "algrasp.Plan", "type": "object",
    "required": ["action", "symmetry_period_deg", "steps", "final_orientations_deg", "verified"],
    "properties": {
        "action": {"enum": ["squeeze", "push_grasp"]},
        "symmetry_period_deg": _NUM,
        "intervals_deg": {"type": "array", "items": {"type": "array", "items": _NUM, "minItems": 2, "maxItems": 2}},
        "steps": {"type": "array", "minItems": 1, "items": {
            "type": "object", "required": ["gripper_angle_deg", "margin_deg"],
            "properties": {"gripper_angle_deg": _NUM, "margin_deg": _NUM_OR_NULL, "push_distance": _NUM_OR_NULL,
                           "duration_s": _NUM, "trajectory": _OBJ}}},
        "final_orientations_deg": {"type": "array", "items": _NUM},
        "verified": {"type": "boolean"},
        "cycle_time_s": _NUM,
        "timings_s": {"type": "object", "additionalProperties": _NUM},
    },
}

VALIDATION: dict[str, Any] = {
    "title": "algrasp.Validation", "type": "object",
    "required": ["samples", "agreement", "agreement_clear", "tolerance_deg", "placement", "sim_seconds", "wall_seconds"],
    "properties": {
        "samples": {"type": "array", "items": {
            "type": "object", "required": ["initial_deg", "predicted_deg", "simulated_deg", "agrees"],
            "properties": {"initial_deg": _NUM, "predicted_deg": _NUM, "simulated_deg": _NUM, "agrees": {"type": "boolean"},
                           "near_unstable": {"type": "boolean"}, "pushed_deg": _NUM_OR_NULL}}},
        "agreement": _NUM, "agreement_clear": _NUM, "push_agreement": _NUM_OR_NULL,
        "tolerance_deg": _NUM, "placement": {"enum": ["centred", "random"]},
        "sim_seconds": _NUM, "wall_seconds": _NUM, "model": _OBJ,
    },
}

TRAJECTORY: dict[str, Any] = {
    "title": "algrasp.SimState", "type": "object",
    "required": ["sample", "t_s", "x_m", "y_m", "phi_deg", "gripper_angle_deg", "lower_jaw_m", "higher_jaw_m"],
    "properties": {"sample": {"type": "integer"}, "t_s": _NUM, "x_m": _NUM, "y_m": _NUM, "phi_deg": _NUM,
                   "gripper_angle_deg": _NUM, "lower_jaw_m": _NUM, "higher_jaw_m": _NUM},
}

RUN: dict[str, Any] = {
    "title": "algrasp.Run", "type": "object",
    "required": ["run_id", "command", "status", "started_unix_s", "timings_s", "versions"],
    "properties": {
        "run_id": {"type": "string"}, "command": {"type": "string"},
        "status": {"enum": ["ok", "error"]}, "error": {"type": ["object", "null"]},
        "started_unix_s": _NUM, "part_name": {"type": ["string", "null"]}, "action": {"type": ["string", "null"]},
        "steps": {"type": ["integer", "null"]}, "agreement": _NUM_OR_NULL, "cycle_time_s": _NUM_OR_NULL,
        "timings_s": {"type": "object", "additionalProperties": _NUM},
        "versions": {"type": "object", "additionalProperties": {"type": "string"}},
    },
}

TOPICS: dict[str, dict[str, Any]] = {
    "/request": REQUEST, "/analysis": ANALYSIS, "/plan": PLAN, "/validation": VALIDATION,
    "/sim/state": TRAJECTORY, "/run": RUN,
}
