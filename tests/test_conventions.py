"""Conventions the code keeps everywhere (brief: "How we write code").

- Degrees ↔ radians are converted in one place, :mod:`algrasp.geometry.angles`.
- No bare small tolerance inside a function: every epsilon is a named, documented constant
  (most in :mod:`algrasp.geometry.tolerances`), so each comparison says which one it makes.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SOURCES = sorted(p for pkg in ("algrasp", "optimisation", "service") for p in (ROOT / pkg).rglob("*.py"))
CONVERSION = re.compile(r"\b(np|numpy|math)\.(degrees|radians|deg2rad|rad2deg)\(")


def _code(path: Path) -> str:
    """The source without docstrings (doctests may show a conversion in an example)."""
    tree = ast.parse(path.read_text())
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if isinstance(body, list) and body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
            body[0] = ast.Pass()
    return ast.unparse(tree)


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(ROOT)))
def test_angles_are_converted_in_one_place(path: Path) -> None:
    if path.name == "angles.py":
        return
    found = CONVERSION.findall(_code(path))
    assert not found, f"{path.name}: use algrasp.geometry.angles.to_deg/to_rad, not {found}"


def _bare_epsilons(tree: ast.AST) -> list[tuple[int, float]]:
    out = []
    for fn in ast.walk(tree):
        if not isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            continue
        for node in ast.walk(fn):
            if isinstance(node, ast.Constant) and isinstance(node.value, float) and 0.0 < abs(node.value) < 1e-5:
                out.append((node.lineno, node.value))
    return out


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(ROOT)))
def test_no_bare_epsilon_inside_functions(path: Path) -> None:
    found = _bare_epsilons(ast.parse(path.read_text()))
    assert not found, f"{path.name}: name these tolerances (algrasp.geometry.tolerances): {found}"


def test_the_checks_can_fail() -> None:
    assert CONVERSION.search("x = math.degrees(a)")
    assert _bare_epsilons(ast.parse("def f(x):\n    return abs(x) < 1e-9\n")) == [(2, 1e-9)]
    assert _bare_epsilons(ast.parse("EPS = 1e-9\ndef f(x):\n    return abs(x) < EPS\n")) == []
