"""The ``algrasp`` command line: a thin shell over the pure core.

Errors the user can cause end as one line on stderr and a non-zero exit; with
``--json`` they are ``{"error": {"type": .., "message": ..}}`` on stdout.
"""

from __future__ import annotations

import argparse
import functools
import json
import re
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from algrasp.errors import AlgraspError, ConfigError, PartDocumentError

if TYPE_CHECKING:  # the geometry and planning stack (numpy, scipy) loads on first use, not for --help
    from algrasp.planning.analysis import Analysis, Model
    from algrasp.planning.plans import Plan

EXIT_USER_ERROR = 2


def read_document(path: str, args: argparse.Namespace | None = None) -> dict[str, Any]:
    """Read a part document file, or import a DXF/SVG/mesh file with the
    ``--layer``/``--id``/``--pose``/``--part`` options of ``args``."""
    from algrasp.io.parts import read_part_file

    return read_part_file(path, **_import_options(args))


def _import_options(args: argparse.Namespace | None) -> dict[str, Any]:
    keys = {"layer": "layer", "id": "element_id", "pose": "pose", "tolerance": "tolerance", "units": "units", "sheet_part": "part",
            "engrave_colours": "engrave_colours"}
    return {v: getattr(args, k) for k, v in keys.items() if getattr(args, k, None) is not None}


def cmd_import(args: argparse.Namespace) -> int:
    from algrasp.io.cad import import_file

    if args.list:
        return _list_parts(args)
    doc = import_file(args.file, **_import_options(args))
    from algrasp.io.fence_import import is_fence_layout

    if is_fence_layout(doc):
        from algrasp.cli_fences import print_imported_layout

        return print_imported_layout(doc, args.file, args.output)
    from algrasp.geometry.part import load_part

    load_part(doc)  # the imported document must be a valid part
    for w in doc.get("source", {}).get("warnings", []):
        print(f"algrasp: warning: {w}", file=sys.stderr)
    text = json.dumps(doc, indent=2)
    if args.output is None:
        print(text)
        return 0
    Path(args.output).write_text(text + "\n", encoding="utf-8")
    loops = [doc["boundary"], *doc.get("holes", [])] if "boundary" in doc else [doc["polygon"]]
    kinds = sorted({s["type"] for lp in loops if isinstance(lp[0], dict) for s in lp}) or ["polygon"]
    print(f"{args.file} → {args.output}: part {doc['name']!r} in {doc['units']}, {len(loops[0])} boundary "
          f"segments/vertices ({', '.join(kinds)}), {len(loops) - 1} hole(s)"
          f"{', approximate (mesh projection)' if doc.get('approximate') else ''}")
    return 0


def _list_parts(args: argparse.Namespace) -> int:
    """``algrasp import FILE --list [--json]``: the parts on a sheet."""
    from algrasp.io.cad import list_parts

    opts = {k: v for k, v in _import_options(args).items() if k not in ("part", "pose")}
    p = Path(args.file)
    if not p.is_file():
        raise PartDocumentError("FILE", f"no such file: {args.file}")
    from algrasp.cli_fences import listed_layout

    if listed_layout(p, args.json):  # a fence layout has no parts: its fences are listed
        return 0
    out = list_parts(p.name, p.read_bytes(), **opts)
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    for r in out["parts"]:
        x0, y0, x1, y1 = r["bbox"]
        on = f" on layer {r['layer']!r}" if r.get("layer") else ""
        print(f"part {r['index']}{on}: {x1 - x0:.4g} × {y1 - y0:.4g} {r['units']} at ({x0:.4g}, {y0:.4g}), "
              f"area {r['area']:.6g}, {r['holes']} hole(s), {r['segments']} outline segments")
    for w in [*out["ignored"], *out["warnings"]]:
        print(f"  note: {w}")
    return 0


def _print_function(title: str, rows: list[dict[str, Any]], consts: list[list[float]]) -> None:
    from rich.console import Console
    from rich.table import Table

    table = Table(title=title)
    for col in ("θ (deg)", "value", "kind", "equilibrium"):
        table.add_column(col, justify="right")
    for e in rows:
        table.add_row(f"{e['theta_deg']:.4f}", f"{e['value']:.6g}", e["kind"], e["equilibrium"])
    Console().print(table)
    if consts:
        print("  constant on: " + ", ".join(f"[{a:.4f}, {b:.4f})" for a, b in consts))


