"""check_agent: every registered model passes it, one registered here too; broken ones fail."""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np
import pytest

from jointattention import MODELS, Body, ModelOptions
from jointattention.agent.options import AgentConfig
from jointattention.models.bootstrap import BootstrapOptions
from jointattention.testing import AgentCheckError, check_agent
from test_seams import WandererOptions

KINDS = sorted(MODELS)


@pytest.mark.parametrize("kind", KINDS)
def test_every_registered_model_passes(kind):
    """Each model of the registry, with its default options, passes every check it declares."""
    check_agent(MODELS[kind]())


@pytest.mark.parametrize("learner", ["memory", "population"])
def test_the_bootstrap_model_passes_with_each_learning_module(learner):
    """The episodic and the population-coded modules pass too (the network is the default)."""
    check_agent(BootstrapOptions(learner=learner))


@pytest.fixture
def registered():
    """Register ``kinds`` for one test; unregister them after."""
    names = []

    def register(name, options):
        MODELS.register(name, options)
        names.append(name)

    yield register
    for name in names:
        MODELS.unregister(name)


def test_a_model_registered_by_a_test_passes(registered):
    """A model from outside the package (test_seams' wanderer) is one class and one line."""
    registered("wanderer", WandererOptions)
    check_agent(WandererOptions(step_deg=6.0))


class _Broken:
    """A wanderer whose faults the options choose."""

    def __init__(self, fault: str, rng):
        self.fault, self.rng, self.learning_time_steps = fault, rng, 0

    def begin_trial(self, face_window, theta_rad):
        """Nothing."""

    def act(self, detections, theta_rad):
        """A random step, or one with a fault."""
        self.learning_time_steps += 1
        draw = np.random.uniform() if self.fault == "global" else self.rng.uniform()
        step = np.array([np.cos(6.3 * draw), np.sin(6.3 * draw)]) * 0.07
        return (np.array([np.nan, 0.0]) if self.fault == "nan" else step), "wander"

    def end_trial(self, outcome):
        """Nothing."""


@dataclass(frozen=True)
class _BrokenOptions(ModelOptions):
    fault: str = "nan"

    def build(self, agent: AgentConfig, body: Body, rng):
        return _Broken(self.fault, rng)


@pytest.mark.parametrize(("fault", "words"), [
    ("nan", "expected a finite (pan, tilt) step"),
    ("global", "two new agents of the same seed moved differently"),
])
def test_a_broken_model_fails_naming_the_check(registered, fault, words):
    """A step of NaN, or draws from numpy's global generator, fail with the check's words."""
    registered("broken", _BrokenOptions)
    with pytest.raises(AgentCheckError, match=re.escape(words)):
        check_agent(_BrokenOptions(fault=fault))


def test_unregistered_options_are_refused():
    """Options of a kind nobody registered: one error saying to register it."""
    with pytest.raises(AgentCheckError, match="not registered"):
        check_agent(_BrokenOptions())
