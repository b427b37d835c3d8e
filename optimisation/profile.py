"""Gripper profiles: the limits a jaw trajectory must respect (SI units).

A profile is a YAML or JSON object whose keys are the fields of :class:`GripperProfile`
(any subset; missing keys take the documented defaults, unknown keys are refused). The
bundled ``profiles/default.yaml`` is the default written out.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, fields, replace
from pathlib import Path
from typing import Any

from algrasp.errors import ConfigError


@dataclass(frozen=True)
class GripperProfile:
    """Limits and set-points of a parallel-jaw gripper.

    Attributes:
        jaw_max_speed_m_s: top speed of each jaw (and of the gripper's translation).
        jaw_max_accel_m_s2: acceleration limit of each jaw.
        contact_speed_m_s: top jaw speed wherever a jaw may touch the part (quasi-static
            pushing and squeezing; the validation's contact speed).
        rotate_max_speed_rad_s, rotate_max_accel_rad_s2: gripper rotation limits.
        grip_force_n: largest squeeze force; the jaw servo (stiffness
            ``jaw_stiffness_n_m``) is commanded grip_force_n / stiffness past the
            narrowest predicted grasp width, and its effort is capped at this force.
        open_clearance_m: open jaws stand this far outside the part's largest half-width.
        placement_tolerance_m: how far the part may lie off the gripper centre along the
            closing axis; slow contact zones and push strokes are widened by it.
        hold_s: dwell with the jaws closed.
        push_tolerance_deg: a push is complete when the part is this close to its
            push-function fixed point.
        unstable_band_deg: orientations this close to an unstable push equilibrium are
            left out of the worst case (the needed distance is unbounded there).
        sample_hz: rate of the trajectory samples in the plan document.
        jaw_max_jerk_m_s3: jerk limit of the jaws (0: not limited; the moves are then the
            closed-form bang-bang profiles, else CasADi's jerk-limited S-curves).
    """

    jaw_max_speed_m_s: float = 0.05
    jaw_max_accel_m_s2: float = 0.5
    contact_speed_m_s: float = 0.01
    rotate_max_speed_rad_s: float = 6.0
    rotate_max_accel_rad_s2: float = 30.0
    grip_force_n: float = 2.0
    jaw_stiffness_n_m: float = 2000.0
    open_clearance_m: float = 0.002
    placement_tolerance_m: float = 0.0
    hold_s: float = 0.1
    push_tolerance_deg: float = 0.5
    unstable_band_deg: float = 2.0
    sample_hz: float = 100.0
    jaw_max_jerk_m_s3: float = 0.0

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            lo, hi, zero_ok = RANGES[f.name]
            if not isinstance(value, (int, float)) or isinstance(value, bool) or not math.isfinite(value) \
                    or not (lo <= value <= hi) or (value == lo and not zero_ok):
                bracket = "[" if zero_ok else "("
                raise ConfigError(f.name, f"must be a number in {bracket}{lo:g}, {hi:g}], got {value!r}")
            object.__setattr__(self, f.name, float(value))  # JSON integers are durations too
        if self.contact_speed_m_s > self.jaw_max_speed_m_s:
            raise ConfigError("contact_speed_m_s", "must not exceed jaw_max_speed_m_s")

    @property
    def squeeze_overtravel_m(self) -> float:
        """How far past the part's surface a jaw is commanded so its force is grip_force_n."""
        return self.grip_force_n / self.jaw_stiffness_n_m

    def to_dict(self) -> dict[str, float]:
        return {f.name: float(getattr(self, f.name)) for f in fields(self)}


RANGES: dict[str, tuple[float, float, bool]] = {
    "jaw_max_speed_m_s": (0.0, 10.0, False), "jaw_max_accel_m_s2": (0.0, 1000.0, False),
    "contact_speed_m_s": (0.0, 10.0, False), "rotate_max_speed_rad_s": (0.0, 100.0, False),
    "rotate_max_accel_rad_s2": (0.0, 10_000.0, False), "grip_force_n": (0.0, 10_000.0, False),
    "jaw_stiffness_n_m": (0.0, 1e9, False), "open_clearance_m": (0.0, 1.0, False),
    "placement_tolerance_m": (0.0, 1.0, True), "hold_s": (0.0, 60.0, True),
    "push_tolerance_deg": (0.0, 44.9, False), "unstable_band_deg": (0.0, 44.9, False),
    "sample_hz": (0.0, 1000.0, False), "jaw_max_jerk_m_s3": (0.0, 1e6, True),
}
"""The documented range of each key: (low, high, whether low itself is allowed). The
upper bounds keep a plan's size and duration finite (``sample_hz`` ≤ 1 kHz: a plan
document stays a few MB); ``push_tolerance_deg``/``unstable_band_deg`` stay below 45°."""

DEFAULT_PROFILE = GripperProfile()
DEFAULT_PROFILE_PATH = Path(__file__).parent / "profiles" / "default.yaml"


def profile_from_dict(data: Any, source: str = "profile") -> GripperProfile:
    """Build a profile from a mapping, naming unknown keys and bad values."""
    if not isinstance(data, dict):
        raise ConfigError(source, "a gripper profile must be a mapping of limits")
    known = {f.name for f in fields(GripperProfile)}
    unknown = sorted(set(data) - known)
    if unknown:
        raise ConfigError(unknown[0], f"unknown gripper profile key (known: {', '.join(sorted(known))})")
    return replace(DEFAULT_PROFILE, **data)


def load_profile(path: str | Path) -> GripperProfile:
    """Read a YAML (.yaml/.yml) or JSON gripper profile file."""
    p = Path(path)
    if not p.is_file():
        raise ConfigError("gripper", f"no such profile file: {path}")
    text = p.read_text(encoding="utf-8")
    try:
        if p.suffix.lower() in (".yaml", ".yml"):
            import yaml

            data = yaml.safe_load(text)
        else:
            data = json.loads(text)
    except Exception as exc:  # noqa: BLE001 - any parse error is the user's file
        raise ConfigError("gripper", f"cannot parse {p.name}: {exc}") from None
    return profile_from_dict(data, "gripper")