def _print_transfer(title: str, F: dict[str, Any]) -> None:
    from rich.console import Console
    from rich.table import Table

    table = Table(title=f"{title}: period {F['period_deg']:g}°, symmetry period {F['symmetry_period_deg']:.6g}°")
    for col in ("piece", "start (deg)", "end (deg)", "maps to (deg)"):
        table.add_column(col, justify="right")
    rows = [("step", s["start_deg"], s["end_deg"], f"{s['fixed_point_deg']:.4f}") for s in F["steps"]]
    rows += [("ramp", r["start_deg"], r["end_deg"], "itself") for r in F["ramps"]]
    for kind, a, b, img in sorted(rows, key=lambda r: r[1]):
        table.add_row(kind, f"{a:.4f}", f"{b:.4f}", img)
    Console().print(table)
    if not F["orientable"]:
        print(f"  {F['reason']}")


def print_analysis(a: Analysis) -> None:
    d = a.to_dict()
    part = d["part"]
    assert isinstance(part, dict)
    print(f"part {part['name']!r}: area {part['area']:.6g} {a.part.units}², hull perimeter "
          f"{part['hull_perimeter']:.6g} {a.part.units}, centre of mass "
          f"({part['center_of_mass'][0]:.6g}, {part['center_of_mass'][1]:.6g})"
          f"{'' if part['center_of_mass_given'] else ' (area centroid)'}")
    for key, title in (("diameter", "Diameter function d(θ)"), ("radius", "Radius function r(θ)")):
        f = d[key]
        assert isinstance(f, dict)
        _print_function(title, f["extrema"], f["constant_intervals_deg"])
    for key, title in (("squeeze", "Squeeze-grasp Γ"), ("push", "Push p"), ("push_grasp", "Push-grasp Γ∘p")):
        F = d[key]
        assert isinstance(F, dict)
        _print_transfer(title, F)


def _request(args: argparse.Namespace) -> Any:
    """The plan request the command line describes."""
    from algrasp.pipeline import PlanRequest

    profile = _gripper_profile(args.gripper).to_dict() if getattr(args, "gripper", None) else None
    extra = {k: getattr(args, k) for k in ("samples", "seed", "tolerance_deg", "push_scale", "sim_physics") if hasattr(args, k)}
    model = model_from_args(args)
    return PlanRequest(args.action, args.min_margin_deg, args.optimise, profile, **extra,
                       exact=model.exact, physics=model.physics.to_dict(), limits="all" if args.limits else "headline")


def _action(value: str) -> str:
    """``--action``: one spelling, the other accepted (:mod:`algrasp.planning.actions`)."""
    from algrasp.planning.actions import parse_action

    try:
        return parse_action(value, "--action")
    except ConfigError as exc:
        raise argparse.ArgumentTypeError(exc.problem) from None


def model_from_args(args: argparse.Namespace) -> Model:
    """``--exact`` or the robust model over the cell's physics (``--cell``, the range flags)."""
    from algrasp.cli_physics import physics_from_args
    from algrasp.planning.analysis import Model

    return Model(bool(getattr(args, "exact", False)), physics_from_args(args))


def _options(args: argparse.Namespace) -> dict[str, Any]:
    """The request options a run record keeps (what replay needs to recompute)."""
    if hasattr(args, "action"):
        return _request(args).record_options()
    return model_from_args(args).to_options()


def _recording(args: argparse.Namespace, command: str, doc: dict[str, Any]) -> Any:
    from algrasp.io.record.session import recording

    return recording(not args.no_record, Path(args.record_dir) if args.record_dir else None, command, doc, _options(args))


def _with_run(doc: dict[str, Any], rec: Any) -> dict[str, Any]:
    return {**doc, **rec.fields()}


def cmd_analyze(args: argparse.Namespace) -> int:
    doc = read_document(args.part, args)
    model = model_from_args(args)
    with _recording(args, "analyze", doc) as rec:
        from algrasp.planning.analysis import analyse_document

        analysis = analyse_document(doc, model)
        rec.analysis(analysis.to_dict())
    if args.json:
        print(json.dumps(_with_run(analysis.to_dict(), rec), indent=2))
    else:
        print_analysis(analysis)
        _print_record(rec)
    return 0


def _print_record(rec: Any) -> None:
    if rec.record_path:
        print(f"run {rec.run_id} recorded to {rec.record_path}")


