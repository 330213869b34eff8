"""The package's layers: every import, lazy ones included, runs down the documented order."""

from __future__ import annotations

import ast
import importlib
import re
import sys
from pathlib import Path

import pytest

import jointattention
from jointattention._moved import MOVED, new_paths

ROOT = Path(jointattention.__file__).parent

# The layers, lowest first (docs/architecture.md): a module may import its own layer's and
# lower layers' modules. Two folders of one layer never import each other (the world and the
# models: the robot's side never sees the world). Each entry: the layer's name and
# the top-level names (folders or modules) in it.
LAYERS = [
    ("plumbing", {"errors", "rng", "datasets", "_arrays", "_checks", "_fields", "_files", "_jit",
                  "_moved", "_readers", "_toml", "_version", "data", "presets"}),
    ("robot", {"agent"}),
    ("world and models", {"world", "models"}),
    ("config", {"config"}),
    ("data and deployment", {"head_recording", "deploy"}),
    ("runner", {"experiment"}),
    ("analysis and env", {"analysis", "env"}),
    ("figures", {"figures"}),
    ("jobs", {"jobs", "testing"}),
    ("cli", {"cli", "__main__"}),
]
# The package's root (``jointattention/__init__``) is above them all: it names its exports
# as strings and loads each on first use.
ROOT_MODULE = ""
# Folders inside a layer's folder (docs/architecture.md, "Modules and their names"): one per
# learner with kernels of its own, and the compiled engine. A learner's folder imports only
# itself, the robot's parts and the plumbing; the engine's private loops only the engine.
LEARNERS = ("models.memory", "models.network", "models.population")
ENGINE = "experiment.compiled"



def layer_of(module: str) -> int:
    """The index in :data:`LAYERS` of ``module``'s layer (KeyError if it has none)."""
    head = module.split(".")[0]
    for i, (_, heads) in enumerate(LAYERS):
        if head in heads:
            return i
    raise KeyError(module)


def wrong_imports(graph: dict[str, set[str]]) -> list[str]:
    """Every import that runs up the layers or across folders of one layer, as text."""
    wrong = []
    for module, imported in sorted(graph.items()):
        if module == ROOT_MODULE:
            continue
        here = layer_of(module)
        for other in sorted(imported):
            there = layer_of(other)
            heads = {module.split(".")[0], other.split(".")[0]}
            apart = (here == there and len(heads) == 2
                     and all((ROOT / head).is_dir() for head in heads))
            if there > here or apart:
                wrong.append(f"{module} ({LAYERS[here][0]}) imports {other} "
                             f"({LAYERS[there][0]})")
    return wrong


def module_graph(root: Path, unresolved: dict[str, set[str]] | None = None
                 ) -> dict[str, set[str]]:
    """{module: modules of the same package it imports}, imports in function bodies included.

    Names are relative to ``root`` (``agent.bootstrap``; a package is its folder's name).
    ``from X import name`` counts as importing ``X.name`` when that is a module, else ``X``.
    Imports of the package that name no module go into ``unresolved`` if it is given.
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
        if unresolved is not None and found - set(modules):
            unresolved[name] = found - set(modules)
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


def test_every_module_has_a_layer():
    """Each module of the package belongs to one documented layer (a new folder needs one)."""
    graph = module_graph(ROOT)
    missing = []
    for module in graph:
        if module != ROOT_MODULE:
            try:
                layer_of(module)
            except KeyError:
                missing.append(module)
    assert not missing


def test_imports_run_down_the_layers():
    """No module imports a higher layer, or another folder of its own layer; lazy ones count."""
    assert wrong_imports(module_graph(ROOT)) == []


def test_each_folder_states_its_layer():
    """Each folder's docstring names its layer's number, as the test's order has it."""
    for i, (name, heads) in enumerate(LAYERS):
        for head in heads:
            init = ROOT / head / "__init__.py"
            if head.startswith("_") or not init.exists() or head in ("data", "presets"):
                continue
            doc = ast.get_docstring(ast.parse(init.read_text(encoding="utf-8"))) or ""
            assert f"Layer {i + 1}" in doc, f"{head}/: expected 'Layer {i + 1}' ({name})"


def subfolders(root: Path) -> list[str]:
    """Every package folder below a top-level folder, as a dotted name (``models.memory``)."""
    return sorted(".".join(init.parent.relative_to(root).parts)
                  for init in root.glob("*/*/**/__init__.py"))


def test_each_subfolder_says_what_it_holds_and_may_import():
    """Each folder inside a layer's folder names its layer and what it may import."""
    assert set(LEARNERS) | {ENGINE} <= set(subfolders(ROOT))
    for folder in subfolders(ROOT):
        init = ROOT.joinpath(*folder.split(".")) / "__init__.py"
        doc = ast.get_docstring(ast.parse(init.read_text(encoding="utf-8"))) or ""
        assert f"layer {layer_of(folder) + 1}" in doc.lower(), folder
        assert "may import" in doc, folder


def foreign_imports(graph: dict[str, set[str]]) -> list[str]:
    """Imports out of a learner's folder past the robot, and into the engine's private loops."""
    wrong = []
    for module, imported in sorted(graph.items()):
        for folder in LEARNERS:
            if module.startswith(f"{folder}."):
                wrong += [f"{module} imports {other}" for other in sorted(imported)
                          if not other.startswith(f"{folder}.") and layer_of(other) > 1]
        if not module.startswith(f"{ENGINE}."):
            wrong += [f"{module} imports {other}" for other in sorted(imported)
                      if other.startswith(f"{ENGINE}._")]
    return wrong


