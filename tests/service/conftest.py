"""A real service: uvicorn in a subprocess on a free loopback port, its own log dir and
SQLite database; tests talk to it over HTTP with httpx."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import httpx
import pytest

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "algrasp" / "examples" / "pie-20.json"


@dataclass
class Server:
    url: str
    proc: subprocess.Popen[bytes]
    log_dir: Path
    env: dict[str, str]

    def client(self, **kw: Any) -> httpx.Client:
        return httpx.Client(base_url=self.url, timeout=120, **kw)

    def kill(self) -> None:
        """SIGKILL the server and its worker processes (its own process group)."""
        if self.proc.poll() is None:
            os.killpg(self.proc.pid, signal.SIGKILL)
            self.proc.wait(10)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def start_server(log_dir: Path, **env_extra: str) -> Server:
    port = free_port()
    env = {**os.environ, "ALGRASP_LOG_DIR": str(log_dir), "ALGRASP_WORKERS": "1", **env_extra}
    log = open(log_dir / f"server-{port}.log", "ab")  # noqa: SIM115 - the server outlives this function
    proc = subprocess.Popen([sys.executable, "-m", "algrasp.cli", "serve", "--no-example", "--port", str(port),
                             "--log-level", "warning"], env=env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    server = Server(f"http://127.0.0.1:{port}", proc, log_dir, env)
    deadline = time.time() + 60
    while time.time() < deadline:
        if proc.poll() is not None:
            raise RuntimeError((log_dir / f"server-{port}.log").read_text())
        try:
            if httpx.get(f"{server.url}/healthz", timeout=1).status_code == 200:
                return server
        except httpx.TransportError:
            time.sleep(0.2)
    server.kill()
    raise RuntimeError("the service did not start within 60 s")


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
