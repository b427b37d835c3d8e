"""The CLI's physics flags, built from the one options type (``algrasp.planning.physics``).

Every range flag takes one value or ``lo,hi`` (``--jaw-friction 0,0.2``); ``--cell``
(or ``ALGRASP_CELL``) names the cell the flags refine: a preset (``default``, ``ideal``)
or a JSON object of physics keys.
"""

from __future__ import annotations

import argparse
import os
from typing import Any

from algrasp.planning.physics import DEFAULT_RANGES, PARAMETERS, PLACEMENTS, PRESETS, Physics, cell_from_text

CELL_ENV = "ALGRASP_CELL"
_FLAGS = {"support_friction": ("--support-friction", "--friction"), "jaw_friction": ("--jaw-friction",),
          "part_mass_kg": ("--part-mass-kg",), "grip_force_n": ("--grip-force-n",)}
_LENGTHS = {"com_tolerance": "radius of the centre-of-mass disk, part units (default 1 %% of the part's size)",
            "shape_tolerance": "slope error σ of the drawing, part units per radian (default: from the drawing)",
            "profile_tolerance": "manufacturing profile tolerance, part units: the floor of σ "
                                 "(default ISO 2768-1 class f for the part's size)"}


def span(text: str) -> list[float]:
    """``0.3`` or ``0.05,0.6`` as a list of numbers (checked later by Physics)."""
    try:
        values = [float(x) for x in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number or LO,HI, got {text!r}") from None
    if len(values) not in (1, 2):
        raise argparse.ArgumentTypeError(f"expected a number or LO,HI, got {text!r}")
    return values


def add_physics_options(g: Any) -> None:
    """Add the physics flags to an argument group."""
    g.add_argument("--cell", metavar="NAME|JSON", help=f"the cell the flags below refine: {', '.join(PRESETS)} "
                   f"or a JSON object of physics keys (default ${CELL_ENV} or 'default')")
    for key, flags in _FLAGS.items():
        p = PARAMETERS[key]
        lo, hi = DEFAULT_RANGES[key]
        text = f"{p.help}{' in ' + p.unit if p.unit else ''} (default {lo:g},{hi:g}: {p.source})"
        # argparse %-formats help strings: a literal "%" (the sources say "±20 %") must be doubled
        g.add_argument(*flags, dest=f"physics_{key}", type=span, metavar="V|LO,HI", help=text.replace("%", "%%"))
    for key, text in _LENGTHS.items():
        g.add_argument(f"--{key.replace('_', '-')}", dest=f"physics_{key}", type=float, metavar="T", help=text)
    g.add_argument("--placement", dest="physics_placement", choices=[*PLACEMENTS, "random"],
                   help="where the part lies between the open jaws: centred, or any offset (default any; "
                        "'random' is read as any); validation places it the same way")


def env_cell() -> Physics:
    """The cell $ALGRASP_CELL names (default: the real-cell defaults)."""
    return cell_from_text(os.environ.get(CELL_ENV) or "default", CELL_ENV)


def physics_from_args(args: argparse.Namespace) -> Physics:
    """The cell (``--cell`` or $ALGRASP_CELL) refined by the given flags."""
    given_cell = getattr(args, "cell", None)
    cell = cell_from_text(given_cell, "--cell") if given_cell else env_cell()
    keys = [*_FLAGS, *_LENGTHS, "placement"]
    given = {k: getattr(args, f"physics_{k}") for k in keys if getattr(args, f"physics_{k}", None) is not None}
    return cell.merged(given)


def describe(physics: dict[str, Any]) -> str:
    """One line of a plan's physics (its ``dead_band`` object: ranges as [lo, hi])."""
    def rng(key: str, unit: str = "") -> str:
        lo, hi = physics[key]
        return f"{lo:g}{unit}" if lo == hi else f"{lo:g}–{hi:g}{unit}"

    com = physics.get("com_tolerance")
    return (f"support μ {rng('support_friction')}, jaw μ {rng('jaw_friction')}, mass {rng('part_mass_kg', ' kg')}, "
            f"force {rng('grip_force_n', ' N')}, centre of mass ± {com:.3g}, profile tolerance "
            f"{physics.get('profile_floor_per_rad', 0.0):.3g}, placement {physics['placement']}")