def test_learner_folders_and_the_engine_keep_to_themselves():
    """A learner folder imports no other learner or model; no one else runs the engine's loops."""
    assert foreign_imports(module_graph(ROOT)) == []


# What the compiled engine may not name: the learners' options (the memory's and the
# population code's sections, the network's fields of [model]), the developmental model's own,
# the reinforcement learner's, and the words for their parts. Their kernels carry them
# (agent.protocol.ModuleKernels, AgentKernels, TrialKernels).
LEARNER_WORDS = ("memory", "population", "network", "backprop", "saccade", "recall",
                 "left_out", "pass_over", "hidden", "cell_rad", "radius", "radius_rad",
                 "n_passes", "momentum", "learning_rate", "init_scale", "replay", "blur",
                 "criterion", "developmental")
RL_WORDS = ("min_std", "steps_rad", "lo_rad", "q_stay", "habituation", "reward", "stay",
            "shift", "choice_rng")
# The reinforcement learner's modules, which the engine may not import either.
RL_MODULES = ("models.rl", "models.rl.agent", "models.rl._kernels", "models.rl._trial")


def learner_option_words() -> set[str]:
    """The learners' and the RL model's option names, the developmental model's own, the words."""
    from dataclasses import fields

    from jointattention.models.bootstrap import BootstrapOptions
    from jointattention.models.developmental import DevelopmentalOptions
    from jointattention.models.memory.options import MemoryOptions
    from jointattention.models.population.options import PopulationOptions
    from jointattention.models.rl import RLOptions

    own = {f.name for f in fields(DevelopmentalOptions)} - {
        f.name for f in fields(BootstrapOptions)}
    return {f.name for cls in (MemoryOptions, PopulationOptions, RLOptions)
            for f in fields(cls)} | set(LEARNER_WORDS) | set(RL_WORDS) | own


def words_named(source: str, words: set[str]) -> list[str]:
    """The ``words`` that ``source`` names as whole words, in its order."""
    return [m.group(0) for m in re.finditer(r"[A-Za-z_][A-Za-z0-9_]*", source)
            if m.group(0).lower() in words]


def test_the_compiled_engine_names_no_learner_and_none_of_its_options():
    """No module of the engine imports a learner or the RL model, or names a model's option."""
    engine = ROOT.joinpath(*ENGINE.split("."))
    words = learner_option_words()
    for path in sorted(engine.glob("*.py")):
        assert words_named(path.read_text(encoding="utf-8"), words) == [], path.name
    graph = module_graph(ROOT)
    reached = {other for module, imported in graph.items() if module.startswith(f"{ENGINE}.")
               for other in imported}
    assert not [m for m in reached for folder in LEARNERS if m.startswith(f"{folder}.")]
    assert not reached & set(RL_MODULES)


def test_the_option_scan_sees_a_learner_option_in_the_engine():
    """A loop naming the memory's ``saccade``, a ``cell_rad`` or an RL option is caught."""
    words = learner_option_words()
    assert words_named("d = place_step(a, b, memory.saccade_rad, s.cell_rad)", words) == [
        "memory", "cell_rad"]
    assert words_named("rl_choice_odds(q, state.q_stay, robot.temperature, cdf)", words) == [
        "q_stay", "temperature"]
    assert words_named("evidence = module_observe(module, pan, tilt)", words) == []
    assert words_named("d_pan, d_tilt, lm = agent_act(agent, pan, tilt, act_rng)", words) == []


def test_the_folder_check_sees_a_learner_reaching_out():
    """A memory module importing the population code, and a job the engine's loop, are caught."""
    graph = {"models.memory.module": {"models.population.code", "agent.moves", "_jit"},
             "jobs.y": {"experiment.compiled._loop", "experiment.compiled.cell"}}
    assert len(foreign_imports(graph)) == 2


def test_the_layer_check_sees_an_upward_import():
    """A figure that imports a job, and the world importing a model, are both caught."""
    graph = {"figures.x": {"jobs.y"}, "world.a": {"models.b"}, "jobs.y": set(),
             "models.b": set(), "agent.c": {"errors"}, "errors": set()}
    assert len(wrong_imports(graph)) == 2


def test_no_import_cycle():
    """The package has no import cycle, lazy imports counted."""
    assert cycles(module_graph(ROOT)) == []


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


def test_the_package_imports_no_old_path():
    """Every import of the package names one of its modules: none goes through an old path."""
    unresolved: dict[str, set[str]] = {}
    module_graph(ROOT, unresolved)
    assert unresolved == {}


@pytest.mark.parametrize("old", sorted(MOVED))
def test_an_old_module_path_warns_and_gives_the_new_objects(old):
    """Importing a path of version 0.3.0 warns, naming the new ones, and holds their objects."""
    new = [importlib.import_module(f"jointattention.{path}") for path in new_paths(old)]
    sys.modules.pop(f"jointattention.{old}", None)
    with pytest.warns(DeprecationWarning, match=f"jointattention.{new_paths(old)[-1]}"):
        module = importlib.import_module(f"jointattention.{old}")
    assert module.__all__ == [name for n in new for name in n.__all__]
    assert all(getattr(module, name) is getattr(n, name) for n in new for name in n.__all__)
