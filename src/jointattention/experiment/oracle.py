"""The oracle gaze-line follower: the ceiling every learning curve is judged against.

It knows the caregiver's true target direction (world knowledge, so it lives outside
``agent/``), steps along it like the learning module does, and stops at the first object that
enters the evaluator's circle. A distractor lying nearer along the gaze line defeats it too.
"""

from __future__ import annotations

import numpy as np

from ..agent.protocol import LM, Outcome

__all__ = ["OracleAgent"]


class OracleAgent:
    """Follows the true direction to the target, ``step_rad`` per step (an Agent)."""

    def __init__(self, theta_target_rad, step_rad: float):
        self.theta_target = np.asarray(theta_target_rad, dtype=float)
        self.step_rad = step_rad
        self.learning_time_steps = 0

    def begin_trial(self, face_window, theta_rad) -> None:
        """Nothing to prepare."""

    def act(self, det, theta_rad):
        """One step along the line to the target (shorter at the end)."""
        diff = self.theta_target - np.asarray(theta_rad)
        dist = float(np.hypot(*diff))
        self.learning_time_steps += 1
        return diff * min(1.0, self.step_rad / max(dist, 1e-12)), LM

    def end_trial(self, outcome: Outcome) -> None:
        """Nothing to learn."""
