"""A model from outside the package that runs in the compiled engine: the compass.

The compass is the bootstrap agent (visual attention, the gate, Eq. 3's evaluator: the
paper's) with a learning module of its own. It keeps one direction for every face: the running
mean of the directions, from the caregiver's face, of the places its trials found. Its command
steps along that direction. A poor learner of joint attention (it ignores the face), but a
whole one, written here and nowhere else:

1. its state, a named tuple of numbers and arrays (:class:`CompassState`);
2. its part of a trial as four compiled kernels over that state (``begin``, ``command``,
   ``direction``, ``learn``: :class:`jointattention.ModuleKernels` gives their signatures);
3. the learning module, whose step-by-step methods call the same kernels
   (:class:`CompassModule`), and which declares them (``kernels``, ``compiled_state``,
   ``learn_rng``, ``sync``);
4. its options, registered as a model kind that declares ``compiled = True``
   (:class:`CompassOptions`).

The compiled engine compiles its loop once for these kernels (cached: a second run loads it),
so the compass runs as fast as the package's own learners. ``check_agent`` checks, among the
rest, that its compiled cell equals its step-by-step cell byte for byte.

Run: ``python examples/new_model.py`` (about a minute, most of it compiling the loop the first
time).
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass
from typing import ClassVar, NamedTuple

import numpy as np
from numba import njit

from jointattention import (
    MODELS,
    BootstrapAgent,
    BootstrapOptions,
    ConditionConfig,
    Config,
    ModuleKernels,
    param,
)
from jointattention.experiment.cells import engine_of, run_cell
from jointattention.testing import check_agent


class CompassState(NamedTuple):
    """The compass's options and arrays, as its kernels take them (its own, changed in place)."""

    rate: float  # how far one place moves the direction kept
    mean: np.ndarray  # (2,): the running mean of the unit directions taught
    trial: np.ndarray  # (3,): this trial's direction, and the head angle at its start
    counters: np.ndarray  # (1,): places learned


@njit
def compass_begin(s, face, face_id, pan, tilt, learning):
    """The trial starts at the face: its direction is the mean's. No evidence: 0.0."""
    s.trial[0] = math.atan2(s.mean[1], s.mean[0])
    s.trial[1], s.trial[2] = pan, tilt
    return 0.0


@njit
def compass_direction(s, pan, tilt, step_rad):
    """One step in the trial's direction (it draws nothing)."""
    return step_rad * math.cos(s.trial[0]), step_rad * math.sin(s.trial[0])


@njit
def compass_command(s, pan, tilt, step_rad, rng):
    """The module's step: :func:`compass_direction`, from any head angle."""
    return compass_direction(s, pan, tilt, step_rad)


@njit
def compass_learn(s, place, centre, seen, pan, tilt, cx, cy, gain_rad_per_px, face, thetas,
                  steps, rng):
    """The mean moves toward the unit direction, from the trial's start, of the place found."""
    d_pan, d_tilt = place[0] - s.trial[1], place[1] - s.trial[2]
    norm = math.hypot(d_pan, d_tilt)
    if norm > 0.0:
        s.mean[0] += s.rate * (d_pan / norm - s.mean[0])
        s.mean[1] += s.rate * (d_tilt / norm - s.mean[1])
    s.counters[0] += 1
    return 1


