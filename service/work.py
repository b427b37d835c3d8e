"""The tasks worker processes run (local pool or Dask): plain functions of picklable
arguments. Each records its run (MCAP) and returns ``(response, run, error)``: the
response (None on error), the run row the server stores, and the user error (an
:class:`AlgraspError`, which pickles across processes) or None.
"""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import TYPE_CHECKING, Any

from algrasp.errors import AlgraspError, StorageError
from algrasp.io.record.session import Recording, recording

if TYPE_CHECKING:  # the planning stack loads in the worker, on first use
    from algrasp.pipeline import PlanRequest

TaskResult = tuple[dict[str, Any] | None, dict[str, Any], AlgraspError | None]


def _run_row(rec: Recording, command: str, doc: dict[str, Any], action: str | None, error: AlgraspError | None,
             plan_doc: dict[str, Any] | None = None, agreement: float | None = None) -> dict[str, Any]:
    name = doc.get("name") if isinstance(doc.get("name"), str) else None
    return {"run_id": rec.run_id, "command": command, "part_name": name, "action": action,
            "steps": None if plan_doc is None else len(plan_doc["steps"]), "agreement": agreement,
            "cycle_time_s": None if plan_doc is None else plan_doc.get("cycle_time_s"),
            "status": "error" if error else "ok", "error": error.to_dict() if error else None}


def analysis_task(doc: dict[str, Any], record_dir: str, options: dict[str, Any] | None = None,
                  run_id: str | None = None) -> TaskResult:
    """``POST /v1/analyses``: the analysis object of ``algrasp analyze``; ``options``
    ``{"exact", "physics"}`` choose the model (default robust); ``"samples"`` > 0 adds the
    drawing samples of :mod:`algrasp.planning.sampled` (not recorded: they follow from it)."""
    from algrasp.planning.analysis import Model, analyse_document
    from algrasp.planning.sampled import sampled

    options = dict(options or {})
    samples = int(options.pop("samples", 0))
    model = Model.from_options(options)
    try:
        with recording(True, Path(record_dir), "analyze", doc, model.to_options(), run_id) as rec:
            analysis = analyse_document(doc, model)
            out = analysis.to_dict()
            rec.analysis(out)
            if samples:
                out = {**out, **sampled(analysis, samples)}
    except StorageError:
        raise  # no run to report: the record could not be written
    except AlgraspError as exc:
        return None, _run_row(rec, "analyze", doc, None, exc), exc
    return {**out, "run_id": rec.run_id}, _run_row(rec, "analyze", doc, None, None), None


def fences_task(doc: dict[str, Any], options: dict[str, Any], drawing: str | None = None) -> dict[str, Any] | str:
    """``POST /v1/fences``: the fence document, or with ``drawing`` ("svg", "dxf") the
    drawing's text (not recorded: no run of the gripper cell)."""
    from algrasp.api import fences
    from algrasp.io.fence_drawing import dxf_text, svg_text

    layout = fences(doc, **options)
    if drawing is None:
        return dict(layout.to_dict())
    return svg_text(layout) if drawing == "svg" else dxf_text(layout)


def fences_validate_task(doc: dict[str, Any], options: dict[str, Any], samples: int, seed: int,
                         record_dir: str) -> dict[str, Any]:
    """``POST /v1/fences`` with ``validate``: the fence document with its ``validation``
    (simulated on a belt in Drake, in this worker) and the record's ``run_id``."""
    from algrasp.api import fences, validate_fences

    layout = fences(doc, **options)
    v = validate_fences(doc, samples=samples, seed=seed, record=True, record_dir=record_dir, **options)
    return {**layout.to_dict(), "validation": v.to_dict(), "run_id": v.run_id}


