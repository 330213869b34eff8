"""The bootstrap agent with the episodic learning module (``learner = "memory"``).

Visual attention, the evaluator, the gate and the readings are the paper's
(:class:`~.bootstrap.BootstrapAgent`); the learning module is an
:class:`~.memory.EpisodicMemory`. At the start of a trial it recalls, from the caregiver's face,
the place to look at; its command is one step from the head angle toward that place. A trial
the evaluator ends is kept as (face code, place): the place is the attended object's
(``object_direction``: the final head angle plus the visual controller's command that centres
it) or the final head angle (``final_direction``); with ``memory.keep = "in_view"`` (the
default) every other object in the last image is kept too, at its place.
"""

from __future__ import annotations

import numpy as np

from .._arrays import angles, windows
from .bootstrap import BootstrapAgent, BootstrapOptions
from .memory import EpisodicMemory
from .moves import random_step, unit_step
from .protocol import Body, Outcome

__all__ = ["MemoryAgent"]


class MemoryAgent(BootstrapAgent):
    """The bootstrap agent whose learning module is an episodic memory.

    Args are :class:`~.bootstrap.BootstrapAgent`'s; ``rng`` is split once more, after the
    bootstrap agent's streams, for the face code's projection.

    Attributes:
        memory: the learning module.
        support_: the support of the place recalled for the current trial's face (-1 before
            anything is kept).
    """

    def __init__(self, options: BootstrapOptions, agent, body: Body, rng: np.random.Generator):
        super().__init__(options, agent, body, rng)
        (code_rng,) = rng.spawn(1)
        self.memory = EpisodicMemory(body.face_size_px[0] * body.face_size_px[1],
                                     options.memory, body.joint_limits_rad, code_rng)
        self.support_ = -1.0

    def _command(self, aim_rad, theta_rad) -> np.ndarray:
        """One step toward the recalled place; no step without one."""
        if aim_rad is None:
            return np.zeros(2)
        return np.array(unit_step(aim_rad[0] - theta_rad[0], aim_rad[1] - theta_rad[1],
                                  self.step_rad))

    def lm_command(self, face_window: np.ndarray, theta_rad) -> np.ndarray:
        """The module's command for a face window and head angle (zero with no memory)."""
        face = windows("face_window", face_window, self.body.face_size_px)
        aim, _ = self.memory.recall(self.memory.code(face))
        return self._command(aim, angles("theta_rad", theta_rad))

    def lm_commands(self, face_windows: np.ndarray, thetas_rad: np.ndarray) -> np.ndarray:
        """:meth:`lm_command` for K face windows (K, H, W) and head angles (K, 2), (K, 2)."""
        faces = windows("face_windows", face_windows, self.body.face_size_px, None)
        thetas = angles("thetas_rad", thetas_rad, len(faces))
        return np.array([self.lm_command(f, t) for f, t in zip(faces, thetas, strict=True)]
                        ).reshape(-1, 2)

    def begin_trial(self, face_window: np.ndarray, theta_rad) -> None:
        """Recall the place for the caregiver's face, then start the trial as the paper does."""
        self._code = self.memory.code(windows("face_window", face_window,
                                              self.body.face_size_px))
        self._aim_rad, self.support_ = self.memory.recall(self._code)
        super().begin_trial(face_window, theta_rad)

    def _lm(self, face_part, theta_rad) -> np.ndarray:
        """A step toward the recalled place; a random step while nothing is kept."""
        if self._aim_rad is None:
            return np.array(random_step(self.move_rng, self.step_rad))
        return self._command(self._aim_rad, theta_rad)

    def _lm_direction(self, theta_rad) -> np.ndarray:
        """A step toward the recalled place; no step while nothing is kept."""
        return self._command(self._aim_rad, theta_rad)

    def end_trial(self, outcome: Outcome) -> int:
        """Keep the trial if the evaluator fired; returns the number of places kept.

        With ``memory.keep = "in_view"`` the places of the other objects in the last image are
        kept too, after the attended one's.
        """
        if not self._learns(outcome):
            return 0
        self._measure(outcome)
        self.memory.store(self._code, self._aim(outcome))
        if self.options.memory.keep == "attended":
            return 1
        others = [i for i in range(len(outcome.detections)) if i != outcome.seen]
        for i in others:
            self.memory.store(self._code, self._place_of(outcome, i))
        return 1 + len(others)
