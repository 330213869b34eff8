"""Running an agent of the trial loop through the environment: :class:`EnvTrial`."""

from __future__ import annotations

import gymnasium as gym
import numpy as np

from ..agent.detections import Detections
from ..agent.protocol import Outcome
from ..experiment.trial import END_FIRED, END_LIMIT, END_STEPS
from ._observation import detections_of

__all__ = ["EnvTrial"]


class EnvTrial:
    """One episode of a ``JointAttention-v1`` environment (any observation mode) as a trial.

    So that :func:`~jointattention.experiment.trial.run_trial` drives an
    :class:`~jointattention.agent.protocol.Agent` through it.

    The agent gets what the environment gives: the head angle from the observation and the
    detections from ``info``; each step is ``env.step``. ``attended`` and ``target`` come from
    ``info`` (the experimenter's knowledge, for the trial's record only).

    Args:
        env: the environment (wrapped or not).
        seed: the seed of its reset (None: continue its random stream).

    Attributes:
        observation, info: the last ones the environment returned; ``reward`` the last
            reward (0 before the first step).
    """

    def __init__(self, env: gym.Env, seed: int | None = None):
        self.env = env
        self.observation, self.info = env.reset(seed=seed)
        self.reward, self.n_steps, self.end = 0.0, 0, None
        kin = env.unwrapped.kinematics
        self._image_size_px = (kin.width_px, kin.height_px)

    @property
    def theta_rad(self) -> np.ndarray:
        """The head angle of the last observation."""
        return self.observation["head_angle"].astype(float)

    @property
    def detections(self) -> Detections:
        """The detector's report in the last ``info``."""
        return detections_of(self.info, self._image_size_px)

    @property
    def attended(self) -> int:
        """The object the evaluator fired on, -1 if none (from ``info``)."""
        return int(self.info["attended"])

    @property
    def target(self) -> int:
        """The caregiver's target (from ``info``)."""
        return int(self.info["target"])

    def step(self, dtheta_rad) -> None:
        """``env.step(dtheta_rad)``, scaled if its actions are normalised.

        The episode's end decides the trial's.
        """
        env = self.env.unwrapped
        action = np.asarray(dtheta_rad, dtype=float)
        if env.normalize_actions:
            action = action / env.max_step_rad
        self.observation, self.reward, terminated, truncated, self.info = self.env.step(
            action.astype(np.float32))
        self.n_steps += 1
        if self.info["fired"]:
            self.end = END_FIRED
        elif terminated:
            self.end = END_LIMIT
        elif truncated:
            self.end = END_STEPS

    @property
    def outcome(self) -> Outcome:
        """How the episode ended, as the robot knows it."""
        seen, error = int(self.info["seen"]), float(self.info["caregiver_error_rad"])
        return Outcome(bool(self.info["fired"]), self.theta_rad, self.detections,
                       None if seen < 0 else seen,
                       approved=bool(self.info["external_reward"]),  # fired on her target
                       caregiver_error_rad=error if error >= 0 else None)
