"""``algrasp fences PART``: the conveyor fence design of a part (conventions §9), printed,
as JSON, and drawn (SVG, DXF)."""

from __future__ import annotations

import argparse
import json
from typing import TYPE_CHECKING, Any

from algrasp.cli_physics import span

if TYPE_CHECKING:  # the planning stack loads on first use, not for --help
    from optimisation.fence_layout import FenceLayout


def add_fences_command(sub: Any) -> None:
    """Register ``fences`` on the CLI's sub-parsers."""
    from algrasp.cli import _cad_options, model_options

    p = sub.add_parser("fences", help="fewest conveyor fences that orient the part, laid out on a belt")
    p.add_argument("part", metavar="PART.json")
    _cad_options(p)
    fence_design_options(p)
    p.add_argument("--min-margin-deg", type=float, default=1.0, metavar="M",
                   help="every fence angle may be off by M degrees (default 1)")
    p.add_argument("--json", action="store_true", help="print the fence document as JSON")
    p.add_argument("--svg", metavar="OUT.svg", help="draw the belt and fences (dimensioned, part units)")
    p.add_argument("--dxf", metavar="OUT.dxf", help="the same drawing as DXF (layer FENCES: one line per fence)")
    p.add_argument("--drawing", metavar="OUT.dxf|OUT.svg", help="the drawing, as its suffix says")
    p.add_argument("--validate", type=int, metavar="N", help="simulate N seeded starts on the belt in Drake "
                   "(orientation and lateral position random; needs the sim extra)")
    p.add_argument("--seed", type=int, default=0, metavar="S", help="with --validate: the random starts' seed (default 0)")
    from algrasp.cli import _record_options

    _record_options(p)
    model_options(p)
    p.set_defaults(func=cmd_fences)


def fence_design_options(p: Any, tail: bool = True) -> None:
    """The belt and fence flags ``fences``, ``validate --fences`` and ``batch --fences``
    share (not the margin: ``validate`` and ``batch`` have their own ``--min-margin-deg``;
    ``tail`` False: no ``--tail``, as for a catalogue)."""
    p.add_argument("--fence-friction", "--belt-friction", dest="fence_friction", type=span, metavar="V|LO,HI",
                   help="part–fence friction μ_f (default 0.1,0.3: UHMW-PE guide rails on dry parts); a fence "
                        "slides the part only if its angle to the belt is below 90° − atan μ_f")
    p.add_argument("--belt-width", type=float, metavar="W", help="between the rails, part units (default: the least needed)")
    if tail:
        p.add_argument("--tail", type=float, metavar="R", help="a curved tail of radius R (part units) on the last "
                       "fence, tangent at its tip (Brokowski, Peshkin & Goldberg 1995)")
        p.add_argument("--tail-sweep", type=float, metavar="DEG", help="with --tail: how far it turns towards the belt "
                       "(default the last fence's angle to the belt less the exit guide's: it ends tangent to the guide)")
    p.add_argument("--exit-steepness-deg", type=float, metavar="DEG", dest="exit_steepness_deg",
                   help="the exit guide's angle to the belt (default 2, at most 10): the claim past it is ±DEG/2 wider, "
                        "the guide cot(DEG) times its push bound long")
    p.add_argument("--no-exit-turns", dest="exit_turns", action="store_false",
                   help="plan in Berretty et al.'s model: a part keeps its orientation between fences (by default "
                        "it may turn towards the belt by up to a fence's angle to it as it comes off the tip)")
    p.add_argument("--same-rail", dest="same_rail", action="store_true",
                   help="let consecutive fences stand on one rail (the later reaching further across the belt); by "
                        "default fences alternate rails")


def add_validate_fences_options(p: Any) -> None:
    """``validate --fences``: the belt validation of ``fences --validate N`` (``--samples``,
    ``--seed``, ``--min-margin-deg``, ``--tolerance-deg`` are ``validate``'s own)."""
    g = p.add_argument_group("conveyor fences (with --fences: validate the part's fence design on the belt)")
    g.add_argument("--fences", action="store_true", help="simulate the fence design (conventions §9) on a belt instead "
                   "of the gripper plan: --samples seeded starts, orientation and lateral position random")
    g.add_argument("--drawing", metavar="OUT.dxf|OUT.svg", help="with --fences: the layout's drawing, as its suffix says")
    fence_design_options(g)


GRIPPER_ONLY = {"action": "squeeze", "limits": False, "optimise": False, "gripper": None, "push_scale": 1.0,
                "sim_physics": "nominal", "workers": 2}
"""``validate`` flags of a gripper plan, and their defaults: refused with ``--fences``."""
FENCES_ONLY = ("fence_friction", "belt_width", "tail", "tail_sweep", "drawing", "exit_steepness_deg")
"""``validate`` flags that need ``--fences``."""


