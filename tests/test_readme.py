"""Every code block of the README runs as written (issue 33), in a scratch directory that
sees the checkout's ``.venv``, ``algrasp/`` and ``tests/`` and the default cell:

- ``console`` blocks: each ``$ command`` runs, and each line printed under it in the README
  appears in what it prints (``…`` stands for anything);
- ``sh`` blocks: run with ``bash -e`` (``localhost:8000`` becomes a service this test starts);
- ``python`` blocks: saved as a script and run with the venv's Python.

Only the ``make`` lines of the first block are not run here: CI runs ``make test`` itself,
and ``make run`` is ``algrasp serve`` (started below for the HTTP example)."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BLOCK = re.compile(r"^```(\w+)\n(.*?)^```", re.S | re.M)
BLOCKS = [(m.group(1), m.group(2), ROOT.joinpath("README.md").read_text()[: m.start()].count("\n") + 1)
          for m in BLOCK.finditer(ROOT.joinpath("README.md").read_text(encoding="utf-8"))]


@pytest.fixture(scope="module")
def sandbox(tmp_path_factory: pytest.TempPathFactory) -> Path:
    box = tmp_path_factory.mktemp("readme")
    for name in (".venv", "algrasp", "tests"):
        (box / name).symlink_to(ROOT / name)
    return box


@pytest.fixture(scope="module")
def service_url(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    from service.launch import start_server

    server = start_server(tmp_path_factory.mktemp("readme-service"), ALGRASP_WORKERS="1", ALGRASP_CELL="default")
    yield server.url
    server.kill()


def _env() -> dict[str, str]:
    """The environment of a fresh shell: the embedded defaults (records in ``logs/``, the
    default cell), none of the suite's settings."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("ALGRASP_")}
    return {**env, "PATH": f"{ROOT / '.venv' / 'bin'}{os.pathsep}{os.environ['PATH']}"}


def _run(cmd: list[str], cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(cmd, cwd=cwd, env=_env(), capture_output=True, text=True, timeout=900)


def _ids(kind: str) -> list[str]:
    return [f"line-{line}" for k, _, line in BLOCKS if k == kind]


def test_the_readme_has_each_kind_of_block() -> None:
    kinds = [k for k, _, _ in BLOCKS]
    assert {"sh", "console", "python"} <= set(kinds) and kinds.count("sh") >= 6


@pytest.mark.parametrize("text", [t for k, t, _ in BLOCKS if k == "console"], ids=_ids("console"))
def test_console_blocks_print_what_they_show(text: str, sandbox: Path) -> None:
    for command, shown in re.findall(r"^\$ (.+)\n((?:(?!\$ ).*\n)*)", text, re.M):
        out = _run(["bash", "-c", command.split("  #")[0]], sandbox)
        printed = out.stdout + out.stderr
        for line in shown.splitlines():
            pieces = [p.strip() for p in line.split("…") if p.strip()]
            at = 0
            for piece in pieces:  # in order, "…" standing for anything
                at = printed.find(piece, at)
                assert at >= 0, f"{command!r} did not print {piece!r}; it printed:\n{printed}"


@pytest.mark.parametrize("text", [t for k, t, _ in BLOCKS if k == "sh"], ids=_ids("sh"))
def test_shell_blocks_run(text: str, sandbox: Path, request: pytest.FixtureRequest) -> None:
    lines = [ln for ln in text.replace("\\\n", " ").splitlines() if ln.strip() and not ln.startswith("make ")]
    if not lines:
        assert "make test" in text and "make run" in text  # the first block: CI runs these
        return
    script = "\n".join(lines)
    if "localhost:8000" in script:
        script = script.replace("localhost:8000", request.getfixturevalue("service_url").removeprefix("http://"))
        script = script.replace("curl -s ", "curl -sf ")  # an HTTP error fails the block
    out = _run(["bash", "-e", "-o", "pipefail", "-c", script], sandbox)
    assert out.returncode == 0, f"{script}\n--- stdout\n{out.stdout[-3000:]}\n--- stderr\n{out.stderr[-3000:]}"


@pytest.mark.sim
@pytest.mark.parametrize("text", [t for k, t, _ in BLOCKS if k == "python"], ids=_ids("python"))
def test_python_blocks_run_as_scripts(text: str, sandbox: Path) -> None:
    script = sandbox / "readme_example.py"
    script.write_text(text, encoding="utf-8")
    out = _run([str(ROOT / ".venv" / "bin" / "python"), script.name], sandbox)
    assert out.returncode == 0, f"--- stdout\n{out.stdout[-3000:]}\n--- stderr\n{out.stderr[-3000:]}"
    assert "Traceback" not in out.stderr and out.stdout.count("\n") >= 5
    assert sys.executable  # the scripts run in the venv's Python, not this one's site
