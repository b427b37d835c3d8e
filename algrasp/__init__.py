"""algrasp: sensorless orienting of algebraic planar parts with a parallel-jaw gripper.

The public API (see :mod:`algrasp.api` and the README's "Python API")::

    from algrasp import load_part, analyse, plan, validate, import_drawing

Names are imported on first use, so ``import algrasp`` (and the CLI) stays cheap.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

__version__ = "0.1.0"

_API = {
    "load_part": "algrasp.api", "analyse": "algrasp.api", "plan": "algrasp.api", "validate": "algrasp.api",
    "import_drawing": "algrasp.api", "document": "algrasp.api", "fences": "algrasp.api", "model": "algrasp.api",
    "validate_fences": "algrasp.api", "Drawing": "algrasp.api",
    "Validation": "algrasp.sim.validate",
    "Part": "algrasp.geometry.part", "Tolerances": "algrasp.geometry.tolerances",
    "DEFAULT_TOLERANCES": "algrasp.geometry.tolerances",
    "Analysis": "algrasp.planning.analysis", "Plan": "algrasp.planning.plans", "Model": "algrasp.planning.analysis",
    "Physics": "algrasp.planning.deadband", "DEFAULT_PHYSICS": "algrasp.planning.deadband",
    "AlgraspError": "algrasp.errors", "PartDocumentError": "algrasp.errors", "LimitExceededError": "algrasp.errors",
    "GeometryError": "algrasp.errors", "NotOrientableError": "algrasp.errors", "ConfigError": "algrasp.errors",
    "SimulationError": "algrasp.errors", "TimeLimitError": "algrasp.errors", "UnavailableError": "algrasp.errors",
    "StorageError": "algrasp.errors",
}
__all__ = ["AlgraspError", "Analysis", "ConfigError", "DEFAULT_PHYSICS", "DEFAULT_TOLERANCES", "Drawing",
           "GeometryError", "LimitExceededError", "Model", "NotOrientableError", "Part", "PartDocumentError",
           "Physics", "Plan", "SimulationError", "StorageError", "TimeLimitError", "Tolerances",
           "UnavailableError", "Validation", "analyse", "document", "fences", "import_drawing", "load_part", "model", "plan",
           "validate", "validate_fences"]
# (kept literal for linters; a test checks it equals the lazy table)

if TYPE_CHECKING:  # pragma: no cover - for type checkers and IDEs
    from algrasp.api import (
        Drawing,
        analyse,
        document,
        fences,
        import_drawing,
        load_part,
        model,
        plan,
        validate,
        validate_fences,
    )
    from algrasp.errors import (
        AlgraspError,
        ConfigError,
        GeometryError,
        LimitExceededError,
        NotOrientableError,
        PartDocumentError,
        SimulationError,
        StorageError,
        TimeLimitError,
        UnavailableError,
    )
    from algrasp.geometry.part import Part
    from algrasp.geometry.tolerances import DEFAULT_TOLERANCES, Tolerances
    from algrasp.planning.analysis import Analysis, Model
    from algrasp.planning.deadband import DEFAULT_PHYSICS, Physics
    from algrasp.planning.plans import Plan
    from algrasp.sim.validate import Validation


def __getattr__(name: str) -> Any:
    import importlib

    if name not in _API:
        raise AttributeError(f"module 'algrasp' has no attribute {name!r}")
    value = getattr(importlib.import_module(_API[name]), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted([*globals(), *_API])
