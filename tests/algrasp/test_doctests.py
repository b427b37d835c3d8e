"""The docstring examples run as tests: pytest collects every module of the packages with
``--doctest-modules`` (pyproject.toml), not a hand-kept list (one module on such a list
once never ran). This checks the configuration that makes it so."""

from __future__ import annotations

import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_every_package_module_is_collected_for_doctests() -> None:
    options = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["pytest"]["ini_options"]
    assert "--doctest-modules" in options["addopts"].split()
    assert {"algrasp", "optimisation", "service"} <= set(options["testpaths"])


def test_the_public_api_has_examples() -> None:
    with_examples = sorted(p.relative_to(ROOT).as_posix() for pkg in ("algrasp", "optimisation", "service")
                           for p in (ROOT / pkg).rglob("*.py") if ">>> " in p.read_text())
    assert "algrasp/api.py" in with_examples and "algrasp/io/documents.py" in with_examples
    assert len(with_examples) >= 17, with_examples  # the count only grows