def print_plan(plan: Plan) -> None:
    from rich.console import Console
    from rich.table import Table

    d: dict[str, Any] = plan.to_dict()
    table = Table(title=f"{len(plan.steps)}-step {d['action']} plan (execution order)")
    for col in ("step", "gripper angle (deg)", "margin (deg)", "interval Θ (deg)"):
        table.add_column(col, justify="right")
    intervals = d["intervals_deg"][::-1]
    for i, s in enumerate(d["steps"]):
        margin = "—" if s["margin_deg"] is None else f"{s['margin_deg']:.4f}"
        a, b = intervals[i]
        table.add_row(str(i + 1), f"{s['gripper_angle_deg']:.4f}", margin, f"[{a:.4f}, {b:.4f})")
    Console().print(table)
    finals = ", ".join(f"{f:.4f}" for f in d["final_orientations_deg"])
    print(f"symmetry period {d['symmetry_period_deg']:.6g}°; final orientations (deg): {finals} "
          f"± {d['final_uncertainty_deg']:.4f} ({d['model']} model)")
    if plan.bounds is not None and isinstance(d.get("dead_band"), dict):
        from algrasp.cli_physics import describe

        print(f"physics: {describe(d['dead_band'])}")
    if plan.limits:
        print(f"limits: {plan.limits['advice']}")
    times = ", ".join(f"{k} {1000 * v:.2f} ms" for k, v in d["timings_s"].items())
    print(f"verified: {d['verified']}; {times}")


@functools.lru_cache(maxsize=4)
def _gripper_profile(path: str) -> Any:
    """The ``--gripper`` profile, read once per call (the record and the optimiser share it)."""
    from optimisation.profile import load_profile

    return load_profile(path)


def print_execution(execution: Any) -> None:
    from rich.console import Console
    from rich.table import Table

    u = execution.units
    table = Table(title="Optimised execution")
    for col in ("step", f"push distance ({u})", f"Peshkin bound ({u})", "duration (s)"):
        table.add_column(col, justify="right")
    for i, s in enumerate(execution.steps):
        push = "—" if s.push is None else f"{s.push.distance:.4f}"
        bound = "—" if s.push is None else f"{s.push.bound:.4f}"
        table.add_row(str(i + 1), push, bound, f"{s.duration_s:.3f}")
    Console().print(table)
    print(f"cycle time {execution.cycle_time_s:.3f} s (naive constant contact speed: {execution.naive_cycle_time_s:.3f} s)")


def cmd_plan(args: argparse.Namespace) -> int:
    from algrasp.pipeline import plan_part

    doc = read_document(args.part, args)
    with _recording(args, "plan", doc) as rec:
        out = plan_part(doc, _request(args), rec)
    if args.figure:
        from algrasp.plots import plan_figure

        plan_figure(out.analysis, out.plan, args.figure)
    if args.json:
        print(json.dumps(_with_run(out.plan_doc, rec), indent=2))
    else:
        _print_record(rec)
        print_plan(out.plan)
        if out.execution is not None:
            print_execution(out.execution)
        if args.figure:
            print(f"figure written to {args.figure}")
    return 0


def cmd_validate(args: argparse.Namespace) -> int:
    from algrasp.cli_fences import check_validate_flags, design_and_validate
    from algrasp.pipeline import plan_part

    if args.samples < 1 or args.samples > 10_000:
        raise ConfigError("--samples", f"must be in [1, 10000], got {args.samples}")
    check_validate_flags(args)
    if args.fences:  # the belt validation of ``algrasp fences --validate N``
        return design_and_validate(args, args.samples, args.tolerance_deg)
    args.min_margin_deg = 0.0 if args.min_margin_deg is None else args.min_margin_deg
    args.tolerance_deg = 1.0 if args.tolerance_deg is None else args.tolerance_deg
    if not (0.0 < args.push_scale <= 10.0):
        raise ConfigError("--push-scale", f"must be in (0, 10], got {args.push_scale}")
    doc = read_document(args.part, args)
    with _recording(args, "validate", doc) as rec:
        out = plan_part(doc, _request(args), rec, sim_workers=args.workers, record_sim=not args.no_record)
    if args.json:
        print(json.dumps(_with_run(out.validation_doc() or {}, rec), indent=2))
        return 0
    _print_record(rec)
    print_plan(out.plan)
    if out.execution is not None:
        print_execution(out.execution)
    print_validation(out.validation)
    return 0


