"""The oracle gaze-line follower: the ceiling every learning curve is judged against.

It knows the caregiver's true target direction (world knowledge, so it lives outside
``agent/``), steps along it like the learning module does, and stops at the first object that
enters the evaluator's circle. A distractor lying nearer along the gaze line defeats it too.
With the robot's ``line_capture_deg``, it moves as the learning module then does: to the first
object in view ahead along the line and that near it, in one move.
"""

from __future__ import annotations

import numpy as np

from .._jit import jit
from ..agent.attention import visual_feedback_rad
from ..agent.moves import capped_step, line_capture
from ..agent.protocol import LM, Outcome
from .compiled.steps import draw_trial, look, look_arrays, look_camera
from .trial import RUNNING, move_head

__all__ = ["OracleAgent", "oracle_step", "oracle_trials"]


class OracleAgent:
    """Follows the true direction to the target, ``step_rad`` per step (an Agent).

    With ``capture_rad`` > 0 (the robot's ``line_capture_deg``) it moves to the first object
    in view along that line instead, by Eq. 2 with ``gain_rad_per_px``.
    """

    def __init__(self, theta_target_rad, step_rad: float, capture_rad: float = 0.0,
                 gain_rad_per_px: float = 0.0):
        self.theta_target = np.asarray(theta_target_rad, dtype=float)
        self.step_rad, self.capture_rad, self.gain_rad_per_px = (step_rad, capture_rad,
                                                                 gain_rad_per_px)
        self.learning_time_steps = 0

    def begin_trial(self, face_window, theta_rad) -> None:
        """Keep where the trial starts: the line runs from there."""
        self._start = np.asarray(theta_rad, dtype=float).copy()

    def act(self, det, theta_rad):
        """One step along the line to the target (shorter at the end), or the capture."""
        self.learning_time_steps += 1
        (cx, cy), start = det.image_centre_px, self._start
        return np.array(oracle_step(
            self.theta_target[0], self.theta_target[1], float(theta_rad[0]),
            float(theta_rad[1]), float(self.step_rad), float(start[0]), float(start[1]),
            np.ascontiguousarray(det.centre_px, dtype=float).reshape(-1, 2), float(cx),
            float(cy), float(self.gain_rad_per_px), float(self.capture_rad))), LM

    def end_trial(self, outcome: Outcome) -> None:
        """Nothing to learn."""


@jit
def oracle_step(target_pan, target_tilt, pan, tilt, step_rad, start_pan, start_tilt, centre_px,
                cx_px, cy_px, gain_rad_per_px, capture_rad) -> tuple[float, float]:
    """One step from the head angle along the line to the target's (shorter at the end).

    With ``capture_rad`` > 0, Eq. 2's move to the first object in view along the line from
    the start, if one lies that near it (:func:`~jointattention.agent.moves.line_capture`).
    """
    if capture_rad > 0:
        i = line_capture(centre_px, cx_px, cy_px, gain_rad_per_px, pan, tilt, start_pan,
                         start_tilt, target_pan - start_pan, target_tilt - start_tilt,
                         capture_rad)
        if i >= 0:
            return visual_feedback_rad(centre_px[i, 0], centre_px[i, 1], cx_px, cy_px,
                                       gain_rad_per_px)
    return capped_step(target_pan - pan, target_tilt - tilt, step_rad)


@jit
def oracle_trials(world, theta_target_rad, rng, step_rad, d_th_px, max_steps, n_trials,
                  capture_rad=0.0, gain_rad_per_px=0.0, any_object=False) -> int:
    """How many of ``n_trials`` trials the oracle ends on the target (-1: objects not placed).

    ``any_object``: count the trials it ends on any object instead (the evaluator fired: the
    intrinsic reward's ceiling).

    The compiled engine's trials (:mod:`.compiled._loop`: the same draws as
    :func:`~.cells.random_scene` and :class:`~.trial.SceneTrial`) with :class:`OracleAgent`'s
    step toward ``theta_target_rad`` (K, 2), the target's head angle of each data set.
    """
    n = world.n_objects
    obj_pos, obj_rad, edge = np.empty((n, 3)), np.empty(n), np.empty(n)
    arrays, lim, wins = look_arrays(n), world.limits_rad, 0
    camera = look_camera(world, d_th_px)
    cx, cy, centre = (world.width_px - 1) / 2, (world.height_px - 1) / 2, arrays[1]
    for _ in range(n_trials):
        k, target, _ = draw_trial(world, rng, rng, obj_pos, obj_rad, edge)
        if target < 0:
            return -1
        pan, tilt = world.theta_face_rad[k, 0], world.theta_face_rad[k, 1]
        n_steps, limit_hit = 0, False
        while True:
            m, _, end, attended = look(obj_pos, obj_rad, edge, pan, tilt, camera, limit_hit,
                                       n_steps, max_steps, arrays)
            if end != RUNNING:
                break
            d_pan, d_tilt = oracle_step(theta_target_rad[k, 0], theta_target_rad[k, 1], pan,
                                        tilt, step_rad, world.theta_face_rad[k, 0],
                                        world.theta_face_rad[k, 1], centre[:m], cx, cy,
                                        gain_rad_per_px, capture_rad)
            pan, tilt, limit_hit = move_head(pan, tilt, d_pan, d_tilt, lim[0], lim[1], lim[2],
                                             lim[3])
            n_steps += 1
        wins += (attended >= 0) if any_object else (attended == target)
    return wins
