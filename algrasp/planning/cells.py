"""Cells of the physics ranges to simulate (``--sim-physics``): pure, no I/O.

* ``nominal``: the middle of every range, the drawn centre of mass;
* ``corners``: every corner of the box of ranges, the centre of mass on the rim of its
  disk (a seeded direction per corner);
* ``random``: ``count`` cells uniform in the box, the centre of mass uniform in its disk;
* ``KEY=VALUE,...``: one cell of explicit values over the middle of the ranges, e.g.
  ``support_friction=0.05,jaw_friction=0.2,part_mass_kg=0.005,com_offset=0.5,0``
  (``com_offset`` in part units, x then y).

>>> [c.label for c in sim_cells(parse_cells("jaw_friction=0.2,com_offset=0.5,0"), Physics(), 0.1, 1, 0)]
['jaw_friction=0.2, com_offset=(0.5, 0)']
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from algrasp.errors import ConfigError
from algrasp.planning.physics import PARAMETERS, Physics

MODES = ("nominal", "corners", "random")
FIELD = "sim_physics"


@dataclass(frozen=True)
class Cell:
    """One simulated cell: single-valued physics and the true centre of mass's offset
    from the drawn one (part units, part frame)."""

    physics: Physics
    com_offset: tuple[float, float]
    label: str

    def to_dict(self) -> dict[str, object]:
        p = self.physics
        return {"label": self.label, **{k: getattr(p, k)[0] for k in PARAMETERS}, "com_offset": list(self.com_offset)}


def parse_cells(text: str) -> str | dict[str, object]:
    """A mode name or the explicit cell's values; ConfigError naming ``sim_physics``."""
    text = text.strip()
    if text in MODES:
        return text
    values: dict[str, object] = {}
    offset: list[float] = []
    last = ""
    for token in text.split(","):
        if "=" not in token:
            if last != "com_offset":
                raise ConfigError(FIELD, f"expected {', '.join(MODES)} or KEY=VALUE,..., got {text[:80]!r}")
            offset.append(_number(token))
            continue
        key, _, value = token.partition("=")
        key = key.strip()
        if key not in (*PARAMETERS, "com_offset"):
            raise ConfigError(FIELD, f"unknown key {key!r} (known: {', '.join((*PARAMETERS, 'com_offset'))})")
        if key == "com_offset":
            offset.append(_number(value))
            values[key] = offset
        else:
            values[key] = _number(value)
        last = key
    if "com_offset" in values and len(offset) != 2:
        raise ConfigError(FIELD, "com_offset needs two numbers: X,Y in part units")
    return values


def _number(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise ConfigError(FIELD, f"expected a number, got {text!r}") from None
    if not math.isfinite(v):
        raise ConfigError(FIELD, f"expected a finite number, got {text!r}")
    return v


def _nominal(physics: Physics) -> Physics:
    return physics.with_values(**{k: (0.5 * sum(getattr(physics, k)),) * 2 for k in PARAMETERS})


def sim_cells(spec: str | dict[str, object], physics: Physics, com_radius: float, count: int, seed: int) -> list[Cell]:
    """The cells ``spec`` (:func:`parse_cells`) names for a plan made under ``physics``
    whose centre-of-mass disk has radius ``com_radius`` (part units)."""
    rng = np.random.default_rng(seed)
    if spec == "nominal":
        return [Cell(_nominal(physics), (0.0, 0.0), "nominal")]
    if spec == "corners":
        out = []
        for corner in physics.corners():
            a = float(rng.uniform(0.0, 2.0 * math.pi))
            label = ", ".join(f"{k}={getattr(corner, k)[0]:g}" for k in PARAMETERS if getattr(physics, k)[0] != getattr(physics, k)[1])
            out.append(Cell(corner, (com_radius * math.cos(a), com_radius * math.sin(a)), label or "the only cell"))
        return out
    if spec == "random":
        return [_random_cell(physics, com_radius, rng, i) for i in range(count)]
    assert isinstance(spec, dict)
    base = _nominal(physics)
    given = {k: v for k, v in spec.items() if k != "com_offset"}
    cell = base.merged({k: [v, v] for k, v in given.items()})
    off = spec.get("com_offset", [0.0, 0.0])
    assert isinstance(off, list)
    words = [f"{k}={v:g}" for k, v in given.items()]
    if "com_offset" in spec:
        words.append(f"com_offset=({off[0]:g}, {off[1]:g})")
    label = ", ".join(words)
    return [Cell(cell, (float(off[0]), float(off[1])), label)]


def _random_cell(physics: Physics, com_radius: float, rng: np.random.Generator, i: int) -> Cell:
    values = {k: (v := float(rng.uniform(*getattr(physics, k))), v) for k in PARAMETERS}
    r, a = com_radius * math.sqrt(float(rng.uniform())), float(rng.uniform(0.0, 2.0 * math.pi))
    return Cell(physics.with_values(**values), (r * math.cos(a), r * math.sin(a)), f"random {i + 1}")
