"""The one loop over the steps of a trial (DESIGN.md, reading 1).

The robot starts looking at the caregiver's face. Each step the internal evaluator looks at
the image centre; if an object is there the trial ends ("fired"). Otherwise the agent moves
the head. A trial also ends at the step limit or when a move hits a joint limit.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["TrialResult", "run_trial"]

END_FIRED, END_STEPS, END_LIMIT = 0, 1, 2


@dataclass(frozen=True)
class TrialResult:
    """What happened in one trial (the experimenter's record)."""

    n_steps: int
    n_lm_steps: int
    attended: int  # object id the evaluator fired on, -1 if it did not fire
    target: int
    end: int  # END_FIRED, END_STEPS or END_LIMIT
    theta_end_rad: np.ndarray

    @property
    def fired(self) -> bool:
        return self.end == END_FIRED

    @property
    def success(self) -> bool:
        """Joint attention: the object finally attended is the caregiver's target."""
        return self.attended == self.target


def run_trial(scene, agent, face_window: np.ndarray, theta_face_rad, max_steps: int,
              kinematics) -> TrialResult:
    """Run one trial of ``agent`` in ``scene`` and let the agent learn from it.

    ``scene`` offers ``observe(theta) -> Detections``, ``visible_ids`` and ``target_index``;
    ``agent`` offers ``begin_trial``, ``evaluate``, ``act`` and ``end_trial``; ``kinematics``
    gives the joint limits (``clip``).
    """
    theta = np.asarray(theta_face_rad, dtype=float)
    agent.begin_trial(face_window, theta)
    n_lm, attended, end = 0, -1, END_STEPS
    for step in range(max_steps + 1):
        det = scene.observe(theta)
        seen = agent.evaluate(det)
        if seen is not None:
            attended, end = int(scene.visible_ids[seen]), END_FIRED
            break
        if step == max_steps or end == END_LIMIT:
            break
        dtheta, module = agent.act(det, theta)
        n_lm += module == "lm"
        wanted = theta + dtheta
        theta = kinematics.clip(wanted)
        if not np.array_equal(theta, wanted):
            end = END_LIMIT  # look once more at where the head stopped, then end
    agent.end_trial(end == END_FIRED, theta)
    return TrialResult(step, n_lm, attended, scene.target_index, end, theta)
