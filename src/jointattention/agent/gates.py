"""The gate: how often the learning module's command is chosen (paper, III-E and Fig. 4b).

Each gate is a configuration section holding its own parameters, registered in
:data:`GATES` under the name a configuration uses (``[model.gate] kind = "sigmoid"``). A new
gate is one :class:`Gate` subclass and one :meth:`~jointattention._fields.Registry.register`
call.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .._fields import Registry, Section, param
from .._jit import jit
from ..errors import ConfigError

__all__ = ["CONSTANT", "EVIDENCE", "GATES", "PERFORMANCE", "SIGMOID", "ConstantGate",
           "EvidenceGate", "Gate", "PerformanceGate", "SigmoidGate", "agreement_update",
           "evidence_rate", "performance_rate", "sigmoid_rate"]

# The compiled loop's code of each gate it runs (jointattention.experiment.compiled._loop)
SIGMOID, CONSTANT, PERFORMANCE, EVIDENCE = 0, 1, 2, 3


@jit
def sigmoid_rate(t: float, midpoint_steps: float, width_steps: float) -> float:
    """The paper's gate (Fig. 4b): 1 / (1 + exp(-(t - midpoint) / width))."""
    return 1.0 / (1.0 + math.exp(-(t - midpoint_steps) / width_steps))


class Gate(Section):
    """Base of the gates: a rate of choosing the learning module at each learning time.

    Each gate declares what the rest of the package needs to know of it:

    Attributes:
        compiled: whether the compiled engine runs it (then :meth:`compiled_inputs` says how).
        claims_role: which of the paper's claims its conditions are checked by: ``"sigmoid"``
            (the paper's gate: rises, reaches the ceiling, beats the constant rates),
            ``"constant"`` (a fixed rate: the baseline), ``"performance"`` (as the sigmoid,
            and it must beat the others at 5 objects) or None (no claim of the paper).
        measured: whether its rate follows a measure the agent keeps (:meth:`rate_of`,
            :meth:`update`) rather than the learning time.
        per_face: whether its rate follows the learning module's evidence for the face in
            view (:meth:`rate_of`); only the episodic memory measures it.
    """

    compiled: ClassVar[bool] = False
    claims_role: ClassVar[str | None] = None
    measured: ClassVar[bool] = False
    per_face: ClassVar[bool] = False

    def rate_at(self, learning_time_steps):
        """The rate (0 to 1) at learning time(s) ``learning_time_steps``."""
        raise NotImplementedError

    def compiled_inputs(self) -> tuple[int, float, float, float]:
        """The gate as the compiled loop takes it: its code and up to three parameters."""
        raise NotImplementedError(f"the compiled engine does not run gate {self.label!r}")

    @property
    def label(self) -> str:
        """A short name for figures and tables."""
        return GATES.name_of(self)


@dataclass(frozen=True)
class SigmoidGate(Gate):
    """The paper's gate: the rate rises from 0 to 1 as a sigmoid of learning time."""

    compiled: ClassVar[bool] = True
    claims_role: ClassVar[str | None] = "sigmoid"

    midpoint_steps: float = param(
        1.2e5, "learning time at which the sigmoid gate chooses each module equally", lo=0)
    width_steps: float = param(
        2.0e4, "learning time over which the sigmoid gate rises by a factor e", lo=1)

    def rate_at(self, learning_time_steps):
        """:func:`sigmoid_rate` at each learning time."""
        t = np.asarray(learning_time_steps, dtype=float)
        mid, width = float(self.midpoint_steps), float(self.width_steps)
        return np.array([sigmoid_rate(x, mid, width) for x in t.ravel()]).reshape(t.shape)

    def compiled_inputs(self) -> tuple[int, float, float, float]:
        """The code and the midpoint and width."""
        return SIGMOID, float(self.midpoint_steps), float(self.width_steps), 1.0


@dataclass(frozen=True)
class ConstantGate(Gate):
    """A constant rate (the paper compares 0.7, 0.9 and 1.0 with the sigmoid in Fig. 5)."""

    compiled: ClassVar[bool] = True
    claims_role: ClassVar[str | None] = "constant"

    rate: float = param(0.9, "rate of choosing the learning module", lo=0, hi=1)

    def rate_at(self, learning_time_steps):
        """``rate`` at every learning time."""
        return np.full(np.shape(learning_time_steps), float(self.rate))

    def compiled_inputs(self) -> tuple[int, float, float, float]:
        """The code and the rate."""
        return CONSTANT, float(self.rate), 0.0, 1.0

    @property
    def label(self) -> str:
        """``constant <rate>``."""
        return f"constant {self.rate}"


@jit
def agreement_update(agreement: float, u0: float, u1: float, v0: float, v1: float,
                     agree_rad: float, window_trials: float) -> float:
    """The running agreement after one self-evaluated trial.

    The trial agrees if the learning module's command at its start, ``u``, points within
    ``agree_rad`` of the place the evaluator fired on, ``v`` (both from the start's head angle).
    The agreement is an exponential average over about ``window_trials`` trials.
    """
    nu, nv = math.hypot(u0, u1), math.hypot(v0, v1)
    agreed = nu > 0 and nv > 0 and (u0 * v0 + u1 * v1) > math.cos(agree_rad) * nu * nv
    return agreement + ((1.0 if agreed else 0.0) - agreement) / window_trials


