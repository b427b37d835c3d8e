"""A job's results as files: ``results.jsonl`` (one part per line), ``summary.csv``,
``gripper_spec.json`` (the catalogue specification) and ``report.md`` (both, readable)."""

from __future__ import annotations

import csv
import io
import json
import zipfile
from pathlib import Path
from typing import Any

from service.fixture import catalogue_spec

COLUMNS = ("index", "name", "status", "action", "steps", "final_orientations", "jaw_opening_mm", "jaw_length_mm",
           "push_distance_mm", "cycle_time_s", "agreement", "run_id", "note")


def results_jsonl(results: list[dict[str, Any]]) -> str:
    return "".join(json.dumps(r, sort_keys=True) + "\n" for r in results)


def _row(r: dict[str, Any]) -> dict[str, Any]:
    row: dict[str, Any] = {k: None for k in COLUMNS}
    row.update(index=r["index"], name=r["name"], status=r["status"], run_id=r.get("run_id"))
    res = r.get("result")
    if r["status"] != "done" or res is None:
        row["note"] = (r.get("error") or {}).get("message", r["status"])
    elif not res["orientable"]:
        row.update(status="not orientable", note="; ".join(res["reasons"].values()))
    else:
        g, plan = res["gripper"], res["plan"]
        row.update(action=res["action"], steps=len(plan["steps"]), final_orientations=_orientations(plan),
                   jaw_opening_mm=g["jaw_opening_mm"], jaw_length_mm=g["jaw_length_mm"],
                   push_distance_mm=g["push_distance_mm"], cycle_time_s=g["cycle_time_s"],
                   agreement=(res.get("validation") or {}).get("agreement"))
    return row


def _orientations(plan: dict[str, Any]) -> str:
    """The plan's final world orientations, e.g. ``70.00°; 250.00° ± 0.10°``."""
    u = plan.get("final_uncertainty_deg") or 0.0
    return "; ".join(f"{f:.2f}°" for f in plan["final_orientations_deg"]) + (f" ± {u:.2f}°" if u else "")


def summary_csv(results: list[dict[str, Any]]) -> str:
    buf = io.StringIO()
    w = csv.DictWriter(buf, COLUMNS)
    w.writeheader()
    for r in results:
        w.writerow(_row(r))
    return buf.getvalue()


def _fmt(x: Any) -> str:
    if x is None:
        return "—"
    return f"{x:.3f}" if isinstance(x, float) else str(x)


def report_markdown(results: list[dict[str, Any]], job: dict[str, Any]) -> str:
    spec = catalogue_spec(results)
    lines = [f"# Fixture design report — job {job['id']}", "",
             f"State **{job['state']}**: {spec['oriented']} of {spec['parts']} parts oriented "
             f"({job['failed']} failed, {job['cancelled']} cancelled, {job['pending']} pending).", "",
             "## Gripper specification (covers every oriented part)", "",
             "| quantity | value |", "|---|---|"]
    for key in ("jaw_opening_mm", "jaw_length_mm", "push_stroke_mm", "max_cycle_time_s", "mean_cycle_time_s",
                "jaw_friction_max"):
        lines.append(f"| {key} | {_fmt(spec[key])} |")
    lines.append(f"| jaw friction | {spec['jaw_advice']} |")
    lines.append(f"| plans | {', '.join(f'{a}: {n}' for a, n in spec['actions'].items())} |")
    lines += ["", "## Parts", "", "| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    lines += ["| " + " | ".join(_fmt(v).replace("|", "/") for v in _row(r).values()) + " |" for r in results]
    # a part that failed (or was cancelled) was never judged: it is not one that cannot be oriented
    judged = {r["index"] for r in results if r["status"] == "done"}
    lines += ["", "## Parts that cannot be oriented", ""]
    lines += [f"- {p['index']} `{p['name']}`: {p['why']}" for p in spec["not_oriented"] if p["index"] in judged] or ["(none)"]
    unjudged = [p for p in spec["not_oriented"] if p["index"] not in judged]
    if unjudged:
        lines += ["", "## Parts without a result (failed, cancelled or pending)", ""]
        lines += [f"- {p['index']} `{p['name']}`: {p['why']}" for p in unjudged]
    return "\n".join(lines + _fence_lines(results)) + "\n"


def _fence_lines(results: list[dict[str, Any]]) -> list[str]:
    """The report's conveyor-fence section (conventions §9), when the job designed fences."""
    rows: list[tuple[dict[str, Any], dict[str, Any]]] = [
        (r, r["result"]["fences"]) for r in results if (r.get("result") or {}).get("fences") is not None]
    if not rows:
        return []
    said = next((f["options"] for _, f in rows if f.get("options")), None)  # the job's: one for every part
    out = ["", "## Conveyor fences", ""] + ([_fence_options(said), ""] if said else [])
    out += ["| index | name | fences | belt width | total length | final ± | note |", "|---|---|---|---|---|---|---|"]
    for r, f in rows:
        if f.get("orientable"):
            unit = f["units"]
            out.append(f"| {r['index']} | {r['name']} | {len(f['fences'])} | {f['belt_width']:.4g} {unit} | "
                       f"{f['total_length']:.4g} {unit} | ±{f['final_uncertainty_deg']:.3g}° | "
                       + ", ".join(f"{x['angle_deg']:.2f}°" for x in f["fences"]) + " |")
        else:
            out.append(f"| {r['index']} | {r['name']} | — | — | — | — | {f['message'].replace('|', '/')} |")
    return out


def _fence_options(o: dict[str, Any]) -> str:
    """The fence options a job designed with, as a sentence (``fence_design``'s ``options``)."""
    mu = o["fence_friction"]
    width = "the least each design needs" if o["belt_width"] is None else f"{o['belt_width']:g} (each part's unit)"
    return (f"Designed with fence friction {mu[0]:g}–{mu[1]:g}; "
            + ("consecutive fences on either rail (same rail)" if o["same_rail"] else "fences alternating rails")
            + "; " + ("the turn over each fence's tip modelled" if o["exit_turns"]
                      else "Berretty model (no turn over the fences' tips)")
            + f"; exit guide at {o['exit_steepness_deg']:g}° to the belt; fence margins ≥ {o['min_margin_deg']:g}°; "
            f"belt width {width}.")


def report_files(results: list[dict[str, Any]], job: dict[str, Any]) -> dict[str, str]:
    """File name → text of every report file."""
    return {"results.jsonl": results_jsonl(results), "summary.csv": summary_csv(results),
            "gripper_spec.json": json.dumps(catalogue_spec(results), indent=2) + "\n",
            "report.md": report_markdown(results, job)}


def report_zip(results: list[dict[str, Any]], job: dict[str, Any]) -> bytes:
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as zf:
        for name, text in report_files(results, job).items():
            zf.writestr(name, text)
    return buf.getvalue()


def write_reports(out_dir: Path, results: list[dict[str, Any]], job: dict[str, Any]) -> list[Path]:
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = []
    for name, text in report_files(results, job).items():
        (out_dir / name).write_text(text, encoding="utf-8")
        paths.append(out_dir / name)
    return paths