def plan_task(doc: dict[str, Any], req: PlanRequest, record_dir: str, sim_workers: int,
              run_id: str | None = None) -> TaskResult:
    """``POST /v1/plans``: the plan document (+ ``validation`` when asked for). ``req`` is
    the request's options as the route checked them (built once, pickled with its model)."""
    from algrasp.pipeline import plan_part

    command = "validate" if req.samples else "plan"
    try:
        with recording(True, Path(record_dir), command, doc, req.record_options(), run_id) as rec:
            out = plan_part(doc, req, rec, sim_workers=sim_workers)
    except StorageError:
        raise  # no run to report: the record could not be written
    except AlgraspError as exc:
        return None, _run_row(rec, command, doc, req.action, exc), exc
    v = out.validation_doc(with_plan=False)
    response = {**out.plan_doc, "run_id": rec.run_id, "validation": v}
    return response, _run_row(rec, command, doc, req.action, None, out.plan_doc, None if v is None else v["agreement"]), None


def design_task(doc: dict[str, Any], options: dict[str, Any], record_dir: str, sim_workers: int,
                run_id: str | None = None) -> TaskResult:
    """One part of a batch job: its fixture design (``service.fixture.design_part``)."""
    from algrasp.planning.analysis import analyse_document
    from service.fixture import DesignOptions, design_part

    opts = DesignOptions(**options)
    out: dict[str, Any] = {}
    try:
        with recording(True, Path(record_dir), "design", doc, {"design": options}, run_id) as rec:
            analysis = analyse_document(doc, opts.model)
            if not (analysis.squeeze.steps or analysis.push_grasp.steps):
                rec.analysis(analysis.to_dict())  # no plan follows; else plan_part records the analysis
            out = design_part(doc, opts, rec, analysis, sim_workers)
    except StorageError:
        raise  # no run to report: the record could not be written
    except AlgraspError as exc:
        return None, _run_row(rec, "design", doc, None, exc), exc
    val = out.get("validation") or {}
    return {**out, "run_id": rec.run_id}, _run_row(rec, "design", doc, out.get("action"), None, out.get("plan"),
                                                   val.get("agreement")), None


def design_chunk(items: list[tuple[dict[str, Any], str]], options: dict[str, Any], record_dir: str,
                 sim_workers: int) -> list[TaskResult]:
    """Several parts of a batch job in one task: ``design_task`` for each ``(doc, run_id)``,
    in order. Chunks spare the per-task round trip to the pool; a chunk whose worker is
    lost is retried part by part by the runner."""
    return [design_task(doc, options, record_dir, sim_workers, run_id) for doc, run_id in items]


def figure_task(record_path: str) -> bytes:
    """The plan figure (SVG) of a recorded plan run, recomputed from its request."""
    from algrasp.io.record.replay import recorded_plan
    from algrasp.plots import plan_figure

    analysis, plan = recorded_plan(Path(record_path))
    with tempfile.TemporaryDirectory() as tmp:
        return plan_figure(analysis, plan, Path(tmp) / "figure.svg").read_bytes()


def import_task(filename: str, data: bytes, options: dict[str, Any]) -> dict[str, Any]:
    """``POST /v1/imports``: a CAD file's part document (checked to be a valid part), or
    with ``list_parts`` the list of the parts on the sheet; a fence layout DXF its layout."""
    from algrasp.geometry.part import load_part
    from algrasp.io.cad import import_bytes, list_parts, sheet_documents
    from algrasp.io.fence_import import fence_layout_of

    if filename.lower().endswith(".dxf") and (layout := fence_layout_of(data, filename[:-4])) is not None:
        return layout  # a fence layout DXF answers its layout (listed or not: it has no parts)
    if options.pop("list_parts", False):
        options.pop("part", None)
        documents = options.pop("documents", 0)
        sheet_options = {k: v for k, v in options.items() if k != "pose"}
        if documents:
            out = sheet_documents(filename, data, documents, **sheet_options)
            for doc in out["documents"]:
                load_part(doc)
            return out
        return list_parts(filename, data, **sheet_options)
    doc = import_bytes(filename, data, **options)
    load_part(doc)
    return doc
