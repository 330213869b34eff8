"""The oracle gaze-line follower: the ceiling every learning curve is judged against.

It knows the caregiver's true target direction (world knowledge, so it lives outside
``agent/``), steps along it like the learning module does, and stops at the first object that
enters the evaluator's circle. A distractor lying nearer along the gaze line defeats it too.
"""

from __future__ import annotations

import numpy as np

from .agent.attention import attended_object

__all__ = ["OracleAgent"]


class OracleAgent:
    """Follows the true direction to the target, ``step_rad`` per step."""

    def __init__(self, theta_target_rad, step_rad: float, d_th_px: float):
        self.theta_target = np.asarray(theta_target_rad, dtype=float)
        self.step_rad, self.d_th_px = step_rad, d_th_px

    def begin_trial(self, face_window, theta_rad) -> None:
        pass

    def evaluate(self, det):
        return attended_object(det, self.d_th_px)

    def act(self, det, theta_rad):
        diff = self.theta_target - np.asarray(theta_rad)
        dist = float(np.hypot(*diff))
        return diff * min(1.0, self.step_rad / max(dist, 1e-12)), "lm"

    def end_trial(self, fired, theta_end_rad) -> int:
        return 0
