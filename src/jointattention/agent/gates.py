"""The gate: how often the learning module's command is chosen (paper, III-E and Fig. 4b).

Each gate is a configuration section holding its own parameters, registered in
:data:`GATES` under the name a configuration uses (``[model.gate] kind = "sigmoid"``). A new
gate is one :class:`Gate` subclass and one :meth:`~jointattention._fields.Registry.register`
call.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._fields import Registry, Section, param
from .._jit import jit

__all__ = ["GATES", "ConstantGate", "Gate", "SigmoidGate", "sigmoid_rate"]


@jit
def sigmoid_rate(t: float, midpoint_steps: float, width_steps: float) -> float:
    """The paper's gate (Fig. 4b): 1 / (1 + exp(-(t - midpoint) / width))."""
    return 1.0 / (1.0 + math.exp(-(t - midpoint_steps) / width_steps))


class Gate(Section):
    """Base of the gates: a rate of choosing the learning module at each learning time."""

    def rate_at(self, learning_time_steps):
        """The rate (0 to 1) at learning time(s) ``learning_time_steps``."""
        raise NotImplementedError

    @property
    def label(self) -> str:
        """A short name for figures and tables."""
        return GATES.name_of(self)


@dataclass(frozen=True)
class SigmoidGate(Gate):
    """The paper's gate: the rate rises from 0 to 1 as a sigmoid of learning time."""

    midpoint_steps: float = param(
        1.2e5, "learning time at which the sigmoid gate chooses each module equally", lo=0)
    width_steps: float = param(
        2.0e4, "learning time over which the sigmoid gate rises by a factor e", lo=1)

    def rate_at(self, learning_time_steps):
        """:func:`sigmoid_rate` at each learning time."""
        t = np.asarray(learning_time_steps, dtype=float)
        mid, width = float(self.midpoint_steps), float(self.width_steps)
        return np.array([sigmoid_rate(x, mid, width) for x in t.ravel()]).reshape(t.shape)


@dataclass(frozen=True)
class ConstantGate(Gate):
    """A constant rate (the paper compares 0.7, 0.9 and 1.0 with the sigmoid in Fig. 5)."""

    rate: float = param(0.9, "rate of choosing the learning module", lo=0, hi=1)

    def rate_at(self, learning_time_steps):
        """``rate`` at every learning time."""
        return np.full(np.shape(learning_time_steps), float(self.rate))

    @property
    def label(self) -> str:
        """``constant <rate>``."""
        return f"constant {self.rate}"


GATES = Registry("gate", {"sigmoid": SigmoidGate, "constant": ConstantGate})
