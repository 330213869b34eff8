"""A reinforcement-learning model of gaze following: the basic set of Triesch et al.

After Triesch, Teuscher, Deák and Carlson (2006), "Gaze following: why (not) learn it?",
Developmental Science 9(2), 125-147. Their *basic set*: a preference for looking at
interesting things (reward), habituation (what is looked at grows less rewarding) and
temporal-difference learning of where to look given the caregiver's head pose. Gaze following
emerges because the caregiver looks at objects; nobody tells the robot where she looks: the
reward is what it finds rewarding in looking, never her judgement (it does not read
:attr:`~.protocol.Outcome.approved`).

Our reading for this trial loop (the paper has discrete places and continuous time; the parts
marked *reading* are ours):

- **Decisions.** A trial starts looking at the caregiver. At each step while it still looks at
  her, the robot keeps looking (``"stay"``, no move) or shifts its gaze in one of
  ``n_directions`` directions (*reading*: the paper's discrete places become directions in the
  (pan, tilt) plane); once shifted it moves along that direction, one ``[agent] lm_step_deg``
  step per step (module :data:`~.protocol.LM`), until the trial loop ends the trial. Choices
  are a softmax of the action values with ``temperature``.
- **Reward.** Looking at her pays ``face_reward`` at the first step, times
  ``face_habituation ** k`` after k steps of looking in the trial; the end pays
  ``object_reward`` if the evaluator fired on an object, times 1 - h, the robot's habituation
  to the place where it found the object.
- **Habituation to places** (*reading*: the robot does not tell objects apart, so a place stands
  for the object): a grid of ``place_cell_deg`` cells over the joint ranges; every cell recovers
  once per trial (``h *= place_recovery``), then the cell where the evaluator fired rises
  (``h += place_habituation * (1 - h)``).
- **Values and TD learning** (SARSA over the decisions, learnt at the trial's end):
  ``Q(stay | k) = q_stay_[k]``, ``Q(shift d | face) = W_[d] . x + b_[d]`` with x the
  standardised face window. A shift is one decision lasting to the end; its return is
  ``gamma ** (n_moves - 1)`` times the end reward (*reading*). Each stay is moved toward
  ``r_k + gamma * Q(next decision)`` (next value 0 when the step limit ends the trial while it
  stays); the shift's weights by normalised LMS.

There is no gate and no visual controller: steps spent looking at her are module ``"stay"``
(neither :data:`~.protocol.LM` nor random in the trial records). Its arithmetic is compiled
(:mod:`._kernels`), and so is its whole part of a trial (:mod:`._trial`, a
:class:`~jointattention.agent.protocol.TrialKernels`): the agent's methods call those kernels,
and the compiled engine runs them too (:mod:`jointattention.experiment.compiled.rl_cell`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..._arrays import angles, windows
from ..._fields import param
from ...agent.detections import Detections
from ...agent.face_standardiser import NO_FACE_SEEN, FaceStandardiser
from ...agent.options import AgentConfig
from ...agent.protocol import LM, Body, Outcome
from ...errors import ArgumentError, ConfigError
from ..registry import ModelOptions
from . import _kernels as equations
from ._trial import KERNELS, SHIFT, RLArrays

__all__ = ["STAY", "RLAgent", "RLOptions"]

STAY = "stay"  # the module name of a step spent looking at the caregiver


@dataclass(frozen=True)
class RLOptions(ModelOptions):
    """The reinforcement-learning model's options (Triesch et al. 2006, our reading)."""

    compiled: ClassVar[bool] = True

    readings: ClassVar[tuple[str, ...]] = ("n_directions", "place_cell_deg")

    n_directions: int = param(
        24, "reading: the directions a gaze shift can take (evenly spaced in the (pan, tilt) "
        "plane)", lo=2, hi=360)
    temperature: float = param(
        0.05, "softmax temperature of the choices, in reward units", lo=1e-4, hi=100)
    face_reward: float = param(
        0.3, "reward of the first step looking at the caregiver", lo=0, hi=10)
    face_habituation: float = param(
        0.5, "factor by which each further step looking at her pays less", lo=0, hi=1)
    object_reward: float = param(
        1.0, "reward of a trial whose evaluator fired on an object (at an unhabituated place)",
        lo=0, hi=10)
    place_cell_deg: float = param(
        8.0, "reading: side of the grid cells over the joint ranges that habituate",
        lo=0.1, hi=360)
    place_habituation: float = param(
        0.3, "fraction of the way to full habituation a place goes when an object is found "
        "there", lo=0, hi=1)
    place_recovery: float = param(
        0.9, "factor by which every place's habituation falls once per trial", lo=0, hi=1)
    gamma: float = param(0.95, "discount per step of the TD returns", lo=0, hi=1)
    # not "learning_rate": a condition that changes the model's kind keeps the fields the two
    # kinds share, and would carry over the bootstrap model's 0.0003
    learning_rate_shift: float = param(
        0.5, "step size of the shift values' normalised LMS update", lo=0, hi=2)
    learning_rate_stay: float = param(
        0.1, "step size of the stay values' TD update", lo=0, hi=1)

    def build(self, mechanisms: AgentConfig, body: Body, rng: np.random.Generator) -> RLAgent:
        """The untrained RL agent."""
        return RLAgent(self, mechanisms, body, rng)


