"""The teacher: the bootstrap model taught by the caregiver instead of its own evaluator.

The supervised bound of the bootstrap model, after the authors' earlier model (Nagai, Asada,
Hosoda 2002), where the caregiver tells the robot when it succeeded. Everything is the
bootstrap model's (visual attention, the gate, the learning module, what a trial teaches)
except which trials it learns from: only those in which the evaluator fired on the object
the caregiver looks at (:attr:`~jointattention.agent.protocol.Outcome.approved`). What it
gains over the bootstrap model bounds what the self-evaluation gives up.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..agent.options import AgentConfig
from ..agent.protocol import Body, Outcome
from ..errors import ConfigError
from .bootstrap import BootstrapAgent, BootstrapOptions

__all__ = ["TeacherAgent", "TeacherOptions"]


@dataclass(frozen=True)
class TeacherOptions(BootstrapOptions):
    """The teacher's options: the bootstrap model's (docs/neighbours.md)."""

    compiled: ClassVar[bool] = True
    taught: ClassVar[bool] = True

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.learner != "backprop":
            raise ConfigError(f"model kind 'teacher' with learner = {self.learner!r}: the "
                              "teacher is the paper's network taught by the caregiver; "
                              "expected learner = 'backprop'")

    def build(self, mechanisms: AgentConfig, body: Body, rng: np.random.Generator) -> TeacherAgent:
        """The untrained teacher agent."""
        return TeacherAgent(self, mechanisms, body, rng)


class TeacherAgent(BootstrapAgent):
    """The bootstrap agent that learns only from the trials the caregiver approves."""

    def _judge(self, outcome: Outcome) -> bool:
        """The caregiver judges the trial: whether the evaluator fired on her target."""
        return bool(outcome.approved)

    def end_trial(self, outcome: Outcome) -> int:
        """Learn as the bootstrap agent does, if the caregiver approves the trial."""
        if not self.learning or not self._judge(outcome):
            return 0
        return super().end_trial(outcome)
