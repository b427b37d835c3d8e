"""The cell's physics as ranges (docs/conventions.md §8): the one options type.

A real cell is known only to within ranges, and a plan must hold for every cell in them.
:class:`Physics` holds each parameter as a closed range ``(lo, hi)`` (one value is
``(v, v)``), checks every bound in one place (:data:`PARAMETERS`), and is what the CLI
flags, the HTTP ``physics`` object, the Python API, batch jobs and run records are built
from. Pure: no I/O.

Defaults describe a real cell (sources in :data:`PARAMETERS`):

>>> p = Physics()
>>> p.jaw_friction, p.placement
((0.0, 0.1), 'any')
>>> Physics.from_mapping({"jaw_friction": [0, 0.2], "part_mass_kg": 0.01}).part_mass_kg
(0.01, 0.01)
>>> round(Physics.from_mapping({"support_friction": 0.3}).stall_ratio[0], 4)  # μ m g / F, least
0.0123
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, fields, replace
from typing import Any, Literal, NamedTuple

from algrasp.errors import ConfigError

Span = tuple[float, float]
Placement = Literal["centred", "any"]
PLACEMENTS: tuple[str, ...] = ("centred", "any")


class Parameter(NamedTuple):
    """One physical parameter: bounds any value must lie in, unit, and why its default."""

    lo: float
    hi: float
    unit: str
    help: str
    source: str
    lo_open: bool = False


PARAMETERS: dict[str, Parameter] = {
    "support_friction": Parameter(0.0, 10.0, "", "Coulomb friction μ_s between part and support",
                                  "dry machined metal or plastic on a steel or anodised table, 0.2–0.45 "
                                  "(handbook static/kinetic coefficients; greased steel is 0.1–0.16)"),
    "jaw_friction": Parameter(0.0, 10.0, "", "Coulomb friction μ_j between part and jaws (both jaws, pushing too)",
                              "PTFE-faced jaws against metal, 0.04–0.1 (0 with a linear bearing, as in the paper); "
                              "bare aluminium or steel jaws are 0.2–0.4: give those with --jaw-friction"),
    "part_mass_kg": Parameter(0.0, 1000.0, "kg", "part mass",
                              "a small sheet-metal or moulded part, 10–50 g"),
    "grip_force_n": Parameter(0.0, 1e5, "N", "grip (and push) force of the jaw servo",
                              "a 2 N setting of a small electric gripper, ±20 % force accuracy", lo_open=True),
    "gravity_m_s2": Parameter(0.0, 100.0, "m/s²", "gravity", "standard gravity"),
}
"""Range parameters, their bounds and the sources of their defaults."""

DEFAULT_RANGES: dict[str, Span] = {
    "support_friction": (0.2, 0.45), "jaw_friction": (0.0, 0.1), "part_mass_kg": (0.01, 0.05),
    "grip_force_n": (1.6, 2.4), "gravity_m_s2": (9.81, 9.81),
}
COM_TOLERANCE_REL = 0.01
"""Default radius of the centre-of-mass disk, relative to the part's size: density
varies by about 1 % across cut sheet or moulded stock."""
SCALARS = ("com_tolerance", "shape_tolerance", "profile_tolerance")
"""Non-negative lengths in part units (or per radian); None derives them from the part."""

# ISO 2768-1 class f ("fine"), permissible deviation of linear sizes (mm) by nominal size:
# a laser- or water-jet-cut part is at least this far from its drawing.
ISO_2768_F_MM: tuple[tuple[float, float], ...] = ((6.0, 0.05), (30.0, 0.1), (120.0, 0.15), (400.0, 0.2),
                                                  (1000.0, 0.3), (2000.0, 0.5), (math.inf, 1.0))


def iso_2768_f_mm(size_mm: float) -> float:
    """The class-f deviation (mm) for a part of nominal size ``size_mm`` (mm).

    >>> iso_2768_f_mm(5.0), iso_2768_f_mm(50.0)
    (0.05, 0.15)
    """
    return next(t for top, t in ISO_2768_F_MM if size_mm <= top)


def _span(name: str, value: Any) -> Span:
    """A number or a pair [lo, hi] as a checked range (field ``physics.name`` in errors)."""
    where = f"physics.{name}"
    if isinstance(value, (list, tuple)):
        if len(value) not in (1, 2):
            raise ConfigError(where, f"expected a number or [lo, hi], got {len(value)} values")
        lo, hi = (value[0], value[-1])
    else:
        lo = hi = value
    p = PARAMETERS[name]
    for v in (lo, hi):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise ConfigError(where, f"expected finite numbers, got {v!r}")
        if not (p.lo <= v <= p.hi) or (p.lo_open and v <= p.lo):
            raise ConfigError(where, f"must be in {'(' if p.lo_open else '['}{p.lo:g}, {p.hi:g}], got {v!r}")
    if lo > hi:
        raise ConfigError(where, f"range [{lo}, {hi}] has lo > hi")
    return float(lo), float(hi)


def _length(name: str, value: Any) -> float | None:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not (math.isfinite(value) and 0 <= value <= 1e6):
        raise ConfigError(f"physics.{name}", f"must be a finite number in [0, 1e6] (part units), got {value!r}")
    return float(value)


@dataclass(frozen=True)
class Physics:
    """The cell's physics: each range field is ``(lo, hi)`` in SI units (numbers are
    accepted and become ``(v, v)``); lengths are in the part's units. Every bound is checked
    (:data:`PARAMETERS`); :data:`DEFAULT_PHYSICS` is the real cell of conventions §8.

    Parameters
    ----------
    support_friction : (float, float)
        Coulomb friction μ_s between part and support (default 0.2–0.45).
    jaw_friction : (float, float)
        Coulomb friction μ_j between part and jaws, both jaws, pushing too (default 0–0.1).
    part_mass_kg : (float, float)
        Part mass (kg; default 0.01–0.05).
    grip_force_n : (float, float)
        Grip (and push) force of the jaw servo (N; default 1.6–2.4).
    gravity_m_s2 : (float, float)
        Gravity (m/s²; default 9.81).
    com_tolerance : float or None
        Radius of the centre-of-mass disk (part units); None: 1 % of size.
    shape_tolerance : float or None
        σ, slope error per jaw (part units per radian); None: the drawing's own error,
        never below the manufacturing profile tolerance.
    profile_tolerance : float or None
        The manufacturing floor of σ (part units, taken per radian); None: ISO 2768-1
        class f for the part's size.
    placement : {"any", "centred"}
        ``centred`` (both jaws touch together) or ``any`` offset.
    creep : bool
        Whether a part may creep downhill where friction could hold it (vibration of a real
        cell, the regularised friction of the simulation): then rest is never certain short
        of a minimum, and a plan's uncertainty covers every dead zone down to its minimum.

    Raises
    ------
    ConfigError
        Naming the field (``physics.<key>``) out of its bounds.

    Examples
    --------
    >>> p = Physics(jaw_friction=0.2)
    >>> p.jaw_friction, p.exact_cell, DEFAULT_PHYSICS.placement, p.to_dict()["grip_force_n"]
    ((0.2, 0.2), False, 'any', [1.6, 2.4])
    >>> Physics(part_mass_kg=-1)
    Traceback (most recent call last):
    ...
    algrasp.errors.ConfigError: physics.part_mass_kg: must be in [0, 1000], got -1
    """

    support_friction: Span = DEFAULT_RANGES["support_friction"]
    jaw_friction: Span = DEFAULT_RANGES["jaw_friction"]
    part_mass_kg: Span = DEFAULT_RANGES["part_mass_kg"]
    grip_force_n: Span = DEFAULT_RANGES["grip_force_n"]
    gravity_m_s2: Span = DEFAULT_RANGES["gravity_m_s2"]
    com_tolerance: float | None = None
    shape_tolerance: float | None = None
    profile_tolerance: float | None = None
    placement: Placement = "any"
    creep: bool = True

    def __post_init__(self) -> None:
        for name in _CHECKED:
            object.__setattr__(self, name, _checked(name, getattr(self, name)))

    @staticmethod
    def from_mapping(raw: Any) -> Physics:
        """From a JSON-like object (HTTP ``physics``, records, batch options); unknown keys
        and bad values are refused naming ``physics.<key>``. ``random`` is read as ``any``."""
        if raw is None:
            return Physics()
        if not isinstance(raw, Mapping):
            raise ConfigError("physics", "expected an object")
        known = {f.name for f in fields(Physics)}
        unknown = sorted(set(raw) - known)
        if unknown:
            raise ConfigError(f"physics.{unknown[0]}", f"unknown key (known: {', '.join(sorted(known))})")
        values = dict(raw)
        if values.get("placement") == "random":
            values["placement"] = "any"
        if "placement" in values and not isinstance(values["placement"], str):
            raise ConfigError("physics.placement", f"expected one of {', '.join(PLACEMENTS)}")
        return Physics(**values)

    def merged(self, overrides: Any) -> Physics:
        """This physics with the keys of ``overrides`` (a request's ``physics`` object)
        replaced, checked like :meth:`from_mapping`."""
        if not overrides:
            return self
        if not isinstance(overrides, Mapping):
            raise ConfigError("physics", "expected an object")
        return Physics.from_mapping({**self.to_dict(), **overrides})

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: ranges as ``[lo, hi]``."""
        return {name: list(v) if isinstance(v := getattr(self, name), tuple) else v for name in _FIELDS}

    def differences(self) -> dict[str, Any]:
        """The fields that differ from the defaults (what a run record keeps)."""
        base = Physics().to_dict()
        return {k: v for k, v in self.to_dict().items() if v != base[k]}

    @property
    def stall_ratio(self) -> Span:
        """μ_s m g / F (dimensionless), least and most over the ranges: s = ratio · r̄."""
        (ml, mh), (ql, qh), (fl, fh), (gl, gh) = self.support_friction, self.part_mass_kg, self.grip_force_n, \
            self.gravity_m_s2
        return ml * ql * gl / fh, mh * qh * gh / fl

    @property
    def exact_cell(self) -> bool:
        """One value of every range (a single cell)."""
        return all(getattr(self, n)[0] == getattr(self, n)[1] for n in PARAMETERS)

    def with_range(self, name: str, span: Span) -> Physics:
        return self.with_values(**{name: span})

    def with_values(self, **values: Any) -> Physics:
        """A copy with the given fields replaced, each checked as at construction (the
        others already were; a limit search makes a copy per probe). O(fields given)."""
        if not values.keys() <= _CHECKED.keys():
            return replace(self, **values)  # an unknown field: dataclasses' own TypeError
        new = object.__new__(Physics)
        new.__dict__.update(self.__dict__)
        for name in _CHECKED:
            if name in values:
                object.__setattr__(new, name, _checked(name, values[name]))
        return new

    def corners(self) -> Iterator[Physics]:
        """Every corner of the box of ranges (one cell each), degenerate axes once."""
        axes = [sorted(set(getattr(self, n))) for n in PARAMETERS]
        for values in itertools.product(*axes):
            yield self.with_values(**{n: (v, v) for n, v in zip(PARAMETERS, values)})


def _checked(name: str, value: Any) -> Any:
    """One field of :class:`Physics` checked (and ranges made float pairs), naming
    ``physics.<name>`` in errors."""
    if name in PARAMETERS:
        return _span(name, value)
    if name in SCALARS:
        return _length(name, value)
    if name == "creep" and not isinstance(value, bool):
        raise ConfigError("physics.creep", f"expected true or false, got {value!r}")
    if name == "placement" and value not in PLACEMENTS:
        raise ConfigError("physics.placement", f"expected one of {', '.join(PLACEMENTS)}, got {value!r}")
    return value


_CHECKED: dict[str, None] = dict.fromkeys((*PARAMETERS, *SCALARS, "creep", "placement"))
"""The fields of :class:`Physics` in the order they are checked."""


_FIELDS: tuple[str, ...] = tuple(f.name for f in fields(Physics))
"""The fields of :class:`Physics` in their order (what :meth:`Physics.to_dict` writes)."""

DEFAULT_PHYSICS = Physics()
IDEAL_CELL = Physics(support_friction=(0.3, 0.3), jaw_friction=(0.0, 0.0), part_mass_kg=(0.02, 0.02),
                     grip_force_n=(2.0, 2.0), com_tolerance=0.0, profile_tolerance=0.0, placement="centred", creep=False)
"""The one ideal cell earlier plans assumed: frictionless jaws, support μ exactly 0.3,
20 g, 2 N, the part exactly as drawn (σ only from the drawing's own error), uniform
density, jaws centred on the part and Coulomb friction that stalls without creeping
(conventions §7 alone)."""
PRESETS: dict[str, Physics] = {"default": DEFAULT_PHYSICS, "ideal": IDEAL_CELL}
"""Named cells: what ``--cell NAME`` and ``ALGRASP_CELL=NAME`` select."""


def cell_from_text(text: str, where: str = "cell") -> Physics:
    """A cell's physics from a preset name (``default``, ``ideal``) or a JSON object of
    physics keys over the defaults (what ``--cell`` and ``ALGRASP_CELL`` hold).

    >>> cell_from_text('{"jaw_friction": [0, 0.3]}').jaw_friction
    (0.0, 0.3)
    """
    import json

    name = text.strip()
    if name in PRESETS:
        return PRESETS[name]
    try:
        raw = json.loads(name)
    except ValueError:
        raise ConfigError(where, f"expected {' or '.join(PRESETS)} or a JSON object of physics keys, got {text[:60]!r}") from None
    if not isinstance(raw, dict):
        raise ConfigError(where, "expected a JSON object of physics keys")
    return DEFAULT_PHYSICS.merged(raw)