def print_validation(v: Any) -> None:
    from rich.console import Console
    from rich.table import Table

    table = Table(title=f"Drake validation: {len(v.samples)} samples, {v.placement} placement")
    for col in ("initial φ", "predicted φ", "simulated φ", "agrees", "near unstable"):
        table.add_column(col, justify="right")
    for s in v.samples:
        table.add_row(f"{s.initial_deg:.2f}", f"{s.predicted_deg:.2f}", f"{s.simulated_deg:.2f}",
                      "yes" if s.agrees else "NO", "yes" if s.near_unstable else "")
    Console().print(table)
    print(f"agreement within {v.tolerance_deg:g}°: {100 * v.agreement:.1f}% of all samples, "
          f"{100 * v.agreement_clear:.1f}% of those more than 2° from an unstable equilibrium")
    if v.push_agreement is not None:
        print(f"first push ends within {v.tolerance_deg:g}° of its fixed point: {100 * v.push_agreement:.1f}% (clear samples)")
    for c in v.cells if len(v.cells) > 1 or (v.cells and v.cells[0]["label"] != "nominal") else ():
        print(f"cell {c['label']}: {100 * c['agreement']:.0f}% of {c['samples']} (worst {c['worst_error_deg']:.2f}° off)")
    print(f"simulated {v.sim_seconds:.1f} s in {v.wall_seconds:.1f} s wall "
          f"({v.sim_seconds / v.wall_seconds:.2f}× real time); collision chord error "
          f"{1e6 * v.model['chord_error_m']:.2f} µm")


def _record_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--no-record", action="store_true", help="do not write an MCAP run record for this call")
    p.add_argument("--record-dir", metavar="DIR", help="where run records go (default $ALGRASP_LOG_DIR or logs/)")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="algrasp", description="Sensorless orienting of planar parts.")
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("import", help="turn a DXF/SVG drawing or a 3-D mesh into a part document")
    p.add_argument("file", metavar="FILE.dxf|svg|stl|obj|ply")
    _cad_options(p)
    p.add_argument("-o", "--output", metavar="PART.json", help="write here (default: print the document)")
    p.add_argument("--list", action="store_true", help="list the parts on the sheet (choose one with --part K)")
    p.add_argument("--json", action="store_true", help="with --list: print the listing as JSON")
    p.set_defaults(func=cmd_import)
    p = sub.add_parser("analyze", help="diameter/radius functions and transfer functions of a part")
    p.add_argument("part", metavar="PART.json")
    _cad_options(p)
    p.add_argument("--json", action="store_true", help="print the analysis object as JSON")
    model_options(p)
    _record_options(p)
    p.set_defaults(func=cmd_analyze)
    p = sub.add_parser("plan", help="shortest sensorless plan (Algorithm A′) for a part")
    _plan_arguments(p)
    p.add_argument("--json", action="store_true", help="print the plan document as JSON")
    p.add_argument("--figure", metavar="OUT.svg|png", help="draw functions, intervals and plan traces")
    _optimise_options(p)
    _record_options(p)
    p.set_defaults(func=cmd_plan)
    p = sub.add_parser("validate", help="simulate the plan in Drake from many initial orientations")
    _plan_arguments(p)
    p.add_argument("--samples", type=int, default=36)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--sim-physics", default="nominal", metavar="nominal|corners|random|KEY=VALUE,...",
                   help="which cells of the plan's physics ranges to simulate: the middle of every range (default), "
                        "every corner, uniform draws in the box, or one cell of explicit values, e.g. "
                        "support_friction=0.05,jaw_friction=0.2,part_mass_kg=0.005,com_offset=0.5,0")
    p.add_argument("--tolerance-deg", type=float, help="agreement tolerance on the final orientation (default 1°; "
                   "with --fences 0.25° beyond the design's uncertainty)")
    p.add_argument("--workers", type=int, default=2, help="simulation worker processes")
    _optimise_options(p)
    p.add_argument("--push-scale", type=float, default=1.0,
                   help="multiply the optimised push distances (experiments: 0.5 shows the optimum is tight)")
    _record_options(p)
    p.add_argument("--json", action="store_true")
    from algrasp.cli_fences import add_fences_command, add_validate_fences_options

    add_validate_fences_options(p)
    p.set_defaults(func=cmd_validate, min_margin_deg=None)

    add_fences_command(sub)
    _registered_commands(sub)
    return parser


