"""Read run records back: summaries, listing, and replay (recompute and compare).

Reading streams the file, so a crashed run's ``.mcap.partial`` reads up to its last
complete chunk (``read_record(..., partial_ok=True)``).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, cast

from algrasp.errors import AlgraspError, PartDocumentError, RecordError
from algrasp.io.jsonguard import JsonBounds, parse_json

COMPARE_REL = 1e-9
"""Recomputed numbers within this relative difference (or this absolute) are equal."""
RECORD_BOUNDS = JsonBounds(max_string_chars=1_000_000, max_nodes=20_000_000)
"""A record message is read as strictly as a request (finite numbers, valid Unicode),
with room for what the recorder writes (a part document of 100k vertices)."""
IGNORED_KEYS = {"timings_s", "optimisation_timings_s"}
"""Wall-clock fields differ on every run by nature; they are not differences."""


def read_record(path: Path, topics: set[str] | None = None, partial_ok: bool = False) -> dict[str, list[dict[str, Any]]]:
    """JSON messages of a record grouped by topic, in log-time order."""
    from mcap.exceptions import McapError
    from mcap.reader import NonSeekingReader, make_reader

    if not path.is_file():
        raise RecordError(path.name, f"RUN: no such record: {path}")
    out: dict[str, list[dict[str, Any]]] = {}
    try:
        with open(path, "rb") as f:
            reader = make_reader(f) if not partial_ok else NonSeekingReader(f)
            # A partial file is read in file order: sorting by log time would read to
            # the end (and fail there) before yielding anything.
            messages = reader.iter_messages(topics=list(topics) if topics else None, log_time_order=not partial_ok)
            for _schema, channel, message in messages:
                if channel.message_encoding == "json":
                    # The request guard's parser: NaN, lone surrogates, 400-digit numbers
                    # in a damaged record must not reach a JSON response or a plot.
                    out.setdefault(channel.topic, []).append(parse_json(message.data, channel.topic, RECORD_BOUNDS))
    except AlgraspError as exc:
        raise RecordError(path.name, f"RUN: {path.name} is damaged: {exc.message}") from None
    except (McapError, EOFError, ValueError) as exc:
        if not partial_ok:
            raise RecordError(path.name, f"RUN: {path.name} is not a complete MCAP record ({str(exc)[:200]})") from None
    except Exception as exc:  # noqa: BLE001 - a damaged file fails in the decompressor, seek, struct…: all "damaged"
        raise RecordError(path.name, f"RUN: {path.name} is damaged ({type(exc).__name__}: {str(exc)[:200]})") from None
    return out


def summary(path: Path) -> dict[str, Any]:
    """The ``/run`` message of a record (its main figures), checked against its schema
    (a list, a string or a number where the summary should be is a damaged record)."""
    runs = read_record(path, {"/run"}).get("/run", [])
    if not runs:
        raise RecordError(path.name, f"RUN: {path.name} has no /run summary (unfinished run?)")
    checked(runs[-1], "/run", path.name)
    return dict(runs[-1])


def checked(message: Any, topic: str, record: str) -> Any:
    """``message`` if it matches the schema ``topic`` was recorded with, else RecordError."""
    error = next(iter(_validator(topic).iter_errors(message)), None)
    if error is not None:
        where = "/".join(str(x) for x in error.absolute_path) or "(the message)"
        raise RecordError(record, f"RUN: {record} is damaged: {topic} {where}: {error.message[:120]}")
    return message


@functools.cache
def _validator(topic: str) -> Any:
    from jsonschema import Draft202012Validator

    from algrasp.io.record.schemas import TOPICS

    return Draft202012Validator(TOPICS[topic])


def list_runs(directory: Path) -> list[dict[str, Any]]:
    """Summaries (and ``record_path``) of every record in ``directory``, newest first; a
    damaged record is listed as ``{"run_id", "status": "damaged", "error"}`` and the
    listing goes on."""
    out = []
    for p in sorted(directory.glob("*.mcap"), reverse=True):
        try:
            out.append({**summary(p), "record_path": str(p)})
        except AlgraspError as exc:
            out.append({"run_id": p.stem, "status": "damaged", "error": exc.message, "record_path": str(p)})
    return out


def replay(path: Path) -> dict[str, Any]:
    """Recompute analysis and plan from the recorded request and compare them with the
    record. Returns ``{"run_id", "action", "steps", "differences", "summary"}``; a
    difference is ``{"what", "path", "recorded", "recomputed"}``."""
    rec = read_record(path)
    if "/request" not in rec:
        raise RecordError(path.name, f"RUN: {path.name} has no /request: nothing to replay")
    checked(rec["/request"][0], "/request", path.name)
    for topic in ("/plan", "/run"):
        for message in rec.get(topic, []):
            checked(message, topic, path.name)
    with _damaged(path):
        return _replay(rec)


def recorded_plan(path: Path) -> tuple[Any, Any]:
    """``(Analysis, Plan)`` of a recorded plan run, rebuilt from its request — the one
    way replay, ``replay --figure`` and the service's ``figure.svg`` read a plan back.
    Raises RecordError for a run without a plan or a damaged record."""
    rec = read_record(path, {"/request", "/plan"})
    if "/plan" not in rec or "/request" not in rec:
        raise RecordError(path.name, f"RUN: {path.name} has no plan (an analysis, or a failed request)")
    checked(rec["/request"][0], "/request", path.name)
    checked(rec["/plan"][0], "/plan", path.name)
    with _damaged(path):
        request, plan_doc = rec["/request"][0], rec["/plan"][0]
        return _rebuild(request, plan_options(request["options"], plan_doc))


@contextmanager
def _damaged(path: Path) -> Iterator[None]:
    """Messages that decode but are not what we wrote: a RecordError naming the record."""
    try:
        yield
    except PartDocumentError as exc:
        raise RecordError(path.name, f"RUN: {path.name} is damaged: {exc.message}") from None
    except (KeyError, TypeError, IndexError, AttributeError) as exc:
        raise RecordError(path.name, f"RUN: {path.name} is damaged: its messages lack {exc!s:.100}") from None


def _rebuild(request: dict[str, Any], options: dict[str, Any]) -> tuple[Any, Any]:
    """Analysis and (when ``options`` name an action) plan of a recorded request."""
    from algrasp.planning.analysis import Model, analyse_document
    from algrasp.planning.plans import LIMITS_WANTED, LimitsWanted, make_plan

    analysis = analyse_document(request["part"], Model.from_record(options))
    action = options.get("action")
    # A record without the field predates it: its plan searched limits on a refusal only.
    wanted = options.get("limits", "refusal") if analysis.robust is not None else "none"
    limits = cast(LimitsWanted, wanted if wanted in LIMITS_WANTED else "refusal")
    return analysis, None if not action else make_plan(analysis, action, options.get("min_margin_deg", 0.0), limits)


def _replay(rec: dict[str, list[dict[str, Any]]]) -> dict[str, Any]:
    from algrasp.planning.documents import AnalysisDocument, PlanDocument

    request = rec["/request"][0]
    options = request["options"]
    diffs: list[dict[str, Any]] = []
    recorded = rec["/plan"][0] if "/plan" in rec else None
    if recorded is not None:
        PlanDocument.from_json(recorded, "/plan")  # the recorded plan reads back (names what is missing)
        options = plan_options(options, recorded)
    analysis, plan = _rebuild(request, options if recorded is not None else {**options, "action": None})
    if "/analysis" in rec:
        AnalysisDocument.from_json(rec["/analysis"][0], "/analysis")  # reads back (names what is missing)
        diffs += _compare("analysis", rec["/analysis"][0], analysis.to_dict())
    steps: list[Any] = []
    if recorded is not None:
        doc: dict[str, Any] = plan.to_dict()
        if options["optimise"]:
            doc = _optimised(analysis, plan, options, doc)
        diffs += _compare("plan", recorded, doc)
        steps = recorded["steps"]
    if "/fences" in rec:  # a fence validation (conventions §9): its design, recomputed
        diffs += _compare("fences", rec["/fences"][0], _fences(request))
    run = rec.get("/run", [{}])[-1]
    return {"run_id": request["run_id"], "action": options.get("action") or run.get("action"), "steps": steps, "differences": diffs,
            "summary": run, "request": request, "validation": rec.get("/validation", [None])[0]}


def _fences(request: dict[str, Any]) -> dict[str, Any]:
    """The fence document of a recorded fence run's request, recomputed."""
    from algrasp.api import fences

    opts = request["options"]
    from algrasp.planning.analysis import Model

    model = Model.from_record(opts)
    keys = ("fence_friction", "belt_width", "min_margin_deg", "tail")
    layout = fences(request["part"], exact=model.exact, physics=None if model.exact else model.physics.to_dict(),
                    **{k: opts[k] for k in keys if k in opts})
    return dict(layout.to_dict())