def check_validate_flags(args: argparse.Namespace) -> None:
    """ConfigError naming the flag given to ``validate`` that the mode it runs does not use;
    with ``--fences`` it fills the mode's defaults (margin 1°, no SVG/DXF flags)."""
    from algrasp.errors import ConfigError

    if not args.fences:
        for name in FENCES_ONLY:
            if getattr(args, name) is not None:
                raise ConfigError(name, "needs --fences (it describes the belt and its fences)")
        for name in ("exit_turns", "same_rail"):
            if getattr(args, name) != (name == "exit_turns"):
                raise ConfigError(name, "needs --fences (it describes the belt and its fences)")
        return
    for name, default in GRIPPER_ONLY.items():
        if getattr(args, name) != default:
            raise ConfigError(name, "describes a gripper plan; it does not apply with --fences")
    if args.min_margin_deg is None:
        from algrasp.planning.fences import DEFAULT_MIN_MARGIN_DEG

        args.min_margin_deg = DEFAULT_MIN_MARGIN_DEG
    args.svg = args.dxf = None


def cmd_fences(args: argparse.Namespace) -> int:
    return design_and_validate(args, args.validate)


def design_and_validate(args: argparse.Namespace, samples: int | None, tolerance_deg: float | None = None) -> int:
    """Design (and with ``samples`` validate on the belt) the fences of ``args.part``,
    print or ``--json`` them, write the drawings asked for: ``algrasp fences`` and
    ``algrasp validate --fences`` (one path; ``tolerance_deg`` None: the API's 0.25°)."""
    from algrasp.api import fences
    from algrasp.cli import read_document

    doc = read_document(args.part, args)
    options = fence_options(args)
    layout = fences(doc, **options)
    written = _drawings(layout, args)
    validation = None
    if samples is not None:
        from algrasp.api import validate_fences

        extra = {} if tolerance_deg is None else {"tolerance_deg": tolerance_deg}
        validation = validate_fences(doc, samples=samples, seed=args.seed, record=not args.no_record,
                                     record_dir=args.record_dir, **extra, **options)
    if args.json:
        out = dict(layout.to_dict())
        if validation is not None:
            out["validation"] = validation.to_dict()
        print(json.dumps(out, indent=2))
        return 0
    print_layout(layout.to_dict())
    for path in written:
        print(f"drawing written to {path}")
    if validation is not None:
        print_validation(validation.to_dict())
    return 0


def fence_options(args: argparse.Namespace) -> dict[str, Any]:
    """The keywords of ``algrasp.api.fences`` the flags give (the model too)."""
    from algrasp.cli import model_from_args
    from algrasp.errors import ConfigError

    if args.tail is None and args.tail_sweep is not None:
        raise ConfigError("tail", "--tail-sweep needs --tail R")
    model = model_from_args(args)
    tail = None if args.tail is None else {"radius": args.tail, "sweep_deg": args.tail_sweep}
    return {"fence_friction": args.fence_friction, "belt_width": args.belt_width,
            "min_margin_deg": args.min_margin_deg, "exact": model.exact, "physics": model.physics, "tail": tail,
            "exit_steepness_deg": args.exit_steepness_deg, "exit_turns": args.exit_turns,
            "same_rail": args.same_rail}


def print_validation(v: dict[str, Any]) -> None:
    """A belt validation, a line per sample and the agreement."""
    tail = " past the exit guide"
    finals = ", ".join(f"{f:.4g}°" for f in v["final_orientations_deg"])
    print(f"Drake on the belt: {v['belt_speed_m_s']:.3g} m/s, support friction {v['support_friction']:.3g}, "
          f"fence friction {v['fence_friction']:.3g}; seed {v['seed']}; agreement within the claim's "
          f"±{v['final_uncertainty_deg']:.3g}° + {v['tolerance_deg']:g}° of {finals}"
          f"{tail} (mod {v['symmetry_period_deg']:.4g}°)")
    for k, s in enumerate(v["samples"], 1):
        fence = "—" if s["on_last_fence_deg"] is None else f"{s['on_last_fence_deg']:.2f}° (off {s['on_last_fence_error_deg']:.2f}°)"
        print(f"  sample {k}: start {s['initial_deg']:.2f}° at {s['lateral']:.3g} from the rail → on the last fence {fence}, "
              f"final {s['simulated_deg']:.2f}° (off {s['error_deg']:.2f}°): {'agrees' if s['agrees'] else 'DISAGREES'}")
    n = len(v["samples"])
    print(f"agreement {v['agreement']:.0%} ({round(v['agreement'] * n)}/{n}); on the last fence, before the part comes off "
          f"its end: {v['agreement_on_last_fence']:.0%}; {v['wall_seconds']:.1f} s wall")
    if v.get("run_id"):
        print(f"run {v['run_id']} recorded")


