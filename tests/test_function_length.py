"""No function of the package is longer than a reader can hold: 120 lines at most."""

from __future__ import annotations

import ast
from pathlib import Path

import jointattention

MAX_LINES = 120
PACKAGE = Path(jointattention.__file__).parent


def long_functions(root: Path, max_lines: int = MAX_LINES) -> list[str]:
    """Each function (methods and nested ones too) under ``root`` longer than ``max_lines``."""
    found = []
    for path in sorted(root.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                lines = node.end_lineno - node.lineno + 1
                if lines > max_lines:
                    found.append(f"{path.relative_to(root)}:{node.lineno} {node.name} ({lines})")
    return found


def test_no_function_of_the_package_is_over_120_lines():
    """Every function in the package, decorators aside, is at most 120 lines long."""
    assert long_functions(PACKAGE) == []


def test_the_scan_sees_a_long_method(tmp_path):
    """The scan finds a method over the limit, nested in a class, and counts its lines."""
    body = "\n".join(f"        x{i} = {i}" for i in range(MAX_LINES))
    (tmp_path / "m.py").write_text(f"class A:\n    def long(self):\n{body}\n")
    assert long_functions(tmp_path) == [f"m.py:2 long ({MAX_LINES + 1})"]
