"""The robot's side never sees the experimenter's side."""

from __future__ import annotations

import ast
import os
import subprocess
import sys
from pathlib import Path

import jointattention

AGENT = Path(jointattention.__file__).parent / "agent"
# The robot's side: its parts, the whole models, and what runs on a real robot (which reads
# a run's configuration, and so the world's options, but imports nothing of the world itself).
ROBOT_SIDE = ("agent", "models", "deploy")


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
    """No module of the robot's side names the world package in an import."""
    files = sorted(p for side in ROBOT_SIDE for p in (AGENT.parent / side).rglob("*.py"))
    assert len(files) >= 30
    for path in files:
        for name in _imports(path):
            parts = name.lstrip(".").split(".")
            assert "world" not in parts, f"{path.name} imports {name}"


def test_importing_agent_loads_no_world_module():
    """Importing every module of the robot's parts and models pulls no jointattention.world in."""
    code = (
        "import importlib, pkgutil, sys\n"
        "for side in ('agent', 'models'):\n"
        "    a = importlib.import_module(f'jointattention.{side}')\n"
        "    for m in pkgutil.iter_modules(a.__path__):\n"
        "        importlib.import_module(f'{a.__name__}.{m.name}')\n"
        "bad = [m for m in sys.modules if m.startswith('jointattention.world')]\n"
        "assert not bad, bad\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


def test_the_boundary_test_catches_a_violation(tmp_path):
    """The import scan sees a relative import of the world package."""
    bad = tmp_path / "bad.py"
    bad.write_text("from ..world.simulator import World\n")
    assert any("world" in n.split(".") for n in _imports(bad))


def test_the_library_reads_mujoco_gl_and_never_writes_it():
    """Without MUJOCO_GL a world renders nothing: one line says what to set; nothing is set."""
    code = (
        "import os, sys\n"
        "from jointattention.errors import RenderingUnavailable\n"
        "import jointattention.world.simulator, jointattention.world.rendered\n"
        "assert 'mujoco' not in sys.modules\n"
        "world = jointattention.world.simulator.World()\n"
        "try:\n"
        "    world.render()\n"
        "except RenderingUnavailable as err:\n"
        "    assert 'MUJOCO_GL is not set; expected MUJOCO_GL=' in str(err), err\n"
        "else:\n"
        "    raise AssertionError('rendered without MUJOCO_GL')\n"
        "assert 'MUJOCO_GL' not in os.environ and 'PYOPENGL_PLATFORM' not in os.environ\n"
    )
    env = {k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "PYOPENGL_PLATFORM")}
    subprocess.run([sys.executable, "-c", code], check=True, env=env)


def _environment_writes(path: Path) -> list[str]:
    """The environment writes in a module: os.environ set, updated or deleted; os.putenv."""
    def is_environ(node) -> bool:
        return isinstance(node, ast.Attribute) and node.attr == "environ"

    found = []
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        targets = node.targets if isinstance(node, ast.Assign) else (
            node.targets if isinstance(node, ast.Delete) else [])
        if any(isinstance(t, ast.Subscript) and is_environ(t.value) for t in targets):
            found.append(f"line {node.lineno}: os.environ[...]")
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
            f = node.func
            if (is_environ(f.value) and f.attr in ("setdefault", "update", "pop", "clear")) \
                    or f.attr in ("putenv", "unsetenv"):
                found.append(f"line {node.lineno}: {f.attr}")
    return found


def test_no_library_module_writes_an_environment_variable(tmp_path):
    """Only the command line's main sets a variable (MUJOCO_GL, for its own process)."""
    for path in sorted(AGENT.parent.rglob("*.py")):
        writes = _environment_writes(path)
        if path.relative_to(AGENT.parent).as_posix() == "cli/__init__.py":
            assert [w.split(": ")[1] for w in writes] == ["setdefault"], writes
        else:
            assert writes == [], f"{path.name}: {writes}"
    bad = tmp_path / "bad.py"
    bad.write_text("import os\nos.environ['X'] = '1'\nos.environ.setdefault('Y', '2')\n")
    assert len(_environment_writes(bad)) == 2


def test_the_library_never_touches_matplotlib_backends():
    """No module calls ``matplotlib.use`` or imports pyplot: figures are Figure objects."""
    for path in sorted(AGENT.parent.rglob("*.py")):
        assert "matplotlib.use(" not in path.read_text(), path.name
        assert not any("pyplot" in name.split(".") for name in _imports(path)), path.name
