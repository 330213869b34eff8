"""The seams: new gates and models plug in through their registries alone.

And the public API is what ``__all__`` says.
"""

from __future__ import annotations

import dataclasses
import subprocess
import sys
from dataclasses import dataclass

import numpy as np
import pytest

import jointattention
from jointattention import GATES, MODELS, Body, Gate, ModelOptions, Outcome, param, reproduce
from jointattention.config import AgentConfig, load_config, model_options
from jointattention.experiment.results import cell_path, load_cell


@dataclass(frozen=True)
class StepGate(Gate):
    """An example gate: the visual controller until ``switch_steps``, then the module."""

    switch_steps: float = param(1000.0, "learning time of the switch", lo=0)

    def rate_at(self, learning_time_steps):
        """0 before the switch, 1 from it on."""
        return (np.asarray(learning_time_steps, dtype=float) >= self.switch_steps) * 1.0


class Wanderer:
    """An example model: steps of ``step_deg`` in random directions; learns nothing."""

    def __init__(self, step_rad: float, rng: np.random.Generator):
        self.step_rad, self.rng = step_rad, rng
        self.learning_time_steps = 0
        self.trials_seen = 0

    def begin_trial(self, face_window, theta_rad) -> None:
        """Nothing to prepare."""

    def act(self, detections, theta_rad):
        """A random step."""
        self.learning_time_steps += 1
        angle = self.rng.uniform(0, 2 * np.pi)
        return self.step_rad * np.array([np.cos(angle), np.sin(angle)]), "wander"

    def end_trial(self, outcome: Outcome) -> None:
        """Count the trials."""
        self.trials_seen += 1


@dataclass(frozen=True)
class WandererOptions(ModelOptions):
    """The example model's one option."""

    step_deg: float = param(4.0, "length of a random step", lo=0.1, hi=30)

    def build(self, agent: AgentConfig, body: Body, rng: np.random.Generator) -> Wanderer:
        """The wanderer."""
        return Wanderer(np.deg2rad(self.step_deg), rng)


@pytest.fixture
def registered():
    """The example gate and model, registered for one test."""
    GATES.register("step", StepGate)
    MODELS.register("wanderer", WandererOptions)
    yield
    GATES.unregister("step")
    MODELS.unregister("wanderer")


TINY = """
[experiment]
engine = "python"
n_steps = 600
n_seeds = 2
bin_steps = 200
n_ceiling_trials = 40
"""
HELD_OUT = """
[experiment.held_out]  # measured, on few trials: no test here reads the measures
n_trials = 50
n_checkpoints = 2
"""


def _config(tmp_path, conditions: str):
    path = tmp_path / "c.toml"
    path.write_text(TINY + HELD_OUT + conditions)
    return load_config(path)


def test_a_new_gate_is_one_class_and_one_registry_entry(tmp_path, registered):
    """A registered gate is chosen by name in a condition and drives the agent.

    No module steps before its switch, only module steps after; it is tabulated and checked like the
    others.
    """
    cfg = _config(tmp_path, """
[[experiment.conditions]]
name = "n5-sigmoid"
n_objects = 5
[[experiment.conditions]]
name = "n5-never"
n_objects = 5
model = { gate = { kind = "step", switch_steps = 1e9 } }
[[experiment.conditions]]
name = "n5-always"
n_objects = 5
model = { gate = { kind = "step", switch_steps = 0.0 } }
""")
    result = reproduce(cfg, tmp_path / "run")
    never = load_cell(cell_path(result.out, "n5-never", 0))
    always = load_cell(cell_path(result.out, "n5-always", 0))
    assert never["n_lm_steps"].sum() == 0 and never["n_steps"].sum() > 0
    assert np.array_equal(always["n_lm_steps"], always["n_steps"])
    table = (result.out / "table.md").read_text()
    assert "n5-never" in table and "n5-always" in table
    assert (result.out / "fig5_gates.png").exists()
    assert {c.claim for c in result.claims} >= {"5 objects: starts no better than chance and "
                                                "rises"}