def plan_options(options: dict[str, Any], plan_doc: dict[str, Any]) -> dict[str, Any]:
    """The options that made a recorded plan: a CLI/API request's own, or for a batch
    design run (``{"design": ..}``) the chosen action, always optimised."""
    design = options.get("design") or {}
    return {**options, "action": options.get("action") or plan_doc["action"],
            "min_margin_deg": options.get("min_margin_deg", design.get("min_margin_deg", 0.0)),
            "optimise": options.get("optimise", bool(design)),
            "gripper_profile": options.get("gripper_profile", design.get("gripper_profile")),
            # a batch design plans both actions with the headline limit (the largest jaw friction)
            "limits": options.get("limits", "headline" if "placement" in (design.get("physics") or {}) else "none")}


def _optimised(analysis: Any, plan: Any, options: dict[str, Any], doc: dict[str, Any]) -> dict[str, Any]:
    from optimisation.execution import optimise_execution
    from optimisation.profile import profile_from_dict

    profile = profile_from_dict(options.get("gripper_profile") or {})
    return optimise_execution(analysis, plan, profile, options.get("push_scale", 1.0)).apply_to(doc)


def _compare(what: str, recorded: Any, recomputed: Any, path: str = "$") -> list[dict[str, Any]]:
    """Differences between two JSON values (numbers within COMPARE_REL)."""
    if isinstance(recorded, dict) and isinstance(recomputed, dict):
        out = []
        for k in sorted(set(recorded) | set(recomputed)):
            if k in IGNORED_KEYS:
                continue
            if k not in recorded or k not in recomputed:
                out.append({"what": what, "path": f"{path}.{k}", "recorded": recorded.get(k), "recomputed": recomputed.get(k)})
            else:
                out += _compare(what, recorded[k], recomputed[k], f"{path}.{k}")
        return out
    if isinstance(recorded, list) and isinstance(recomputed, list):
        if len(recorded) != len(recomputed):
            return [{"what": what, "path": f"{path}.length", "recorded": len(recorded), "recomputed": len(recomputed)}]
        return [d for i, (a, b) in enumerate(zip(recorded, recomputed)) for d in _compare(what, a, b, f"{path}[{i}]")]
    if isinstance(recorded, (int, float)) and isinstance(recomputed, (int, float)) \
            and not isinstance(recorded, bool) and not isinstance(recomputed, bool):
        if math.isclose(recorded, recomputed, rel_tol=COMPARE_REL, abs_tol=COMPARE_REL):
            return []
    elif recorded == recomputed:
        return []
    return [{"what": what, "path": path, "recorded": recorded, "recomputed": recomputed}]