@jit
def performance_rate(agreement: float, agree_rad: float, full_agreement: float) -> float:
    """The performance gate's rate: 0 at chance agreement, 1 at ``full_agreement``, linear."""
    chance = agree_rad / math.pi  # a command in a uniformly random direction
    return min(max((agreement - chance) / (full_agreement - chance), 0.0), 1.0)


@dataclass(frozen=True)
class PerformanceGate(Gate):
    """Beyond the paper: the rate follows the learning module's measured performance.

    After each trial the evaluator ends, the robot checks whether its learning module, asked
    at the trial's start, pointed toward the place the evaluator fired on
    (:func:`agreement_update`). The rate rises from 0 at chance agreement to 1 at
    ``full_agreement`` (:func:`performance_rate`). The learning time plays no part.
    """

    compiled: ClassVar[bool] = True
    claims_role: ClassVar[str | None] = "performance"
    measured: ClassVar[bool] = True

    agree_deg: float = param(
        20.0, "a trial agrees if the module's command points within this angle of the place "
        "found", lo=1, hi=90)
    window_trials: float = param(
        3000.0, "trials over which the agreement is averaged (exponentially)", lo=1, hi=1e6)
    full_agreement: float = param(
        0.6, "agreement at which the module is always chosen", lo=0, hi=1)

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.full_agreement <= self.agree_deg / 180:
            raise ConfigError(f"full_agreement = {self.full_agreement}: expected more than "
                              f"the chance agreement agree_deg / 180 = {self.agree_deg / 180:.3f}")

    @property
    def agree_rad(self) -> float:
        """``agree_deg`` in radians."""
        return math.radians(self.agree_deg)

    def rate_at(self, learning_time_steps):
        """NaN: the rate is not a function of learning time."""
        return np.full(np.shape(learning_time_steps), np.nan)

    def rate_of(self, agreement: float) -> float:
        """The rate at a measured agreement (:func:`performance_rate`)."""
        return performance_rate(float(agreement), self.agree_rad, float(self.full_agreement))

    def update(self, agreement: float, command, place) -> float:
        """The agreement after a trial whose module pointed ``command`` and found ``place``.

        Both are (pan, tilt) from the trial's start (:func:`agreement_update`).
        """
        return agreement_update(float(agreement), float(command[0]), float(command[1]),
                                float(place[0]), float(place[1]), self.agree_rad,
                                float(self.window_trials))

    def compiled_inputs(self) -> tuple[int, float, float, float]:
        """The code, the agreement angle, the full agreement and the window."""
        return (PERFORMANCE, self.agree_rad, float(self.full_agreement),
                float(self.window_trials))


@jit
def evidence_rate(evidence_trials: float, floor_trials: float, half_trials: float) -> float:
    """The evidence gate's rate: 0 up to the floor, then e / (e + half) of the evidence e beyond."""
    e = evidence_trials - floor_trials
    return e / (e + half_trials) if e > 0 else 0.0


@dataclass(frozen=True)
class EvidenceGate(Gate):
    """Beyond the paper: the rate follows the learning module's evidence for the face in view.

    At each trial's start the episodic memory recalls a place for the caregiver's face, with
    its evidence: how many kept trials agree on it beyond chance
    (:func:`~jointattention.models.memory.episodic.memory_recall`). The module drives the steps
    of faces it has found often and leaves the others to visual attention, so control passes face by
    face as soon as each is known. The rate nears 1 only as the evidence grows
    (:func:`evidence_rate`): visual attention keeps some steps, and a face whose place is wrong
    (its evidence stops growing) goes on being explored. Needs ``learner = "memory"``.
    """

    compiled: ClassVar[bool] = True
    per_face: ClassVar[bool] = True

    floor_trials: float = param(
        1.0, "evidence (kept trials agreeing on the recalled place beyond chance) up to which "
        "visual attention drives every step", lo=0, hi=1e6)
    half_trials: float = param(
        0.5, "evidence beyond the floor at which the module drives half the steps",
        lo=1e-3, hi=1e6)

    def rate_at(self, learning_time_steps):
        """NaN: the rate is not a function of learning time."""
        return np.full(np.shape(learning_time_steps), np.nan)

    def rate_of(self, evidence_trials: float) -> float:
        """The rate for a face whose recalled place has this evidence (:func:`evidence_rate`)."""
        return evidence_rate(float(evidence_trials), float(self.floor_trials),
                             float(self.half_trials))

    def compiled_inputs(self) -> tuple[int, float, float, float]:
        """The code, the floor and the half-rate evidence."""
        return EVIDENCE, float(self.floor_trials), float(self.half_trials), 1.0


GATES = Registry("gate", {"sigmoid": SigmoidGate, "constant": ConstantGate,
                          "performance": PerformanceGate, "evidence": EvidenceGate})