def _drawings(layout: FenceLayout, args: argparse.Namespace) -> list[str]:
    from algrasp.io.fence_drawing import write_drawing, write_dxf, write_svg

    out = []
    if args.drawing:
        out.append(str(write_drawing(layout, args.drawing)))
    if args.svg:
        out.append(str(write_svg(layout, args.svg)))
    if args.dxf:
        out.append(str(write_dxf(layout, args.dxf)))
    return out


def print_layout(doc: dict[str, Any]) -> None:
    """The fence document as a table."""
    from rich.console import Console
    from rich.table import Table

    u = doc["units"]
    n = len(doc["fences"])
    finals = ", ".join(f"{f:.4g}°" for f in doc["final_orientations_deg"])
    print(f"{n} fence{'s' if n > 1 else ''} ({doc['model']} model, fence friction {doc['fence_friction'][0]:g}–"
          f"{doc['fence_friction'][1]:g}: steepness below {doc['max_steepness_deg']:.4g}°); belt width "
          f"{doc['belt_width']:.4g} {u}, total fence length {doc['total_length']:.4g} {u}")
    table = Table()
    for col in ("fence", "side", "angle (deg)", "to belt (deg)", "margin (deg)", f"position ({u})", f"length ({u})",
                f"push bound ({u})"):
        table.add_column(col, justify="right")
    for i, f in enumerate(doc["fences"], 1):
        table.add_row(str(i), f["side"], f"{f['angle_deg']:.2f}", f"{f['steepness_deg']:.2f}", f"±{f['margin_deg']:.2f}",
                      f"{f['position']:.4g}", f"{f['length']:.4g}", f"{f['push_distance_bound']:.4g}")
    Console().print(table)
    last = ", ".join(f"{f:.4g}°" for f in doc["last_fence_orientations_deg"])
    print(f"on the last fence: {last} ± {doc['last_fence_uncertainty_deg']:.3g}°")
    tail, ex = doc.get("tail"), doc.get("exit")
    if tail:
        print(f"tail: radius {tail['radius']:.4g} {u}, sweep {tail['sweep_deg']:.4g}° on fence {n}")
    if ex:
        print(f"exit guide: {ex['side']} rail, {ex['steepness_deg']:.3g}° to the belt (angle {ex['angle_deg']:.2f}°), "
              f"length {ex['length']:.4g} {u} from ({ex['start'][0]:.4g}, {ex['start'][1]:.4g}), push bound "
              f"{ex['push_distance_bound']:.4g} {u}")
    else:
        print("no exit guide collapses the arc the last fence's tip leaves: the claim is widened by its steepness")
    print(f"final orientation{'s' if len(doc['final_orientations_deg']) > 1 else ''} past the layout: {finals} "
          f"± {doc['final_uncertainty_deg']:.3g}°")


def print_imported_layout(doc: dict[str, Any], source: str, output: str | None) -> int:
    """``algrasp import layout.dxf``: the fence layout read back, as JSON (or to ``output``,
    with a line per fence)."""
    text = json.dumps(doc, indent=2)
    if output is None:
        print(text)
        return 0
    from pathlib import Path

    Path(output).write_text(text + "\n", encoding="utf-8")
    print_layout_lines(doc, f"{source} → {output}")
    return 0


def print_layout_lines(doc: dict[str, Any], head: str) -> None:
    """A re-read fence layout, a line per fence (``import -o``, ``import --list``)."""
    u, n = doc["units"], len(doc["fences"])
    print(f"{head}: fence layout, {n} fence{'s' if n > 1 else ''} on a belt {doc['belt_width']:.6g} {u} wide, "
          f"total length {doc['total_length']:.6g} {u}")
    for i, f in enumerate(doc["fences"], 1):
        print(f"  fence {i}: {f['side']}, angle {f['angle_deg']:.4f}° ({f['steepness_deg']:.4f}° to the belt), "
              f"root at x = {f['position']:.6g} {u}, length {f['length']:.6g} {u}")
    if "tail" in doc:
        t = doc["tail"]
        print(f"  tail on fence {t['fence']}: radius {t['radius']:.6g} {u}, sweep {t['sweep_deg']:.4f}°")
    if "exit" in doc:
        e = doc["exit"]
        print(f"  exit guide: {e['steepness_deg']:.4f}° to the belt from x = {e['start'][0]:.6g} {u}, length {e['length']:.6g} {u}")


def listed_layout(path: Any, as_json: bool) -> bool:
    """``algrasp import FILE --list`` of a fence layout DXF: its fences printed (True), else
    False (``path`` a Path; not a fence layout: the sheet's parts are listed)."""
    from algrasp.io.fence_import import fence_layout_of

    layout = fence_layout_of(path.read_bytes(), path.stem) if path.suffix.lower() == ".dxf" else None
    if layout is None:
        return False
    if as_json:
        print(json.dumps(layout, indent=2))
    else:
        print_layout_lines(layout, str(path))
    return True
