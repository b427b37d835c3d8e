"""The engineers' workbench: a static page at ``/`` (``service/static``) that uses the
public REST API only, and the Foxglove layout that opens a run record with the right
panels (``/v1/layouts/foxglove.json``).

Everything the page needs ships in the package (no CDN: the cell network has no
internet); the page itself holds no secret, so it is served without a key and asks
for one when the API answers 401.
"""

from __future__ import annotations

import json
from functools import cache
from importlib.resources import files
from pathlib import Path
from typing import Any

from fastapi import APIRouter, FastAPI
from fastapi.responses import FileResponse
from fastapi.staticfiles import StaticFiles

from service.contract import ERRORS, ExamplesOut, LayoutOut, ok
from service.middleware import ParsedJsonRoute
from service.runtime import AUTH

STATIC = Path(__file__).with_name("static")
LAYOUT = STATIC / "foxglove-layout.json"
EXAMPLES = Path(str(files("algrasp") / "examples"))
router = APIRouter(route_class=ParsedJsonRoute)


@cache
def _layout() -> dict[str, Any]:
    return json.loads(LAYOUT.read_text())  # type: ignore[no-any-return]


@router.get("/", include_in_schema=False)
async def index() -> FileResponse:
    return FileResponse(STATIC / "index.html", media_type="text/html", headers={"Cache-Control": "no-cache"})


@router.get("/v1/layouts/foxglove.json", tags=["runs"], dependencies=AUTH, response_model=None, responses=ok(LayoutOut))
async def foxglove_layout() -> dict[str, Any]:
    """A Foxglove layout for run records: the 3D scene (part and jaws), φ/α and jaw
    plots of ``/sim/state``, and the ``/plan``, ``/validation`` and ``/run`` messages.
    Import it in Foxglove (Layouts → Import), then open the run's MCAP."""
    return _layout()


@cache
def _examples() -> dict[str, tuple[str, dict[str, Any]]]:
    """The bundled example parts by name: the paper's (``algrasp/examples``) and real
    drawings' (``algrasp/examples/real``, origin and licence in each ``source``)."""
    paper = {p.stem: ("paper", json.loads(p.read_text())) for p in sorted(EXAMPLES.glob("*.json"))}
    return {**paper, **{p.stem: ("real", json.loads(p.read_text())) for p in sorted((EXAMPLES / "real").glob("*.json"))}}


@router.get("/v1/examples", tags=["service"], dependencies=AUTH, response_model=None, responses=ok(ExamplesOut))
async def examples() -> dict[str, Any]:
    """The bundled example part documents, by name; ``kind``: ``paper`` (the paper's
    parts) or ``real`` (parts of real drawings, their origin and licence in ``source``)."""
    return {"examples": [{"name": k, "kind": kind, "part": v} for k, (kind, v) in _examples().items()]}


def mount(app: FastAPI) -> None:
    """The page at ``/`` and its scripts and styles at ``/ui``."""
    app.include_router(router, responses=ERRORS)
    app.mount("/ui", StaticFiles(directory=STATIC), name="ui")
