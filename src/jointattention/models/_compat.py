"""The agent classes of version 0.3 whose learning module is not the network, kept until 0.5.

Version 0.3 subclassed the bootstrap agent for the episodic and the population-coded learning
modules (``MemoryAgent``, ``PopulationAgent``); now :class:`~.bootstrap.BootstrapAgent`
composes its module (``options.learner``). The old names build that agent, with a
:class:`DeprecationWarning`; the old module paths (``jointattention.agent.episodic``,
``jointattention.agent.population_agent``) lead here.
"""

from __future__ import annotations

import dataclasses
import warnings

from .bootstrap import BootstrapAgent
from .population.module import line_step

__all__ = ["MemoryAgent", "PopulationAgent", "line_step"]


def _built(learner: str, old: str, options, mechanisms, body, rng) -> BootstrapAgent:
    warnings.warn(f"{old} is deprecated and goes in version 0.5; expected "
                  f"BootstrapOptions(learner={learner!r}).build(...) (a BootstrapAgent)",
                  DeprecationWarning, stacklevel=3)
    return BootstrapAgent(dataclasses.replace(options, learner=learner), mechanisms, body, rng)


def MemoryAgent(options, mechanisms, body, rng) -> BootstrapAgent:
    """The bootstrap agent with the episodic learning module (deprecated)."""
    return _built("memory", "MemoryAgent", options, mechanisms, body, rng)


def PopulationAgent(options, mechanisms, body, rng) -> BootstrapAgent:
    """The bootstrap agent with the population-coded learning module (deprecated)."""
    return _built("population", "PopulationAgent", options, mechanisms, body, rng)
