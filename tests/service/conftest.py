"""A real service: uvicorn in a subprocess on a free loopback port, its own log dir and
SQLite database; tests talk to it over HTTP with httpx."""

from __future__ import annotations

import json
import resource
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import httpx
import psutil
import pytest

from service.launch import LocalServer
from service.launch import start_server as launch

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "algrasp" / "examples" / "pie-20.json"


Server = LocalServer


def dxf_bytes(build: Callable[[Any], None]) -> bytes:
    """A DXF drawing made by ``build(doc)`` on a new ezdxf document, as a file's bytes."""
    import io

    import ezdxf

    doc = ezdxf.new()
    build(doc)
    out = io.StringIO()
    doc.write(out)
    return out.getvalue().encode()


def pool_workers(pid: int) -> list[psutil.Process]:
    """The pool workers (spawned interpreters; not the resource tracker) under server
    ``pid`` that are alive now. A worker a fault just killed can still be listed as a
    child, then be gone or a zombie (not yet reaped) when its command line is read: it is
    no worker any more, so it is left out rather than failing the test."""
    out = []
    for p in psutil.Process(pid).children(recursive=True):
        try:
            if "spawn_main" in " ".join(p.cmdline()):
                out.append(p)
        except psutil.NoSuchProcess:  # gone, or a zombie (ZombieProcess is one)
            continue
    return out


def refuse_writes(server: LocalServer, limit: int) -> None:
    """RLIMIT_FSIZE on the server's workers: no file they write may grow past ``limit``
    bytes (0: every record write fails, as on a full disk; -1 lifts it). Not on the
    server: its own log and database are files too."""
    for p in psutil.Process(server.proc.pid).children(recursive=True):
        try:
            _, hard = resource.prlimit(p.pid, resource.RLIMIT_FSIZE)
            resource.prlimit(p.pid, resource.RLIMIT_FSIZE, (limit if limit >= 0 else hard, hard))
        except (psutil.NoSuchProcess, ProcessLookupError):
            pass


PAUSED = "run records cannot be written"


def paused(server: LocalServer) -> int:
    """How often the service's jobs have paused on a record-store fault (its logs)."""
    return sum(p.read_text(errors="replace").count(PAUSED) for p in server.log_dir.glob("server-*.log"))


def start_server(log_dir: Path, **env: str) -> LocalServer:
    return launch(log_dir, ALGRASP_WORKERS="1", **env)


@pytest.fixture(scope="session")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    s = start_server(tmp_path_factory.mktemp("service"))
    yield s
    s.kill()


@pytest.fixture(scope="session")
def pie() -> dict[str, Any]:
    return json.loads(EXAMPLE.read_text())


def wait_job(client: httpx.Client, job_id: str, timeout_s: float = 120) -> dict[str, Any]:
    deadline = time.time() + timeout_s
    while time.time() < deadline:
        p = client.get(f"/v1/jobs/{job_id}").json()
        if p["state"] not in ("queued", "running"):
            return p  # type: ignore[no-any-return]
        time.sleep(0.2)
    raise AssertionError(f"job {job_id} did not finish in {timeout_s} s")
