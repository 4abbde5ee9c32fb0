"""The house rules, checked on the source (ast): no import circles, no module over 800
lines, no private name or module imported across packages (third-party ones included)."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1] / "liquidamp"
MAX_LINES = 800


def _modules() -> dict[str, Path]:
    mods = {}
    for p in ROOT.rglob("*.py"):
        parts = list(p.relative_to(ROOT.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        mods[".".join(parts)] = p
    return mods


MODULES = _modules()
TREES = {m: ast.parse(p.read_text(), str(p)) for m, p in MODULES.items()}


def _resolve(name: str) -> str | None:
    """The package module that ``name`` (a module or a name in one) lives in."""
    while name and name not in MODULES:
        name = name.rpartition(".")[0]
    return name or None


def _imports(tree):
    """(module, names) of every import anywhere in ``tree`` (function-level ones too)."""
    for n in ast.walk(tree):
        if isinstance(n, ast.ImportFrom) and n.level == 0 and n.module:
            yield n.module, [a.name for a in n.names]
        elif isinstance(n, ast.Import):
            for a in n.names:
                yield a.name, []


def import_graph(trees=None) -> dict[str, set[str]]:
    """Module -> the package modules it imports (at any level of the code)."""
    trees = TREES if trees is None else trees
    graph = {m: set() for m in trees}
    for m, tree in trees.items():
        for mod, names in _imports(tree):
            if not mod.startswith("liquidamp"):
                continue
            targets = [_resolve(f"{mod}.{n}") for n in names] or [_resolve(mod)]
            graph[m].update(t for t in targets if t and t != m and t in graph)
    return graph


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_the_cycle_finder_finds_a_circle():
    """The checker itself: a two-module circle through a function-level import is found."""
    a = ast.parse("from liquidamp.b import f\n")
    b = ast.parse("def g():\n    from liquidamp.a import h\n")
    graph = {"liquidamp.a": {"liquidamp.b"}, "liquidamp.b": {"liquidamp.a"}}
    assert cycles(graph) == [["liquidamp.a", "liquidamp.b"]]
    assert [list(_imports(t)) for t in (a, b)] == [[("liquidamp.b", ["f"])],
                                                   [("liquidamp.a", ["h"])]]


def test_no_import_circles():
    """Imports flow one way (function-level imports count: they only hide a circle)."""
    assert cycles(import_graph()) == []


@pytest.mark.parametrize("module", sorted(MODULES))
def test_no_module_over_800_lines(module):
    n = len(MODULES[module].read_text().splitlines())
    assert n <= MAX_LINES, f"{module} has {n} lines (at most {MAX_LINES}); split it by topic"


def _package(module: str) -> str:
    return ".".join(module.split(".")[:2])


def _private(parts) -> bool:
    return any(p.startswith("_") and not p.startswith("__") for p in parts)


def private_imports() -> list[str]:
    """Imports of a private module or name from another package (or another project)."""
    bad = []
    for m, tree in TREES.items():
        for mod, names in _imports(tree):
            if mod == "__future__":
                continue
            if mod.startswith("liquidamp.") and mod.count(".") == 1:
                continue  # a top-level module (errors, options, _numba_cache): shared by all
            foreign = not mod.startswith("liquidamp") or _package(mod) != _package(m)
            if foreign and (_private(mod.split(".")) or _private(names)):
                bad.append(f"{m}: {mod} {names}")
    return bad


def test_no_private_names_imported_across_packages():
    assert private_imports() == []


def test_the_private_import_check_sees_scipy_private_tables():
    """The checker itself, on the import this rule removed from coupled/fast.py."""
    tree = ast.parse("def f():\n    from scipy.integrate._ivp import dop853_coefficients\n")
    saved = dict(TREES)
    try:
        TREES["liquidamp.coupled.fast"] = tree
        assert private_imports() == [
            "liquidamp.coupled.fast: scipy.integrate._ivp ['dop853_coefficients']"]
    finally:
        TREES.clear()
        TREES.update(saved)


def test_every_cached_kernel_module_is_guarded_against_a_stale_cache():
    """Numba keys a cache on its own file only: each module with cache=True kernels is in
    liquidamp._numba_cache.COMPILED_SOURCES (the stamp) and calls drop_stale at import."""
    from liquidamp._numba_cache import COMPILED_SOURCES

    compiled = sorted(str(p.relative_to(ROOT)) for m, p in MODULES.items()
                      if re.search(r"njit\(\s*cache=True", p.read_text()))
    assert compiled and set(compiled) <= set(COMPILED_SOURCES)
    for rel in compiled:
        assert "drop_stale(__file__)" in (ROOT / rel).read_text(), rel
