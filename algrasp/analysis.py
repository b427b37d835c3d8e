"""One call from a validated part to everything the paper derives from it.

``analyse_part(part)`` → :class:`Analysis`: diameter and radius functions with their
extrema, and the squeeze Γ, push p and push-grasp Γ∘p transfer functions.
Pure: no I/O; ``to_dict`` gives the JSON object of ``algrasp analyze --json``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from algrasp.functions import SupportPairFunction, analyse
from algrasp.part import Part
from algrasp.tolerances import DEFAULT_TOLERANCES, Tolerances
from algrasp.transfer import TransferFunction, describe, from_runs

SYMMETRY_TOL_RAD = 1e-7
"""Tolerance on breakpoints and images when testing F(θ + T) = F(θ) + T: root finding
places curved breakpoints to ~1e-12 rad, far inside this."""


@dataclass(frozen=True, eq=False)
class Analysis:
    part: Part
    diameter: SupportPairFunction
    radius: SupportPairFunction
    squeeze: TransferFunction
    push: TransferFunction
    push_grasp: TransferFunction
    tol: Tolerances

    @property
    def squeeze_orientable(self) -> bool:
        """False for parts of constant width: Γ has no step (paper §4, conventions §6)."""
        return bool(self.squeeze.steps)

    def to_dict(self) -> dict[str, object]:
        """The ``algrasp analyze --json`` object (degrees, lists sorted by start)."""
        out: dict[str, object] = {
            "part": {"name": self.part.name, "units": self.part.units, "area": self.part.area,
                     "hull_perimeter": self.part.hull.perimeter,
                     "center_of_mass": list(self.part.center_of_mass),
                     "center_of_mass_given": self.part.com_given},
            "diameter": _function_dict(self.diameter),
            "radius": _function_dict(self.radius),
        }
        for name, F in (("squeeze", self.squeeze), ("push", self.push), ("push_grasp", self.push_grasp)):
            d = describe(F, SYMMETRY_TOL_RAD)
            d["orientable"] = bool(F.steps)
            if not F.steps:
                d["reason"] = "constant diameter: no step, so no squeeze plan can orient this part" \
                    if name == "squeeze" else "no step: the function is the identity everywhere"
            out[name] = d
        return out


def _function_dict(f: SupportPairFunction) -> dict[str, object]:
    return {
        "extrema": [{"theta_deg": float(np.degrees(e.theta)), "value": e.value, "kind": e.kind,
                     "equilibrium": e.equilibrium} for e in f.extrema],
        "constant_intervals_deg": [[float(np.degrees(a)), float(np.degrees(b))] for a, b in f.constant_intervals],
    }


def analyse_part(part: Part, tol: Tolerances = DEFAULT_TOLERANCES) -> Analysis:
    """Diameter/radius extrema and all three transfer functions. See module docs."""
    d = analyse("diameter", part.hull, part.center_of_mass, part.size, tol)
    r = analyse("radius", part.hull, part.center_of_mass, part.size, tol)
    squeeze = from_runs(list(d.runs), np.pi, tol.angle_rad)
    push = from_runs(list(r.runs), 2 * np.pi, tol.angle_rad)
    push_grasp = squeeze.compose_after(push, tol.angle_rad) if squeeze.steps else push
    return Analysis(part, d, r, squeeze, push, push_grasp, tol)
