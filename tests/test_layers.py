"""The package's import graph: which modules import which, lazy imports included."""

from __future__ import annotations

import ast
from pathlib import Path

import jointattention

ROOT = Path(jointattention.__file__).parent

# The import cycle left (docs/architecture.md; issue 30 removes it). A new cycle, or a
# module joining one, fails the test; removing one means taking it off this list.
KNOWN_CYCLES = [
    {"agent.bootstrap", "agent.episodic", "agent.population_agent"},
]


def module_graph(root: Path) -> dict[str, set[str]]:
    """{module: modules of the same package it imports}, imports in function bodies included.

    Names are relative to ``root`` (``agent.bootstrap``; a package is its folder's name).
    ``from X import name`` counts as importing ``X.name`` when that is a module, else ``X``.
    """
    def name_of(path: Path) -> str:
        parts = list(path.relative_to(root).with_suffix("").parts)
        return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)

    modules = {name_of(p): p for p in root.rglob("*.py")}
    top = root.name
    graph = {}
    for name, path in modules.items():
        here = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
        here = [h for h in here if h]
        found = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                found |= {a.name.removeprefix(f"{top}.") for a in node.names
                          if a.name.startswith(f"{top}.")}
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = here[:len(here) - node.level + 1]
                    target = ".".join(base + ([node.module] if node.module else []))
                elif (node.module or "").startswith(top):
                    target = node.module.removeprefix(top).lstrip(".")
                else:
                    continue
                for alias in node.names:
                    sub = f"{target}.{alias.name}".lstrip(".")
                    found.add(sub if sub in modules else target)
        graph[name] = {m for m in found if m in modules and m != name}
    return graph


def cycles(graph: dict[str, set[str]]) -> list[set[str]]:
    """The strongly connected components of more than one module (Tarjan's algorithm)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    result = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = set()
            while True:
                w = stack.pop()
                component.add(w)
                if w == v:
                    break
            if len(component) > 1:
                result.append(component)

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return result


def test_no_import_cycle_beyond_the_known_ones():
    """The package's import cycles, lazy imports counted, are exactly the listed ones."""
    found = cycles(module_graph(ROOT))
    assert sorted(map(sorted, found)) == sorted(map(sorted, KNOWN_CYCLES))


def test_the_scan_sees_a_cycle_closed_by_a_lazy_import(tmp_path):
    """A cycle whose second import sits in a function body is a cycle."""
    pkg = tmp_path / "pkg"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "sub" / "__init__.py").write_text("")
    (pkg / "sub" / "a.py").write_text("from .b import thing\n")
    (pkg / "sub" / "b.py").write_text("def thing():\n    from . import a\n    return a\n")
    (pkg / "c.py").write_text("from .sub.a import thing\n")
    assert cycles(module_graph(pkg)) == [{"sub.a", "sub.b"}]
