"""Wrappers of ``JointAttention-v1``."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from ..errors import ConfigError

__all__ = ["FaceWindowObservation"]


class FaceWindowObservation(gym.ObservationWrapper, gym.utils.RecordConstructorArgs):
    """Adds ``"face"`` to the ``"image"`` mode: the caregiver's face window, kept for the episode.

    Grayscale uint8, 25 x 30 by default, taken from the first image of the episode, when the robot
    looks at the caregiver, and kept as the robot keeps it in the paper's model. (The ``"face"``
    and ``"detections"`` modes have it already.)
    """

    def __init__(self, env: gym.Env):
        if "image" not in env.observation_space.spaces:
            raise ConfigError("FaceWindowObservation: cuts the face from obs_mode='image'; the "
                              "other observation modes have \"face\" already")
        gym.utils.RecordConstructorArgs.__init__(self)
        super().__init__(env)
        fw = env.unwrapped.config.world.face_window
        self.observation_space = spaces.Dict({
            **env.observation_space.spaces,
            "face": spaces.Box(0, 255, (fw.height_px, fw.width_px), np.uint8),
        })
        self._face: np.ndarray | None = None

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        """Reset the environment and cut the face window from its first image."""
        obs, info = self.env.reset(seed=seed, options=options)
        self._face = self.env.unwrapped.face_window(obs["image"])
        return self.observation(obs), info

    def observation(self, observation):
        """The observation with the episode's face window."""
        return {**observation, "face": self._face.copy()}