class CompassModule:
    """The compass as the bootstrap agent's learning module (the calls every module answers)."""

    kernels = ModuleKernels(compass_begin, compass_command, compass_direction, compass_learn)

    def __init__(self, host: BootstrapAgent, rate: float):
        self.host, self.rate = host, float(rate)
        self.mean_, self._trial, self.n_learned_ = np.zeros(2), np.zeros(3), 0

    @property
    def learn_rng(self) -> np.random.Generator:
        """The stream its ``learn`` kernel is handed (it draws nothing): the agent's moves."""
        return self.host.move_rng

    def compiled_state(self, n_faces: int = 0) -> CompassState:
        """Its state as its kernels take it (its own arrays; it keeps nothing per face)."""
        return CompassState(self.rate, self.mean_, self._trial, np.array([self.n_learned_]))

    def sync(self, state: CompassState) -> None:
        """Take back what the kernels counted."""
        self.n_learned_ = int(state.counters[0])

    def begin(self, face, theta_rad) -> None:
        """A trial starts at the caregiver's face (a flat view), at head angle ``theta_rad``."""
        compass_begin(self.compiled_state(), face, -1, float(theta_rad[0]),
                      float(theta_rad[1]), self.host.learning)

    def observe(self, det, theta_rad) -> None:
        """Nothing: the compass makes nothing of a step's view."""

    def step(self, theta_rad) -> np.ndarray:
        """Its step at a head angle."""
        return np.array(compass_command(self.compiled_state(), float(theta_rad[0]),
                                        float(theta_rad[1]), self.host.step_rad,
                                        self.host.move_rng))

    def direction(self, theta_rad) -> np.ndarray:
        """The step it would take (the performance gate's measure)."""
        return np.array(compass_direction(self.compiled_state(), float(theta_rad[0]),
                                          float(theta_rad[1]), self.host.step_rad))

    def learn(self, outcome, thetas, steps) -> int:
        """Learn the place the trial found (``host.trial_end``); returns how many places."""
        state = self.compiled_state()
        n = compass_learn(state, *self.host.trial_end(outcome), thetas, steps, self.learn_rng)
        self.sync(state)
        return n

    def command(self, face, theta_rad) -> np.ndarray:
        """The first step from a face at a head angle."""
        return self.commands(np.reshape(face, (1, -1)), np.reshape(theta_rad, (1, 2)))[0]

    def commands(self, faces, thetas) -> np.ndarray:
        """:meth:`command` of K faces and head angles, (K, 2): the same step for every face."""
        psi, step = math.atan2(self.mean_[1], self.mean_[0]), self.host.step_rad
        return np.tile([step * math.cos(psi), step * math.sin(psi)], (len(faces), 1))

    def saved_arrays(self) -> dict:
        """No members of its own in a model file (it keeps none: ``save_refusal``)."""
        return {}

    def saved_shapes(self) -> dict:
        """No members, no shapes."""
        return {}

    def load_arrays(self, arrays) -> None:
        """Nothing to load."""


@dataclass(frozen=True)
class CompassOptions(BootstrapOptions):
    """The bootstrap model with the compass as its learning module."""

    compiled: ClassVar[bool] = True  # its learning module declares its kernels
    rate: float = param(0.05, "how far one place found moves the compass's direction",
                        lo=0.0, hi=1.0)

    def save_refusal(self) -> str | None:
        """An example: the compass keeps no model file."""
        return "the compass (an example) keeps no model file"

    def build(self, mechanisms, body, rng) -> BootstrapAgent:
        """The bootstrap agent, its learning module the compass."""
        agent = BootstrapAgent(self, mechanisms, body, rng)
        agent.module = CompassModule(agent, self.rate)
        return agent


def main() -> None:
    """Register the compass, check it, and run a cell of it in the compiled engine."""
    if "compass" not in MODELS:
        MODELS.register("compass", CompassOptions)
    check_agent(CompassOptions())
    print("check_agent: the compass passes (its compiled cell equals its step-by-step cell)")
    base = Config()
    experiment = dataclasses.replace(
        base.experiment, n_steps=20_000, n_seeds=1, bin_steps=10_000, engine="compiled",
        conditions=(ConditionConfig(name="compass", n_objects=5),))
    config = dataclasses.replace(base, model=CompassOptions(), experiment=experiment)
    condition = experiment.conditions[0]
    start = time.perf_counter()
    records = run_cell(config, condition, 0)
    seconds = time.perf_counter() - start
    print(f"ran compiled (engine {engine_of(config, condition)!r}): "
          f"{len(records['success'])} trials, {config.experiment.n_steps} steps in "
          f"{seconds:.1f} s, success {np.mean(records['success']):.2f}")


if __name__ == "__main__":
    main()
