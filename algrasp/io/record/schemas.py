"""JSON schemas of algrasp's own MCAP channels (draft 2020-12), derived from the typed
documents of :mod:`algrasp.io.documents` — not written a second time.

Every message on a JSON channel is validated against these in the tests; payloads use
degrees and the part's unit, as every interface does (docs/conventions.md §1). The
``/validation`` message is the validation document without its embedded plan (the plan is
on ``/plan``).

>>> TOPICS["/plan"]["title"], sorted(TOPICS)
('algrasp.Plan', ['/analysis', '/fence_validation', '/fences', '/plan', '/request', '/run', '/sim/state', '/validation'])
"""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel

from algrasp.io.documents import (
    AnalysisDocument,
    FenceDocument,
    FenceValidationDocument,
    PlanDocument,
    RequestDocument,
    RunSummary,
    SimState,
    ValidationDocument,
    json_schema,
)


def _channel(model: type[BaseModel], title: str) -> dict[str, Any]:
    return {**json_schema(model), "title": title}


TOPICS: dict[str, dict[str, Any]] = {
    "/request": _channel(RequestDocument, "algrasp.Request"),
    "/analysis": _channel(AnalysisDocument, "algrasp.Analysis"),
    "/plan": _channel(PlanDocument, "algrasp.Plan"),
    "/validation": _channel(ValidationDocument, "algrasp.Validation"),
    "/sim/state": _channel(SimState, "algrasp.SimState"),
    "/fences": _channel(FenceDocument, "algrasp.Fences"),
    "/fence_validation": _channel(FenceValidationDocument, "algrasp.FenceValidation"),
    "/run": _channel(RunSummary, "algrasp.Run"),
}
"""Each JSON channel's schema; the title is the MCAP schema name viewers show."""
