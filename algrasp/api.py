"""The public Python API: a part in, its analysis and plan out, in a few calls.

Everything here is re-exported by ``algrasp`` itself (``from algrasp import plan``).
Angles inside the returned objects are radians; their ``to_dict()`` documents use degrees
(conventions §5), as the CLI's ``--json`` and the HTTP API do.

>>> from algrasp import analyse, load_part, plan
>>> square = {"name": "square", "boundary": [[0, 0], [4, 0], [4, 4], [0, 4]]}
>>> part = load_part(square)
>>> round(part.area, 9), part.center_of_mass
(16.0, (2.0, 2.0))
>>> p = plan(square, "squeeze", exact=True)
>>> len(p.steps), round(p.symmetry_period * 180 / 3.141592653589793, 6)
(1, 90.0)
>>> p.to_dict()["action"]
'squeeze'
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any, Literal

from algrasp.errors import ConfigError
from algrasp.geometry.part import Part
from algrasp.geometry.part import load_part as _load_part
from algrasp.planning.analysis import Analysis, Model, analyse_document
from algrasp.planning.deadband import DEFAULT_PHYSICS, Physics
from algrasp.planning.plans import LimitsWanted, Plan, make_plan

PartSource = Mapping[str, Any] | str | Path
"""A part document (a mapping), or the path of a part document (``.json``) or of a
drawing/mesh (``.dxf``, ``.svg``, ``.stl``, …)."""
Action = Literal["squeeze", "push_grasp"]


def import_drawing(path: str | Path, **options: Any) -> dict[str, Any]:
    """The part document of a DXF/SVG drawing or a mesh (exact curves; meshes give an
    approximate polygon). ``options``: ``layer``, ``element_id``, ``pose``, ``part`` (one
    of several parts on a sheet), ``tolerance``, ``units`` — as ``algrasp import``.
    Raises PartDocumentError naming the entity (and the parts to choose from)."""
    from algrasp.io.cad import import_file

    return import_file(str(path), **options)


def document(source: PartSource, **import_options: Any) -> dict[str, Any]:
    """The part document of ``source`` (a mapping is returned as a dict)."""
    from algrasp.io.parts import read_part_file

    return dict(source) if isinstance(source, Mapping) else read_part_file(source, **import_options)


def load_part(source: PartSource, **import_options: Any) -> Part:
    """A validated :class:`Part` (exact geometry, area, centre of mass, convex hull).
    Complexity: O(N log N) in the number of segments."""
    return _load_part(document(source, **import_options))


PhysicsSource = Physics | Mapping[str, Any] | None
"""A :class:`Physics`, or physics keys (numbers or ``[lo, hi]``) over the cell
$ALGRASP_CELL names (default: the real-cell defaults of conventions §8)."""


def model(exact: bool = False, physics: PhysicsSource = None) -> Model:
    """The robust model over the cell's physics ranges (conventions §8) or, with
    ``exact``, the paper's frictionless one.

    >>> model(physics={"jaw_friction": [0, 0.2]}).physics.jaw_friction
    (0.0, 0.2)
    """
    if isinstance(physics, Physics):
        return Model(exact, physics)
    from algrasp.cli_physics import env_cell

    return Model.from_options({"exact": exact, "physics": dict(physics or {})}, cell=env_cell())


def analyse(source: PartSource, *, exact: bool = False, physics: PhysicsSource = None) -> Analysis:
    """Diameter and radius functions, squeeze and push-grasp transfer functions and both
    shortest plans' inputs (:class:`Analysis`). Milliseconds for polygons, tens of
    milliseconds for curved parts."""
    return analyse_document(document(source), model(exact, physics))


def plan(source: PartSource | Analysis, action: Action = "squeeze", *, min_margin_deg: float = 0.0,
         exact: bool = False, physics: PhysicsSource = None, limits: LimitsWanted = "headline") -> Plan:
    """The shortest plan (Algorithm A′) that brings the part from any orientation to as
    few as its symmetry allows, holding in every cell of the physics ranges;
    ``min_margin_deg``: every transition tolerates that much gripper error; ``limits``:
    which physics limits to search (``plan.limits``). Raises NotOrientableError (with its
    reason and the limits under which a plan exists) when no plan exists."""
    if action not in ("squeeze", "push_grasp"):
        raise ConfigError("action", f"expected squeeze or push_grasp, got {action!r}")
    analysis = source if isinstance(source, Analysis) else analyse(source, exact=exact, physics=physics)
    return make_plan(analysis, action, min_margin_deg, "none" if analysis.robust is None else limits)


def validate(source: PartSource, action: Action = "squeeze", *, samples: int = 36, seed: int = 0,
             placement: Literal["centred", "random"] | None = None, tolerance_deg: float = 1.0, optimise: bool = False,
             exact: bool = False, physics: PhysicsSource = None, sim_physics: str = "nominal",
             workers: int = 2) -> dict[str, Any]:
    """Simulate the plan in Drake from ``samples`` start orientations in each cell
    ``sim_physics`` names (``nominal``, ``corners``, ``random``, ``KEY=VALUE,...``; needs
    the ``sim`` extra); returns the validation document (``agreement``, per-sample
    outcomes, per-cell agreement). ``placement`` None follows the physics."""
    from algrasp.io.record.session import recording
    from algrasp.pipeline import PlanRequest, plan_part

    doc = document(source)
    m = model(exact, physics)
    req = PlanRequest(action=action, optimise=optimise, samples=samples, seed=seed, placement=placement,
                      tolerance_deg=tolerance_deg, exact=exact, physics=m.physics.to_dict(), sim_physics=sim_physics)
    with recording(False, None, "validate", doc, req.record_options()) as rec:
        out = plan_part(doc, req, rec, sim_workers=workers, record_sim=False)
    v = out.validation_doc()
    assert v is not None  # samples > 0
    return v


__all__ = ["DEFAULT_PHYSICS", "Action", "Analysis", "Model", "Part", "PartSource", "Physics", "Plan", "analyse",
           "document", "import_drawing", "load_part", "model", "plan", "validate"]