def _registered_commands(sub: Any) -> None:
    """Sub-commands of the layers above (``replay``/``runs``, ``serve``/``batch``), registered
    as ``algrasp.commands`` entry points; a layer whose extra is not installed is left out."""
    from importlib.metadata import entry_points

    for ep in sorted(entry_points(group="algrasp.commands"), key=lambda e: e.name):
        try:
            add = ep.load()
        except ImportError:  # e.g. the service without the [service] extra
            continue
        add(sub)


def _plan_arguments(p: argparse.ArgumentParser) -> None:
    """The part and what to plan: shared by ``plan`` and ``validate``."""
    p.add_argument("part", metavar="PART.json")
    _cad_options(p)
    p.add_argument("--action", type=_action, default="squeeze", metavar="{squeeze,push_grasp}",
                   help="the gripper action (push-grasp is read as push_grasp)")
    p.add_argument("--min-margin-deg", type=_non_negative, default=0.0, metavar="M",
                   help="every transition must tolerate M degrees of gripper error")
    p.add_argument("--limits", action="store_true",
                   help="search every physics limit (support friction, mass, profile tolerance; jaw friction always)")
    model_options(p)


def model_options(p: argparse.ArgumentParser) -> None:
    """The model: robust over the cell's physics ranges by default (conventions §8),
    ``--exact`` for the paper's."""
    from algrasp.cli_physics import add_physics_options

    g = p.add_argument_group("model (default: robust — set-valued over the cell's physics ranges)")
    g.add_argument("--exact", action="store_true", help="the paper's exact frictionless model (no dead band)")
    add_physics_options(g)


def _cad_options(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("CAD import (DXF, SVG, STL/OBJ/PLY files)")
    x = g.add_mutually_exclusive_group()
    x.add_argument("--layer", help="DXF: the layer holding the outline (default: every layer)")
    x.add_argument("--id", help="SVG: the element (path, shape or group) to import (default: every shape)")
    x.add_argument("--pose", type=int, help="mesh: stable resting pose, 0 = most probable (default)")
    g.add_argument("--tolerance", type=float,
                   help="join and gap tolerance in drawing units (default: ends within 1e-6 of the drawing's size "
                        "join; gaps up to 2e-3 of the chains meeting there close, reported)")
    g.add_argument("--units", help="override the unit (meshes carry none: default mm)")
    g.add_argument("--engrave-colours", metavar="COLOURS",
                   help="DXF/SVG: stroke colours that are engraving, not cuts (#rrggbb,... ; none: every colour is "
                        "cut; default: a second colour lying on the first colour's parts is engraving, reported)")
    g.add_argument("--part", type=int, metavar="K", dest="sheet_part",
                   help="DXF/SVG sheet: the K-th part (import FILE --list shows them)")


def _optimise_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--optimise", action="store_true",
                   help="optimise push distances and jaw timing (CasADi); adds them and the cycle time to the plan")
    p.add_argument("--gripper", metavar="PROFILE.yaml|json", help="gripper limits (default: optimisation/profiles/default.yaml)")


def _non_negative(text: str) -> float:
    try:
        x = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not (x >= 0.0 and x < 180.0):
        raise argparse.ArgumentTypeError(f"must be in [0, 180), got {text}")
    return x


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args))
    except AlgraspError as exc:
        if getattr(args, "json", False):
            print(json.dumps({"error": exc.to_dict()}))
        else:
            print(f"algrasp: error: {_as_flags(exc)}", file=sys.stderr)
        return exc.exit_code


FLAGS = {"element_id": "--id", "gripper_profile": "--gripper", "exit_turns": "--no-exit-turns"}
"""Library parameters whose command-line flag is not ``--`` + the name with dashes."""


def _as_flags(exc: AlgraspError) -> str:
    """The message with a library parameter (``ConfigError.field``) named as its flag:
    the library names parameters, the command line speaks of flags."""
    if isinstance(exc, ConfigError) and re.fullmatch(r"[a-z][a-z0-9_]*", exc.field) and exc.message.startswith(f"{exc.field}: "):
        flag = FLAGS.get(exc.field, "--" + exc.field.replace("_", "-"))
        return f"{flag}: {exc.problem}"
    return exc.message


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