def _readonly(a: np.ndarray) -> np.ndarray:
    a.flags.writeable = False
    return a


class RLAgent:
    """The robot's side of the RL model: choices, rewards, habituation and SARSA.

    Args:
        options: the model's options.
        mechanisms: the robot's shared mechanisms, the ``[agent]`` section (step length,
            step limit).
        body: joint ranges (for the places) and face window size.
        rng: the agent's own generator, split into one stream per purpose (the choices).

    Learned state: ``W_`` (n_directions, pixels) and ``b_`` (n_directions,), the shift values;
    ``q_stay_`` (max_steps + 1,), the stay values; ``place_habituation_`` (pan cells, tilt
    cells). ``learning``: whether it learns (True); frozen (False), it acts on what it
    learned and changes none of it (nor its learning time).

    Its trial is compiled kernels (:attr:`kernels`, over :meth:`compiled_state`; see
    :class:`~jointattention.agent.protocol.TrialKernels`), which its methods call; ``act``
    draws from :attr:`act_rng`.
    """

    kernels = KERNELS  # its part of a trial, for the compiled engine

    def __init__(self, options: RLOptions, mechanisms: AgentConfig, body: Body,
                 rng: np.random.Generator):
        if body.eye_size_px is not None:
            raise ConfigError("the RL model reads the face window only; expected a world "
                              "without an eye window ([world.eye_window] 0 x 0)")
        self.options, self.mechanisms, self.body = options, mechanisms, body
        (self.choice_rng,) = rng.spawn(1)
        n_pix = body.face_size_px[0] * body.face_size_px[1]
        self.W_ = np.zeros((options.n_directions, n_pix))
        self.b_ = np.zeros(options.n_directions)
        self.q_stay_ = np.zeros(mechanisms.max_steps + 1)
        self.limits_rad = np.asarray(body.joint_limits_rad, dtype=float)
        self.lo_rad = np.ascontiguousarray(self.limits_rad[:, 0])  # the habituation grid's origin
        self.cell_rad = math.radians(options.place_cell_deg)
        n_cells = np.ceil((self.limits_rad[:, 1] - self.limits_rad[:, 0]) / self.cell_rad)
        self.place_habituation_ = np.zeros(tuple(int(max(n, 1)) for n in n_cells))
        self.faces = FaceStandardiser()
        self.learning_time_steps = 0
        self.learning = True
        angles = 2 * np.pi * np.arange(options.n_directions) / options.n_directions
        self.steps_rad = _readonly(math.radians(mechanisms.lm_step_deg)
                                   * np.column_stack([np.cos(angles), np.sin(angles)]))
        self._zero = _readonly(np.zeros(2))
        # a trial's scratch (RLArrays): the face standardised, its values, the choice odds,
        # and the decisions so far (stays, the shift's direction, its moves)
        self._x, self._q = np.zeros(n_pix), self.b_.copy()
        self._cdf, self._p_stay = np.empty(options.n_directions), np.empty(len(self.q_stay_))
        self._trial = np.array([0, -1, 0], dtype=np.int64)
        self._state: RLArrays | None = None  # the trial's (begin_trial makes it)

    @property
    def act_rng(self) -> np.random.Generator:
        """The stream :meth:`act` draws its choices from."""
        return self.choice_rng

    def compiled_state(self, n_pixels: int) -> RLArrays:
        """Its options and its own arrays (changed in place) as the kernels take them.

        ``n_pixels``: a face window's (the face statistics are sized by it before any face).
        """
        o = self.options
        return RLArrays(
            self.steps_rad, float(self.faces.min_std), float(o.temperature),
            float(o.face_reward), float(o.face_habituation), float(o.object_reward),
            float(o.place_habituation), float(o.place_recovery), float(o.gamma),
            float(o.learning_rate_shift), float(o.learning_rate_stay), self.lo_rad,
            float(self.cell_rad), self.W_, self.b_, self.q_stay_, self.place_habituation_,
            *self.faces.statistics(n_pixels), self.faces.seen, self._x, self._q, self._cdf,
            self._p_stay, self._trial)

    # -- values ----------------------------------------------------------------------------
    def _standardised(self, faces: np.ndarray) -> np.ndarray:
        faces = np.asarray(faces, dtype=float).reshape(len(faces), -1)
        return self.faces.transform(faces) if self.faces.n_seen_ else np.zeros_like(faces)

    def shift_values(self, face_windows: np.ndarray) -> np.ndarray:
        """``Q(shift d | face)`` for K face windows (K, H, W): (K, n_directions)."""
        return self._standardised(face_windows) @ self.W_.T + self.b_

    def lm_commands(self, face_windows: np.ndarray, thetas_rad: np.ndarray) -> np.ndarray:
        """One step along the greedy shift direction for each face window (K, H, W): (K, 2).

        The head angles are not used: the shift values depend on the face alone.
        """
        faces = windows("face_windows", face_windows, self.body.face_size_px, None)
        angles("thetas_rad", thetas_rad, len(faces))
        return self.steps_rad[np.argmax(self.shift_values(faces), axis=1)].copy()

    def lm_command(self, face_window: np.ndarray, theta_rad) -> np.ndarray:
        """:meth:`lm_commands` for one face window: (2,)."""
        face = windows("face_window", face_window, self.body.face_size_px)
        return self.lm_commands(face[None], angles("theta_rad", theta_rad)[None])[0]

    def place_of(self, theta_rad) -> tuple[int, ...]:
        """The habituation grid's cell of a head angle (clipped to the grid)."""
        theta = angles("theta_rad", theta_rad)
        return equations.rl_cell(float(theta[0]), float(theta[1]), self.lo_rad, self.cell_rad,
                                 self.place_habituation_.shape)

    # -- rewards (the basic set's preference for interesting things, habituated) ------------
    def stay_reward(self, k: int) -> float:
        """What looking at the caregiver pays after ``k`` steps of looking in the trial."""
        o = self.options
        return equations.stay_reward(float(o.face_reward), float(o.face_habituation), int(k))

    def object_reward_at(self, theta_rad) -> float:
        """What finding an object pays with the head at ``theta_rad``, habituated to its place."""
        return equations.object_reward(float(self.options.object_reward),
                                       float(self.place_habituation_[self.place_of(theta_rad)]))

    # -- a trial: the kernels of models/rl/_trial.py ---------------------------------------
    def begin_trial(self, face_window: np.ndarray, theta_rad) -> None:
        """Start a trial looking at the caregiver: her face's shift values and the choice odds.

        Learning, the face statistics take in her face first (:func:`~._trial.rl_begin`).
        """
        face = windows("face_window", face_window, self.body.face_size_px).ravel()
        self._state = self.compiled_state(len(face))
        if not self.kernels.begin(self._state, np.ascontiguousarray(face, dtype=float),
                                  self.learning):
            raise ArgumentError(NO_FACE_SEEN)

    def act(self, detections: Detections, theta_rad) -> tuple[np.ndarray, str]:
        """One step: stay, shift (a softmax draw) or keep moving along the shift."""
        if self.learning:
            self.learning_time_steps += 1
        theta = np.asarray(theta_rad, dtype=float)
        *_, moves = self.kernels.act(self._state, float(theta[0]), float(theta[1]),
                                     self.act_rng)
        if not moves:
            return self._zero, STAY
        return self.steps_rad[self._trial[SHIFT]], LM

    def end_trial(self, outcome: Outcome) -> None:
        """Reward, habituate, and learn by SARSA from the trial's decisions.

        Reads only ``fired`` and the head angle at the end, never the caregiver's judgement
        (:func:`~._trial.rl_end`).
        """
        if not self.learning:
            return
        theta = angles("theta_rad", outcome.theta_rad)
        self.kernels.learn(self._state, bool(outcome.fired), float(theta[0]), float(theta[1]))
