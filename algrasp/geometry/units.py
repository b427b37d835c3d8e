"""Length units of part documents, in metres (the simulator and the optimiser work in SI).

>>> meters_per_unit("mm"), meters_per_unit("in")
(0.001, 0.0254)
"""

from __future__ import annotations

from algrasp.errors import ConfigError

UNIT_TO_M = {"mm": 1e-3, "cm": 1e-2, "m": 1.0, "in": 0.0254, "um": 1e-6}
"""Metres per unit of each length unit a part document may name."""


def meters_per_unit(units: str) -> float:
    """Metres per ``units``; ConfigError naming ``units`` for an unknown one."""
    try:
        return UNIT_TO_M[units]
    except KeyError:
        raise ConfigError("units", f"a length in metres needs a known unit ({', '.join(UNIT_TO_M)}), got {units!r}") from None
