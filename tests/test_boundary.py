"""The robot's side never sees the experimenter's side."""

from __future__ import annotations

import ast
import os
import subprocess
import sys
from pathlib import Path

import jointattention

AGENT = Path(jointattention.__file__).parent / "agent"


def _imports(path: Path) -> list[str]:
    tree = ast.parse(path.read_text(), filename=str(path))
    names = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names += [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            dots = "." * node.level
            names.append(f"{dots}{node.module or ''}")
            names += [f"{dots}{node.module or ''}.{a.name}" for a in node.names]
    return names


def test_agent_sources_never_import_world():
    """No module under agent/ names the world package in an import, absolute or relative."""
    files = sorted(AGENT.rglob("*.py"))
    assert files, "agent/ has no modules"
    for path in files:
        for name in _imports(path):
            parts = name.lstrip(".").split(".")
            assert "world" not in parts, f"{path.name} imports {name}"


def test_importing_agent_loads_no_world_module():
    """Importing every module of the agent package pulls no jointattention.world in."""
    code = (
        "import importlib, pkgutil, sys, jointattention.agent as a\n"
        "for m in pkgutil.iter_modules(a.__path__):\n"
        "    importlib.import_module(f'{a.__name__}.{m.name}')\n"
        "bad = [m for m in sys.modules if m.startswith('jointattention.world')]\n"
        "assert not bad, bad\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


def test_the_boundary_test_catches_a_violation(tmp_path):
    """The import scan sees a relative import of the world package."""
    bad = tmp_path / "bad.py"
    bad.write_text("from ..world.simulator import World\n")
    assert any("world" in n.split(".") for n in _imports(bad))


def test_importing_the_world_changes_no_environment_variable():
    """Importing the world's modules neither sets MUJOCO_GL nor imports MuJoCo.

    The first World does both.
    """
    code = (
        "import os, sys\n"
        "os.environ.pop('MUJOCO_GL', None)\n"
        "import jointattention.world.simulator, jointattention.world.rendered\n"
        "assert 'MUJOCO_GL' not in os.environ and 'mujoco' not in sys.modules\n"
        "jointattention.world.simulator.World()\n"
        "assert os.environ['MUJOCO_GL'] in ('egl', 'osmesa') and 'mujoco' in sys.modules\n"
    )
    env = {k: v for k, v in os.environ.items() if k != "MUJOCO_GL"}
    subprocess.run([sys.executable, "-c", code], check=True, env=env)


def test_the_library_never_touches_matplotlib_backends():
    """No module calls ``matplotlib.use`` or imports pyplot: figures are Figure objects."""
    for path in sorted(AGENT.parent.rglob("*.py")):
        assert "matplotlib.use(" not in path.read_text(), path.name
        assert not any("pyplot" in name.split(".") for name in _imports(path)), path.name
