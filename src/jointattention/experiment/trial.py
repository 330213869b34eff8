"""The one loop over the steps of a trial, its step function, and the trial record.

The robot starts looking at the caregiver's face. At each step the internal evaluator (Eq. 3)
looks at the image centre; if an object is there the trial ends ("fired"). Otherwise the agent
moves the head. A trial also ends at the step limit, or when a move hits a joint limit (the
robot then looks once more, where the head stopped).

:class:`SceneTrial` is the step function over a :class:`~jointattention.world.protocol.Scene`;
:func:`run_trial` drives any :class:`Trial` with an
:class:`~jointattention.agent.protocol.Agent`. The Gymnasium environment steps a
:class:`SceneTrial` too, and :class:`jointattention.env.EnvTrial` lets :func:`run_trial` drive an
agent through the environment.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from .._jit import jit
from ..agent.detections import Detections
from ..agent.protocol import LM, RANDOM, Agent, Outcome
from ..world.kinematics import HeadKinematics, separation_rad
from ..world.protocol import Scene

__all__ = ["END_FIRED", "END_LIMIT", "END_STEPS", "RECORD", "RUNNING", "SceneTrial", "StepObserver",
           "Trial", "TrialResult", "end_after_look", "move_head", "records", "run_trial"]

END_FIRED, END_STEPS, END_LIMIT = 0, 1, 2
RUNNING = -1  # the end of a trial that has not ended, in the compiled loops


@jit
def move_head(pan: float, tilt: float, d_pan: float, d_tilt: float, lo_pan: float,
              hi_pan: float, lo_tilt: float, hi_tilt: float) -> tuple[float, float, bool]:
    """One move of the head, stopped at its joint limits: (pan, tilt, whether a limit stopped it).

    The one step of every trial: :class:`SceneTrial`, the compiled engine's loop and the native
    vector environment all move the head with it.
    """
    want_pan, want_tilt = pan + d_pan, tilt + d_tilt
    pan = min(max(want_pan, lo_pan), hi_pan)
    tilt = min(max(want_tilt, lo_tilt), hi_tilt)
    return pan, tilt, pan != want_pan or tilt != want_tilt


@jit
def end_after_look(seen: int, limit_hit: bool, n_steps: int, max_steps: int) -> int:
    """How a trial ends after a look, or :data:`RUNNING` if it goes on.

    It fired (Eq. 3: ``seen``, the detection at the image centre, is not -1), a joint limit
    stopped the last move, or it is out of steps.
    """
    if seen >= 0:
        return END_FIRED
    if limit_hit:
        return END_LIMIT
    if n_steps >= max_steps:
        return END_STEPS
    return RUNNING


# The trial record: one row per trial in a cell's file and in trials.csv.
RECORD = {
    "learning_time": (np.int64, "the agent's learning time when the trial began (steps)"),
    "n_steps": (np.int32, "head moves in the trial"),
    "n_lm_steps": (np.int32, "of them, moves made by the learning module"),
    "n_random_steps": (np.int32, "of them, random moves (the visual controller saw nothing)"),
    "attended": (np.int16, "object the evaluator fired on (-1: it did not fire)"),
    "target": (np.int16, "the caregiver's target"),
    "end": (np.int8, "how the trial ended: 0 fired, 1 step limit, 2 joint limit"),
    "success": (bool, "joint attention: the object attended is the target"),
    "fired": (bool, "the internal evaluator fired"),
}


@dataclass(frozen=True)
class TrialResult:
    """What happened in one trial (the experimenter's record, :data:`RECORD`)."""

    learning_time: int
    n_steps: int
    n_lm_steps: int
    n_random_steps: int
    attended: int
    target: int
    end: int
    theta_end_rad: np.ndarray

    @property
    def fired(self) -> bool:
        """Whether the internal evaluator fired."""
        return self.end == END_FIRED

    @property
    def success(self) -> bool:
        """Joint attention: the object finally attended is the caregiver's target."""
        return self.attended == self.target


def records(results: Sequence[TrialResult]) -> dict[str, np.ndarray]:
    """The columns of :data:`RECORD` for ``results``."""
    return {name: np.array([getattr(r, name) for r in results], dtype=dtype)
            for name, (dtype, _) in RECORD.items()}


class Trial(Protocol):
    """A trial in progress, as :func:`run_trial` drives it.

    Attributes:
        theta_rad: the head angle now.
        detections: what the detector reports at ``theta_rad``.
        n_steps: head moves so far.
        end: ``None`` while the trial runs, then :data:`END_FIRED`, :data:`END_STEPS` or
            :data:`END_LIMIT`.
        attended: the object the evaluator fired on (-1 if none): the experimenter's id.
        target: the caregiver's target (the experimenter's knowledge).
    """

    theta_rad: np.ndarray
    detections: Detections
    n_steps: int
    end: int | None
    attended: int
    target: int

    def step(self, dtheta_rad: np.ndarray) -> None:
        """Move the head by ``dtheta_rad`` (stopping at the joint limits), look, evaluate."""

    @property
    def outcome(self) -> Outcome:
        """How the trial ended, as the robot knows it."""


class SceneTrial:
    """The trial's step function over a scene.

    Args:
        scene: what the robot sees (:class:`~jointattention.world.protocol.Scene`).
        theta_start_rad: the head angle at the start (looking at the caregiver).
        kinematics: the head, whose joint limits stop a move.
        max_steps: the step limit.
        evaluate: the internal evaluator: the index of the detection at the image centre,
            or None (Eq. 3, :func:`~jointattention.agent.attention.attended_object`).
    """

    def __init__(self, scene: Scene, theta_start_rad, *, kinematics: HeadKinematics,
                 max_steps: int, evaluate: Callable[[Detections], int | None]):
        self.scene, self.kinematics = scene, kinematics
        self.max_steps, self.evaluate = max_steps, evaluate
        self.target = scene.target_index
        self.theta_rad = np.asarray(theta_start_rad, dtype=float)
        self.n_steps, self.end, self.attended = 0, None, -1
        self.limit_hit = False  # whether the last move was stopped by a joint limit
        self._limits_rad = (*map(float, kinematics.pan_limits_rad),
                            *map(float, kinematics.tilt_limits_rad))
        self._look()

    def _look(self) -> None:
        self.detections = self.scene.observe(self.theta_rad)
        self.seen = self.evaluate(self.detections)  # index in the detections, or None
        end = end_after_look(-1 if self.seen is None else self.seen, self.limit_hit,
                             self.n_steps, self.max_steps)
        if end == END_FIRED:
            self.attended = int(self.scene.visible_ids[self.seen])
        self.end = None if end == RUNNING else end

    def step(self, dtheta_rad) -> None:
        """Move the head by ``dtheta_rad`` (stopping at the joint limits), look, evaluate."""
        if self.end is not None:
            raise RuntimeError("the trial has ended; expected a new trial")
        pan, tilt, self.limit_hit = move_head(
            float(self.theta_rad[0]), float(self.theta_rad[1]), float(dtheta_rad[0]),
            float(dtheta_rad[1]), *self._limits_rad)
        self.theta_rad = np.array([pan, tilt])
        self.n_steps += 1
        self._look()

    @property
    def outcome(self) -> Outcome:
        """How the trial ended, as the robot knows it."""
        fired = self.end == END_FIRED
        error = None
        pos = self.scene.object_pos_m
        if fired and self.attended >= 0:
            error = separation_rad(pos[self.attended], pos[self.target])
        return Outcome(fired, self.theta_rad, self.detections, self.seen,
                       approved=fired and self.attended == self.target,
                       caregiver_error_rad=error)


# Called at each look of a trial with the trial and the module that moves the head next
# (None at the last look).
StepObserver = Callable[[Trial, "str | None"], None]


def run_trial(trial: Trial, agent: Agent, face_window: np.ndarray,
              observer: StepObserver | None = None) -> TrialResult:
    """Run ``trial`` with ``agent`` to its end and let the agent learn from it.

    ``observer``, if given, is called at each look with the trial and the module that moves
    the head next (None at the last look).
    """
    start = agent.learning_time_steps
    agent.begin_trial(face_window, trial.theta_rad)
    n_lm = n_random = 0
    while trial.end is None:
        dtheta, module = agent.act(trial.detections, trial.theta_rad)
        if observer is not None:
            observer(trial, module)
        n_lm += module == LM
        n_random += module == RANDOM
        trial.step(dtheta)
    if observer is not None:
        observer(trial, None)
    agent.end_trial(trial.outcome)
    return TrialResult(start, trial.n_steps, n_lm, n_random, trial.attended, trial.target,
                       trial.end, trial.theta_rad)
