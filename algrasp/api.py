"""The public Python API: a part in, its analysis and plan out, in a few calls.

Everything here is re-exported by ``algrasp`` itself (``from algrasp import plan``). Each
function accepts what the others return — a part document (mapping), a path (``.json``
part document, drawing or mesh), a :class:`Drawing`, a :class:`Part`, an
:class:`Analysis` or a :class:`Plan` — and options are keyword-only. Angles inside the
returned objects are radians; their ``to_dict()`` documents use degrees
(docs/conventions.md §1), as the CLI's ``--json`` and the HTTP API do. A wrong argument
is a :class:`~algrasp.errors.ConfigError` naming it (``field``).

>>> from algrasp import analyse, load_part, plan
>>> square = {"name": "square", "boundary": [[0, 0], [4, 0], [4, 4], [0, 4]]}
>>> part = load_part(square)
>>> round(part.area, 9), part.center_of_mass
(16.0, (2.0, 2.0))
>>> p = plan(part, action="squeeze", exact=True)
>>> len(p.steps), round(p.symmetry_period * 180 / 3.141592653589793, 6)
(1, 90.0)
>>> p.to_dict()["action"], plan(p.analysis, action="push-grasp").action
('squeeze', 'push_grasp')
>>> plan(42)
Traceback (most recent call last):
...
algrasp.errors.ConfigError: source: expected a part document (mapping), a path, a Drawing, a Part, an Analysis or a Plan, got int

Validation (:func:`validate`) starts simulation worker processes with the ``spawn``
method, which imports the calling script again in each worker: a script that calls
``validate`` keeps its work under ``if __name__ == "__main__":`` (the README's example).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from algrasp.errors import ConfigError
from algrasp.geometry.part import Part
from algrasp.geometry.part import load_part as _load_part
from algrasp.planning.actions import Action, parse_action
from algrasp.planning.analysis import Analysis, Model, analyse_part
from algrasp.planning.deadband import DEFAULT_PHYSICS, Physics
from algrasp.planning.plans import LimitsWanted, Plan, make_plan

if TYPE_CHECKING:  # the layout layer loads on first use
    from optimisation.fence_layout import FenceLayout


@dataclass(frozen=True)
class Drawing:
    """A drawing (DXF, SVG) or mesh imported as one part: its part document (exact
    curves; a mesh gives an approximate polygon) and what the import noticed.

    Attributes
    ----------
    document : Mapping[str, Any]
        The part document (lengths in ``units``; ``source`` says where from).
    warnings : tuple of str
        What was assumed or set aside (units read, gaps closed, clutter).
    name, units : str
        The document's ``name`` (``""`` if none) and length unit (default ``"mm"``).

    Examples
    --------
    >>> d = Drawing({"name": "r", "units": "mm", "boundary": [[0, 0], [4, 0], [4, 2], [0, 2]]})
    >>> d.name, d.units, d.warnings, load_part(d).area
    ('r', 'mm', (), 8.0)
    """

    document: Mapping[str, Any]
    warnings: tuple[str, ...] = ()

    @property
    def name(self) -> str:
        return str(self.document.get("name", ""))

    @property
    def units(self) -> str:
        return str(self.document.get("units", "mm"))

    def to_dict(self) -> dict[str, Any]:
        """The part document (as ``algrasp import`` writes it)."""
        return dict(self.document)


PartSource = Mapping[str, Any] | str | Path | Drawing | Part | Analysis | Plan
"""What names a part: a part document, the path of a part document (``.json``) or of a
drawing/mesh (``.dxf``, ``.svg``, ``.stl``, …), or any result of this API."""
PhysicsSource = Physics | Mapping[str, Any] | None
"""A :class:`Physics`, or physics keys (numbers or ``[lo, hi]``) over the cell
$ALGRASP_CELL names (default: the real-cell defaults of docs/conventions.md §8)."""
GripperSource = Mapping[str, Any] | str | Path | Any
"""A gripper profile: a mapping of its keys, a YAML/JSON file, or a ``GripperProfile``."""
_KINDS = "a part document (mapping), a path, a Drawing, a Part, an Analysis or a Plan"


def import_drawing(path: str | Path, **options: Any) -> Drawing:
    """The :class:`Drawing` of a DXF/SVG drawing or a mesh (the ``cad`` extra).

    Parameters
    ----------
    path : str or Path
        The drawing (``.dxf``, ``.svg``) or mesh (``.stl``, …).
    **options
        As ``algrasp import``: ``layer``, ``element_id``, ``pose``, ``part`` (one of
        several parts on a sheet), ``tolerance``, ``units``.

    Returns
    -------
    Drawing
        Its part document and warnings; a fence layout DXF (``algrasp fences --dxf``) gives
        its layout document instead (``kind`` "fence_layout", the fences' ``side``,
        ``angle_deg``, ``position``, ``length`` in the file's unit), which no planner takes.

    Raises
    ------
    PartDocumentError
        Naming the entity (and the parts to choose from).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     svg = pathlib.Path(tmp, "plate.svg")
    ...     _ = svg.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="40mm" height="20mm" '
    ...                        'viewBox="0 0 40 20"><rect width="40" height="20"/></svg>')
    ...     plate = import_drawing(svg)
    >>> plate.name, plate.units, len(plate.document["boundary"]), load_part(plate).area
    ('plate', 'mm', 4, 800.0)
    """
    from algrasp.io.cad import import_file

    if not isinstance(path, (str, Path)):
        raise ConfigError("path", f"expected the path of a drawing or mesh, got {type(path).__name__}")
    doc = import_file(str(path), **options)
    return Drawing(doc, tuple(str(w) for w in doc.get("source", {}).get("warnings", ())))


def document(source: PartSource, **import_options: Any) -> dict[str, Any]:
    """The part document of ``source`` (a new dict).

    Parameters
    ----------
    source : PartSource
        A part document, a path (``.json``, drawing or mesh), a :class:`Drawing`, a
        :class:`Part`, an :class:`Analysis` or a :class:`Plan`.
    **import_options
        Apply to drawings (as :func:`import_drawing`).

    Returns
    -------
    dict
        The part document.

    Examples
    --------
    >>> rect = {"name": "r", "boundary": [[0, 0], [4, 0], [4, 2], [0, 2]]}
    >>> document(plan(rect, exact=True)) == rect
    True
    """
    if isinstance(source, Mapping):
        return dict(source)
    if isinstance(source, Drawing):
        from algrasp.io.fence_import import refuse_layout

        return refuse_layout(dict(source.document), "source")
    if isinstance(source, (str, Path)):
        from algrasp.io.parts import read_part_file

        return read_part_file(source, **import_options)
    return dict(_part_of(source).source_document)


def _part_of(source: object) -> Part:
    if isinstance(source, Part):
        return source
    if isinstance(source, Analysis):
        return source.part
    if isinstance(source, Plan) and source.analysis is not None:
        return source.analysis.part
    raise ConfigError("source", f"expected {_KINDS}, got {type(source).__name__}")


def load_part(source: PartSource, *, exact: bool = False, **import_options: Any) -> Part:
    """A validated :class:`Part` (exact geometry, area, centre of mass, convex hull), read
    as the model reads it: by default (the robust model) runs of polygon vertices that
    tessellate circular arcs become the arcs (``Part.recognised`` says so).
    Complexity: O(N log N) in the number of segments.

    Parameters
    ----------
    source : PartSource
        The part (as :func:`document`); a :class:`Part` without options is returned as it is.
    exact : bool, default False
        Keep every drawn segment (the paper's exact model).
    **import_options
        Apply to drawings (as :func:`import_drawing`).

    Returns
    -------
    Part
        Counter-clockwise, lengths in the document's ``units``.

    Raises
    ------
    PartDocumentError
        Naming the malformed field (``boundary[3].radius``) or the invalid loop.

    Examples
    --------
    >>> part = load_part({"name": "r", "boundary": [[0, 0], [4, 0], [4, 2], [0, 2]]})
    >>> part.area, part.center_of_mass, len(part.boundary), part.units
    (8.0, (2.0, 1.0), 4, 'mm')
    >>> load_part({"name": "r", "boundary": [[0, 0], [1, 0]]})
    Traceback (most recent call last):
    ...
    algrasp.errors.PartDocumentError: boundary: a polygon needs at least 3 vertices, got 2
    """
    if isinstance(source, Part) and not import_options:
        return source
    return _load_part(document(source, **import_options), snap=not exact)


def model(exact: bool = False, physics: PhysicsSource = None) -> Model:
    """The robust model over the cell's physics ranges (docs/conventions.md §8) or, with
    ``exact``, the paper's frictionless one.

    Parameters
    ----------
    exact : bool, default False
        The paper's exact frictionless model (the CLI's ``--exact``).
    physics : PhysicsSource
        A :class:`Physics`, or physics keys (numbers or ``[lo, hi]``) over the cell
        ``$ALGRASP_CELL`` names (default: the real cell).

    Returns
    -------
    Model

    Examples
    --------
    >>> model(physics={"jaw_friction": [0, 0.2]}).physics.jaw_friction
    (0.0, 0.2)
    """
    if not isinstance(exact, bool):
        raise ConfigError("exact", f"expected True or False, got {exact!r}")
    if isinstance(physics, Physics):
        return Model(exact, physics)
    if physics is not None and not isinstance(physics, Mapping):
        raise ConfigError("physics", f"expected a Physics or a mapping of physics keys, got {type(physics).__name__}")
    from algrasp.cli_physics import env_cell

    return Model.from_options({"exact": exact, "physics": dict(physics or {})}, cell=env_cell())


def model_of(analysis: Analysis) -> Model:
    """The model ``analysis`` was made under (the exact model simulates the cell
    $ALGRASP_CELL names, as :func:`model` does)."""
    return model(True) if analysis.robust is None else Model(False, analysis.robust.physics)


def analyse(source: PartSource, *, exact: bool | None = None, physics: PhysicsSource = None) -> Analysis:
    """Diameter and radius functions, squeeze and push-grasp transfer functions and both
    shortest plans' inputs. Milliseconds for polygons, tens of milliseconds for curved parts.

    Parameters
    ----------
    source : PartSource
        The part (as :func:`document`). An :class:`Analysis` or :class:`Plan` given is kept
        when no model is asked for, and re-analysed under the model asked for otherwise.
    exact : bool or None
        The paper's exact model; None: as the source was made, else the robust model.
    physics : PhysicsSource
        The robust model's physics ranges (as :func:`model`).

    Returns
    -------
    Analysis

    Examples
    --------
    >>> a = analyse({"name": "r", "boundary": [[0, 0], [4, 0], [4, 2], [0, 2]]}, exact=True)
    >>> a.squeeze_orientable, a.robust is None, a.to_dict()["squeeze"]["symmetry_period_deg"]
    (True, True, 180.0)
    """
    made = source.analysis if isinstance(source, Plan) else source
    if isinstance(made, Analysis):
        if exact is None and physics is None:
            return made
        wanted = model(model_of(made).exact if exact is None else exact, physics)
        if wanted == model_of(made):
            return made
    else:
        wanted = model(bool(exact), physics)
    part = _load_part(document(source), snap=not wanted.exact)
    return analyse_part(part, physics=None if wanted.exact else wanted.physics)


def plan(source: PartSource, *, action: Action | str = "squeeze", min_margin_deg: float = 0.0,
         exact: bool | None = None, physics: PhysicsSource = None, limits: LimitsWanted = "headline",
         optimise: bool = False, gripper: GripperSource | None = None, push_scale: float = 1.0) -> Plan:
    """The shortest plan (Algorithm A′) that brings the part from any orientation to as
    few as its symmetry allows, holding in every cell of the physics ranges.

    Parameters
    ----------
    source : PartSource
        The part (as :func:`analyse`, which keeps an analysis or plan given unless another
        model is asked for).
    action : {"squeeze", "push_grasp"}
        ``push-grasp`` is read as ``push_grasp``.
    min_margin_deg : float, default 0
        Every transition tolerates that much gripper error (degrees).
    exact, physics
        The model (as :func:`analyse`).
    limits : {"headline", "refusal", "none", "all"}
        Which physics limits to search (``plan.limits``; robust model only): ``headline``
        the largest jaw friction with a plan and every limit with a refusal; ``refusal``
        limits with a refusal only; ``none`` no search at all (a refusal says so); ``all``
        every limit either way.
    optimise : bool, default False
        Push distances, jaw timing and cycle time for the ``gripper`` profile (CasADi;
        ``plan.execution``, and its fields in ``plan.to_dict()``).
    gripper : mapping, path, GripperProfile or None
        The profile's keys, a YAML/JSON file or a profile; None: the default profile.
    push_scale : float, default 1
        Scales the optimised push distances.

    Returns
    -------
    Plan

    Raises
    ------
    NotOrientableError
        No plan exists (with its reason and the limits under which a plan exists).

    Examples
    --------
    >>> p = plan({"name": "r", "boundary": [[0, 0], [4, 0], [4, 2], [0, 2]]}, exact=True)
    >>> [s["gripper_angle_deg"] for s in p.to_dict()["steps"]], p.to_dict()["final_orientations_deg"]
    ([45.0, 0.0], [0.0, 180.0])
    """
    from algrasp.pipeline import PlanRequest, optimise_plan

    if not isinstance(optimise, bool):
        raise ConfigError("optimise", f"expected True or False, got {optimise!r}")
    # the request's options are checked where every interface's are (PlanRequest)
    req = PlanRequest(parse_action(action), _number(min_margin_deg, "min_margin_deg"), optimise, _gripper(gripper),
                      _number(push_scale, "push_scale"), limits=limits)
    analysis = analyse(source, exact=exact, physics=physics)
    out = make_plan(analysis, req.action, req.min_margin_deg, "none" if analysis.robust is None else req.limits)
    return optimise_plan(out, req.gripper_profile, req.push_scale) if optimise else out


def fences(source: PartSource, *, fence_friction: float | list[float] | tuple[float, float] | None = None,
           belt_width: float | None = None, min_margin_deg: float = 1.0, exact: bool | None = None,
           physics: PhysicsSource = None, tail: float | Mapping[str, Any] | None = None,
           exit_steepness_deg: float | None = None, exit_turns: bool = True, same_rail: bool = False) -> FenceLayout:
    """The fewest conveyor fences that bring the part from any orientation to one (up to
    its push function's symmetry), laid out on a belt moving along +x (conventions §9).

    Parameters
    ----------
    source : PartSource
        The part (as :func:`analyse`).
    fence_friction : float or [lo, hi], optional
        μ_f between part and fence (default 0.1–0.3: UHMW-PE rails); a fence slides the
        part along only when its angle to the belt is below 90° − atan μ_f,hi.
    belt_width : float, optional
        Between the rails (part units; default the least the design needs).
    min_margin_deg : float, default 1
        How far every fence angle may be off (degrees).
    exact, physics
        The model (as :func:`analyse`); ``physics.support_friction`` is the belt's.
    tail : float or {"radius", "sweep_deg"}, optional
        A curved tail on the last fence: an arc of that radius (part units) tangent to it
        at its tip, turning towards the belt by ``sweep_deg`` (default the fence's angle
        less the exit guide's: it ends tangent to the guide).
    exit_steepness_deg : float, optional
        The exit guide's angle to the belt (default 2°, at most 10°): a straight wall on the
        last fence's rail from its tip (or its tail's end) that takes the part back onto
        its edge after the tip has turned it; the claimed final orientations
        (``to_dict()["final_orientations_deg"]``) are past its end, ±β_e/2 wider.
    exit_turns : bool, default True
        Model the turn towards the belt (by up to the fence's angle to it) that a part
        takes as it comes off each fence's tip; False plans in Berretty et al.'s model,
        where it keeps its orientation between fences (Drake shows it does not).
    same_rail : bool, default False
        Let consecutive fences stand on one rail (the later one reaching further across the
        belt, past where the part comes off the earlier one's tip); by default they alternate.

    Returns
    -------
    FenceLayout
        ``optimisation.fence_layout.FenceLayout``: ``design`` (radians), lengths, positions,
        belt width; ``to_dict()`` is the fence document (degrees).

    Raises
    ------
    NotOrientableError
        No fence design exists (``limits["fence_friction_max"]``: the friction under which one would).

    Examples
    --------
    >>> out = fences({"name": "r", "boundary": [[0, 0], [4, 0], [4, 2], [0, 2]]}, exact=True)
    >>> len(out.to_dict()["fences"]), [f["side"] for f in out.to_dict()["fences"]]
    (2, ['right', 'left'])
    >>> out.to_dict()["exit"]["steepness_deg"], out.to_dict()["final_uncertainty_deg"]  # past the exit guide
    (2.0, 1.0)
    """
    from algrasp.planning.fences import fence_rules
    from optimisation.fence_layout import plan_fences

    rules = fence_rules(_friction(fence_friction))
    width = None if belt_width is None else _number(belt_width, "belt_width")
    analysis = analyse(source, exact=exact, physics=physics)
    beta_e = None if exit_steepness_deg is None else _number(exit_steepness_deg, "exit_steepness_deg")
    if not isinstance(exit_turns, bool):
        raise ConfigError("exit_turns", f"expected true or false, got {exit_turns!r}")
    if not isinstance(same_rail, bool):
        raise ConfigError("same_rail", f"expected true or false, got {same_rail!r}")
    out = plan_fences(analysis, rules, _number(min_margin_deg, "min_margin_deg"), width, beta_e, exit_turns, same_rail)
    return out if tail is None else _with_tail(out, tail)


def _with_tail(out: FenceLayout, tail: object) -> FenceLayout:
    """``out`` with the tail a request gives: a radius, or ``{"radius", "sweep_deg"}``."""
    from optimisation.fence_layout import with_tail

    if isinstance(tail, Mapping):
        unknown = set(tail) - {"radius", "sweep_deg"}
        if unknown or "radius" not in tail:
            raise ConfigError("tail", f"expected {{\"radius\": R, \"sweep_deg\": S (optional)}}, got {dict(tail)!r}")
        sweep = tail.get("sweep_deg")
        return with_tail(out, _number(tail["radius"], "tail"), None if sweep is None else _number(sweep, "tail"))
    return with_tail(out, _number(tail, "tail"))


def validate_fences(source: PartSource, *, samples: int = 3, seed: int = 0, record: bool = False,
                    record_dir: str | Path | None = None, tolerance_deg: float = 0.25, **options: Any) -> Any:
    """The fence design of :func:`fences` (``options`` as its keywords) simulated on a
    belt in Drake from ``samples`` seeded random orientations and lateral positions
    (conventions §9; needs the ``sim`` extra); ``record`` writes it to one MCAP record in
    ``record_dir`` (default ``$ALGRASP_LOG_DIR`` or ``logs/``).

    Parameters
    ----------
    source : PartSource
        The part (as :func:`fences`).
    samples, seed : int, default 3 and 0
        Starts simulated, and the seed of their random orientations and lateral positions.
    record : bool, default False
        Write the run to an MCAP record (``/tf``: the part's pose; ``/scene``: the walls).
    record_dir : str or Path, optional
        Where the record goes.
    tolerance_deg : float, default 0.25
        A sample agrees within the design's final uncertainty plus this (degrees).
    **options
        The keywords of :func:`fences` (the claim is where the part leaves the exit guide).

    Returns
    -------
    algrasp.sim.belt.BeltValidation
        ``agreement`` (final orientations within the design's uncertainty + ``tolerance_deg``
        of a claimed one, modulo its symmetry), ``agreement_on_last_fence``, per-sample
        outcomes; ``to_dict()`` is the document, ``run_id`` the record's.

    Examples
    --------
    >>> validate_fences({"name": "r", "boundary": [[0, 0], [4, 0], [4, 2], [0, 2]]}, samples=0)
    Traceback (most recent call last):
    ...
    algrasp.errors.ConfigError: samples: expected a whole number ≥ 1, got 0
    """
    from algrasp.sim.belt import record_validation
    from algrasp.sim.belt import validate_fences as simulate

    for name, value, low in (("samples", samples, 1), ("seed", seed, 0)):
        if isinstance(value, bool) or not isinstance(value, int) or value < low:
            raise ConfigError(name, f"expected a whole number ≥ {low}, got {value!r}")
    layout = fences(source, **options)
    analysis = analyse(source, exact=options.get("exact"), physics=options.get("physics"))
    physics = DEFAULT_PHYSICS if analysis.robust is None else analysis.robust.physics
    v = simulate(analysis.part, layout, physics, samples, seed, _number(tolerance_deg, "tolerance_deg"), record)
    if not record:
        return v
    doc = source if isinstance(source, Mapping) else {"name": analysis.part.name}
    opts = {**{k: val for k, val in options.items() if k not in ("physics", "exact")}, **model_of(analysis).to_options()}
    return record_validation(v, layout, dict(doc), {**opts, "samples": samples, "seed": seed},
                             None if record_dir is None else Path(record_dir))


def _friction(value: object) -> float | tuple[float, float] | None:
    """``fence_friction`` as a number or (lo, hi) of numbers; ConfigError naming it otherwise."""
    if value is None or (isinstance(value, (int, float)) and not isinstance(value, bool)):
        return value
    if isinstance(value, (list, tuple)) and len(value) in (1, 2):
        nums = [_number(v, "fence_friction") for v in value]
        return (nums[0], nums[-1])
    raise ConfigError("fence_friction", f"expected a number or [lo, hi], got {value!r}")


def _number(value: object, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ConfigError(name, f"expected a number, got {value!r}")
    return float(value)


def _gripper(gripper: GripperSource | None) -> dict[str, Any] | None:
    """The profile's keys (None: the default profile)."""
    from optimisation.profile import GripperProfile, load_profile, profile_from_dict

    if gripper is None:
        return None
    if isinstance(gripper, GripperProfile):
        return gripper.to_dict()
    if isinstance(gripper, (str, Path)):
        return load_profile(gripper).to_dict()
    if isinstance(gripper, Mapping):
        return profile_from_dict(dict(gripper), "gripper").to_dict()
    raise ConfigError("gripper", f"expected a mapping, a YAML/JSON file or a GripperProfile, got {type(gripper).__name__}")


def validate(source: PartSource, *, action: Action | str | None = None, samples: int = 36, seed: int = 0,
             placement: Literal["centred", "random"] | None = None, tolerance_deg: float = 1.0,
             optimise: bool | None = None, gripper: GripperSource | None = None, exact: bool | None = None,
             physics: PhysicsSource = None, sim_physics: str = "nominal", workers: int = 2) -> Any:
    """Simulate the plan in Drake from ``samples`` start orientations in each cell
    ``sim_physics`` names (needs the ``sim`` extra). Worker processes: see the module
    docstring (``__main__`` guard).

    Parameters
    ----------
    source : PartSource
        A :class:`Plan` is validated as it is (its action, model and execution); anything
        else is planned first (``action`` default squeeze, ``optimise`` default False).
    action, optimise, gripper, exact, physics
        As :func:`plan`. With a :class:`Plan`, ``action`` must be its own; ``exact`` or
        ``physics`` given (or ``optimise`` for a plan not optimised) plan it again.
    samples, seed : int, default 36 and 0
        Start orientations per cell, and the seed of the random starts (and placements).
    placement : {"centred", "random"} or None
        Where the jaws meet the part; None follows the physics.
    tolerance_deg : float, default 1
        A sample agrees within this (degrees) plus the plan's final uncertainty.
    sim_physics : str, default "nominal"
        ``nominal``, ``corners``, ``random`` or ``KEY=VALUE,...``.
    workers : int, default 2
        Simulation worker processes.

    Returns
    -------
    Validation
        ``agreement``, per-sample outcomes (``samples``), per-cell agreement (``cells``);
        ``to_dict()`` is the validation document.

    Raises
    ------
    SimulationError
        The physics engine could not simulate the part (``detail``: the engine's message).

    Examples
    --------
    Simulating needs Drake (the ``sim`` extra), so that line is not run as a test:

    >>> rect = {"name": "r", "boundary": [[0, 0], [4, 0], [4, 2], [0, 2]]}
    >>> validate(rect, samples=2, workers=1).agreement  # doctest: +SKIP
    1.0
    >>> validate(rect, samples=0)
    Traceback (most recent call last):
    ...
    algrasp.errors.ConfigError: samples: expected a whole number ≥ 1, got 0
    """
    from algrasp.pipeline import PlanRequest
    from algrasp.sim.validate import Validation

    for name, value, low in (("samples", samples, 1), ("seed", seed, 0), ("workers", workers, 1)):
        if isinstance(value, bool) or not isinstance(value, int) or value < low:
            raise ConfigError(name, f"expected a whole number ≥ {low}, got {value!r}")
    # placement, tolerance and the simulated cells are checked where every interface's are
    PlanRequest(samples=samples, seed=seed, placement=placement, tolerance_deg=_number(tolerance_deg, "tolerance_deg"),
                sim_physics=sim_physics)
    if isinstance(source, Plan) and source.analysis is not None:
        if action is not None and parse_action(action) != source.action:
            raise ConfigError("action", f"the plan given is a {source.action} plan, not {parse_action(action)}")
        made = source
        if optimise and made.execution is None:
            made = plan(made, action=made.action, exact=exact, physics=physics, optimise=True, gripper=gripper)
        elif exact is not None or physics is not None:
            made = plan(made, action=made.action, exact=exact, physics=physics, optimise=made.execution is not None,
                        gripper=gripper)
    else:
        made = plan(source, action=action or "squeeze", exact=exact, physics=physics, optimise=bool(optimise),
                    gripper=gripper)
    out = _simulate(made, samples, seed, placement, tolerance_deg, sim_physics, workers)
    assert isinstance(out, Validation)
    return out


def _simulate(made: Plan, samples: int, seed: int, placement: Literal["centred", "random"] | None,
              tolerance_deg: float, sim_physics: str, workers: int) -> Any:
    from algrasp.io.record.session import recording
    from algrasp.pipeline import PlanRequest, plan_part

    assert made.analysis is not None
    m = model_of(made.analysis)
    doc = dict(made.analysis.part.source_document)
    execution = made.execution
    req = PlanRequest(action=made.action, optimise=execution is not None,
                      gripper_profile=None if execution is None else execution.profile.to_dict(), samples=samples,
                      seed=seed, placement=placement, tolerance_deg=float(tolerance_deg), exact=m.exact,
                      physics=m.physics.to_dict(), sim_physics=sim_physics)
    with recording(False, None, "validate", doc, req.record_options()) as rec:
        out = plan_part(doc, req, rec, sim_workers=workers, record_sim=False, analysis=made.analysis, plan=made)
    return replace(out.validation, plan_document=out.plan_doc)


__all__ = ["DEFAULT_PHYSICS", "Action", "Analysis", "Drawing", "Model", "Part", "PartSource", "Physics", "Plan",
           "analyse", "document", "import_drawing", "load_part", "model", "plan", "validate"]
