"""Layering (issue 19): dependencies point one way — the top (service, CLI, public API,
adapters: ``algrasp.io`` CAD import and records, ``algrasp.sim``, plots, the pipeline) →
optimisation → the core (``algrasp.planning`` → ``algrasp.geometry``); no import circles
among module-level imports, ``if TYPE_CHECKING:`` ones included.

Known violations still to remove are listed in KNOWN with the reason; the test fails on
any new one, and on a listed one that has gone (so the list only shrinks)."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("algrasp", "optimisation", "service")
ADAPTERS = ("algrasp.io", "algrasp.sim", "algrasp.plots", "algrasp.cli", "algrasp.api",
            "algrasp.lifecycle", "algrasp.pipeline", "algrasp.testing")
KNOWN: dict[tuple[str, str], str] = {}


def _modules() -> dict[str, Path]:
    out = {}
    for pkg in PACKAGES:
        for path in (ROOT / pkg).rglob("*.py"):
            parts = path.relative_to(ROOT).with_suffix("").parts
            out[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return out


def _is_type_checking(node: ast.stmt) -> bool:
    test = node.test if isinstance(node, ast.If) else None
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


def _module_level(tree: ast.Module) -> list[ast.stmt]:
    """The statements run on import, with the bodies of ``if TYPE_CHECKING:`` blocks: an
    import hidden there is still a dependency (a circle hidden from the interpreter is a
    circle for the reader and the type checker)."""
    out: list[ast.stmt] = []
    for node in tree.body:
        out += [node, *node.body] if isinstance(node, ast.If) and _is_type_checking(node) else [node]
    return out


def _imports(path: Path, top_level_only: bool) -> set[str]:
    tree = ast.parse(path.read_text())
    nodes = _module_level(tree) if top_level_only else list(ast.walk(tree))
    out = set()
    for node in nodes:
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            out.add(node.module)
            out |= {f"{node.module}.{a.name}" for a in node.names}
    return {m for m in out if m.split(".")[0] in PACKAGES}


def _layer(module: str) -> int:
    """0 geometry and planning (and the error types), 1 optimisation, 2 the top: adapters,
    the CLI, the public API and the service. Within the core, geometry never imports
    planning (``test_geometry_is_below_planning``)."""
    if module.startswith(("service", "algrasp.lifecycle")) or module == "algrasp" or module.startswith(ADAPTERS):
        return 2
    return 1 if module.startswith("optimisation") else 0


def test_no_upward_imports() -> None:
    mods = _modules()
    found = set()
    for name, path in mods.items():
        for target in _imports(path, top_level_only=False):
            if target in mods and _layer(target) > _layer(name) :
                found.add((name, target))
    new = sorted(found - set(KNOWN))
    assert not new, f"upward imports: {new}"
    gone = sorted(set(KNOWN) - found)
    assert not gone, f"fixed, remove from KNOWN: {gone}"


def test_no_import_circles() -> None:
    mods = _modules()
    graph = {n: {t for t in _imports(p, top_level_only=True) if t in mods and t != n} for n, p in mods.items()}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    circles = []

    def visit(v: str) -> None:  # Tarjan's strongly connected components
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                circles.append(sorted(comp))

    for v in graph:
        if v not in index:
            visit(v)
    assert not circles, circles


def test_geometry_is_below_planning() -> None:
    mods = _modules()
    found = sorted((n, t) for n, p in mods.items() if n.startswith("algrasp.geometry")
                   for t in _imports(p, top_level_only=False) if t.startswith("algrasp.planning"))
    assert not found, found


def test_type_checking_imports_are_read() -> None:
    """The circle check sees imports under ``if TYPE_CHECKING:`` (bank.py once hid
    bank → hull → bank there)."""
    tree = ast.parse("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from algrasp.geometry.hull import X\n")
    names = [n.module for n in _module_level(tree) if isinstance(n, ast.ImportFrom)]
    assert names == ["typing", "algrasp.geometry.hull"]


def test_core_uses_no_test_generators() -> None:
    mods = _modules()
    found = sorted((n, t) for n, p in mods.items() if _layer(n) < 2
                   for t in _imports(p, top_level_only=False) if t.startswith("algrasp.testing"))
    assert not found, found