def test_a_new_model_is_one_module_and_one_registry_entry(tmp_path, registered):
    """A registered model runs in a condition beside the paper's, through reproduce.

    Its options come from the configuration; its cells, table row, claims group and side-by-side
    figure are written.
    """
    cfg = _config(tmp_path, """
[[experiment.conditions]]
name = "n3-bootstrap"
n_objects = 3
[[experiment.conditions]]
name = "n3-wanderer"
n_objects = 3
model = { kind = "wanderer", step_deg = 6.0 }
""")
    assert model_options(cfg, cfg.experiment.conditions[1]) == WandererOptions(step_deg=6.0)
    result = reproduce(cfg, tmp_path / "run")
    cell = load_cell(cell_path(result.out, "n3-wanderer", 1))
    assert cell["n_lm_steps"].sum() == 0 and len(cell["success"]) > 0
    assert "n3-wanderer" in (result.out / "table.md").read_text()
    assert (result.out / "models.png").exists()
    assert result.claims and not any("wanderer" in c.reading for c in result.claims)  # no gate
    assert "kind = \"wanderer\"" in (result.out / "config.toml").read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(TINY + "[[experiment.conditions]]\nname = 'w'\n"
                   "model = { kind = 'wanderer', step_deg = 90.0 }\n")
    with pytest.raises(jointattention.ConfigError, match=r"model\.step_deg = 90\.0"):
        load_config(bad)


def test_the_compiled_engine_refuses_what_it_does_not_run_naming_it(tmp_path, registered):
    """A model or gate the compiled engine cannot run is refused when the configuration loads."""
    compiled = TINY.replace('engine = "python"', 'engine = "compiled"')
    for condition, named in [("model = { kind = 'wanderer' }", "model kind 'wanderer'"),
                             ("model = { gate = { kind = 'step' } }", "gate kind 'step'")]:
        path = tmp_path / "c.toml"
        path.write_text(compiled + f"[[experiment.conditions]]\nname = 'x'\n{condition}\n")
        with pytest.raises(jointattention.ConfigError,
                           match=rf"conditions\[0\] \('x'\): .*does not run {named}"):
            load_config(path)
    path.write_text(compiled + "perception = 'rendered'\n")
    with pytest.raises(jointattention.ConfigError, match="perception = 'rendered'"):
        load_config(path)


def test_registries_refuse_clashes_and_non_sections():
    """A name taken by another kind, or a class that is not an options section, is refused."""
    with pytest.raises(ValueError, match="registered already"):
        GATES.register("sigmoid", StepGate)
    with pytest.raises(TypeError, match="Section subclass"):
        MODELS.register("plain", Wanderer)


def _isort_key(name: str) -> tuple[int, str]:
    """The order ruff gives ``__all__``: CONSTANTS, then Classes, then the rest."""
    if name.isupper():
        return 0, name
    return (1, name) if name[0].isupper() else (2, name)


def test_public_api_is_all_and_loads_lazily():
    """``__all__`` is sorted and resolves; importing the package loads no heavy module.

    No world, MuJoCo or matplotlib module is loaded by ``import jointattention``.
    """
    names = jointattention.__all__
    assert names == sorted(names, key=_isort_key)
    for name in names:
        assert getattr(jointattention, name) is not None, name
    assert set(dir(jointattention)) >= set(names)
    code = ("import sys, jointattention\n"
            "bad = [m for m in sys.modules if m.split('.')[0] in ('mujoco', 'matplotlib') "
            "or m.startswith('jointattention.world')]\n"
            "assert not bad, bad\n")
    subprocess.run([sys.executable, "-c", code], check=True)


def test_every_module_declares_its_public_names():
    """Each module of the package has a docstring and an ``__all__`` naming what it defines."""
    import importlib
    import pkgutil

    for info in pkgutil.walk_packages(jointattention.__path__, "jointattention."):
        if info.name.startswith("jointattention.env") or info.name.endswith("__main__"):
            continue  # the env needs the gym extra, __main__ runs the command line
        module = importlib.import_module(info.name)
        assert module.__doc__, info.name
        if not info.ispkg and not info.name.rsplit(".", 1)[-1].startswith("_"):
            assert hasattr(module, "__all__"), info.name
            for name in module.__all__:
                assert hasattr(module, name), f"{info.name}.{name}"


def test_options_are_sections_with_help():
    """Every field of every registered gate and model carries its help text."""
    for registry in (GATES, MODELS):
        for name in registry:
            for f in dataclasses.fields(registry[name]):
                assert f.metadata.get("help"), f"{registry.part} {name}: {f.name}"
