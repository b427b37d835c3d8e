"""Start the service in a subprocess on a free loopback port (tests and benchmarks):
its own log directory and SQLite database, killed with its workers as one process group."""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any


@dataclass
class LocalServer:
    url: str
    proc: subprocess.Popen[bytes]
    log_dir: Path

    def client(self, **kw: Any) -> Any:
        import httpx

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


def start_server(log_dir: Path, timeout_s: float = 60.0, **env: str) -> LocalServer:
    """``algrasp serve --no-example`` with ``ALGRASP_LOG_DIR=log_dir`` (and ``env``); returns
    once ``/healthz`` answers. The server's output goes to ``log_dir/server-PORT.log``."""
    return _start(log_dir, timeout_s, ("--no-example",), env)


def start_example_server(log_dir: Path, timeout_s: float = 60.0, **env: str) -> LocalServer:
    """:func:`start_server` as ``make run`` starts it: the example part planned at start-up
    (``/healthz`` answers once that plan is made)."""
    return _start(log_dir, timeout_s, (), env)


def _start(log_dir: Path, timeout_s: float, flags: tuple[str, ...], env: dict[str, str]) -> LocalServer:
    import httpx

    port = free_port()
    log_path = log_dir / f"server-{port}.log"
    with open(log_path, "ab") as log:
        proc = subprocess.Popen([sys.executable, "-m", "algrasp.cli", "serve", *flags, "--port", str(port), "--log-level",
                                 "warning"], env={**os.environ, "ALGRASP_LOG_DIR": str(log_dir), **env},
                                stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    server = LocalServer(f"http://127.0.0.1:{port}", proc, log_dir)
    deadline = time.time() + timeout_s
    while time.time() < deadline:
        if proc.poll() is not None:
            raise RuntimeError(log_path.read_text())
        try:
            if httpx.get(f"{server.url}/healthz", timeout=1).status_code == 200:
                return server
        except httpx.TransportError:
            time.sleep(0.2)
    server.kill()
    raise RuntimeError(f"the service did not start within {timeout_s} s")
