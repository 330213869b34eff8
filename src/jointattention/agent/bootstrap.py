"""The bootstrap learning agent: visual attention, self-evaluation, learning and the gate."""

from __future__ import annotations

import numpy as np

from ..config import AgentConfig
from .attention import attended_object, most_interesting, visual_feedback
from .detections import Detections
from .gate import constant_rate, sigmoid_rate
from .learner import FaceStandardiser, LearningModule

__all__ = ["BootstrapAgent"]

VF, LM, RANDOM = "vf", "lm", "random"


class BootstrapAgent:
    """The robot's side of the model (paper, Fig. 2).

    Args:
        config: the agent's parameters and the readings where the paper is silent.
        image_size_px: (W, H) of its camera image.
        joint_limits_rad: ((pan_lo, pan_hi), (tilt_lo, tilt_hi)), the robot's own joint ranges;
            it scales head angles by them for the learning module.
        face_size_px: (width, height) of the face window.
        rng: the agent's own generator (initial weights, gate draws, random steps).

    A trial is ``begin_trial``, then ``evaluate`` and ``act`` at each step, then
    ``end_trial``; learning happens in ``end_trial`` if the internal evaluator fired.
    """

    def __init__(self, config: AgentConfig, *, image_size_px: tuple[int, int],
                 joint_limits_rad, face_size_px: tuple[int, int], rng: np.random.Generator):
        self.config = config
        self.image_size_px = image_size_px
        limits = np.asarray(joint_limits_rad, dtype=float)
        self._theta_mid, self._theta_half = limits.mean(axis=1), np.ptp(limits, axis=1) / 2
        self.rng = rng
        n_in = face_size_px[0] * face_size_px[1] + 2
        self.learner = LearningModule(
            n_in, config.n_hidden, 2, learning_rate=config.learning_rate,
            momentum=config.momentum, init_scale=config.init_scale, rng=rng)
        self.faces = FaceStandardiser()
        self.learning_time_steps = 0
        self._trial_module: str | None = None
        self._thetas: list[np.ndarray] = []
        self._steps: list[np.ndarray] = []

    @property
    def step_rad(self) -> float:
        return np.deg2rad(self.config.lm_step_deg)

    @property
    def d_th_px(self) -> float:
        """Threshold of the internal evaluator (Eq. 3), d_th = W * fraction."""
        return self.config.d_th_px(self.image_size_px[0])

    def gate_rate(self, learning_time_steps=None):
        """Rate of choosing the learning module at a learning time (default: now)."""
        t = self.learning_time_steps if learning_time_steps is None else learning_time_steps
        c = self.config
        if c.gate == "constant":
            return constant_rate(t, c.gate_rate)
        return sigmoid_rate(t, c.gate_midpoint_steps, c.gate_width_steps)

    # -- the learning module ---------------------------------------------------------------
    def _inputs(self, face_x: np.ndarray, thetas: np.ndarray) -> np.ndarray:
        scaled = (np.atleast_2d(thetas) - self._theta_mid) / self._theta_half
        return np.hstack([np.broadcast_to(face_x, (len(scaled), len(face_x))), scaled])

    def lm_command(self, face_window: np.ndarray, theta_rad) -> np.ndarray:
        """LM dtheta for a face window and head angle: the network's direction, one step long."""
        face_x = self.faces.transform(np.asarray(face_window).ravel())
        return self._lm(face_x, theta_rad)

    def _lm(self, face_x: np.ndarray, theta_rad) -> np.ndarray:
        out = self.learner.predict(self._inputs(face_x, theta_rad))[0]
        return self.step_rad * out / max(float(np.hypot(*out)), 1e-12)

    # -- a trial ---------------------------------------------------------------------------
    def begin_trial(self, face_window: np.ndarray, theta_rad) -> None:
        """Start a trial looking at the caregiver, whose face window the robot keeps."""
        face = np.asarray(face_window, dtype=float).ravel()
        self.faces.partial_fit(face)
        self._face_x = self.faces.transform(face)
        self._thetas, self._steps = [], []
        self._trial_module = None
        self._centring_rad = np.zeros(2)
        if self.config.gate_per == "trial":
            self._trial_module = LM if self.rng.random() < self.gate_rate() else VF

    def evaluate(self, det: Detections) -> int | None:
        """The internal evaluator (Eq. 3): the detection at the image centre, if any.

        When it fires, the robot keeps the head angle change that would centre the attended
        object exactly (the visual controller's command for it, Eq. 2): the
        ``object_direction`` learning target aims at the object, not at where the head was
        when the object entered the circle.
        """
        i = attended_object(det, self.d_th_px)
        if i is not None:
            self._centring_rad = visual_feedback(det, i, self.config.vf_gain_rad_per_px)
        return i

    def act(self, det: Detections, theta_rad) -> tuple[np.ndarray, str]:
        """One step: the gate picks VF or LM; returns (dtheta, module that moved the head)."""
        c = self.config
        module = self._trial_module or (LM if self.rng.random() < self.gate_rate() else VF)
        target = most_interesting(det, c.interest_weights) if module == VF else None
        if module == VF and target is None:
            module = LM if c.vf_fallback == "lm" else RANDOM
        if module == VF:
            dtheta = visual_feedback(det, target, c.vf_gain_rad_per_px)
        elif module == LM:
            dtheta = self._lm(self._face_x, theta_rad)
        else:
            angle = self.rng.uniform(0, 2 * np.pi)
            dtheta = self.step_rad * np.array([np.cos(angle), np.sin(angle)])
        self._thetas.append(np.asarray(theta_rad, dtype=float))
        self._steps.append(dtheta)
        self.learning_time_steps += 1
        return dtheta, module

    def end_trial(self, fired: bool, theta_end_rad) -> int:
        """Learn from the trial if the evaluator fired; returns the number of samples taught."""
        if not fired or not self._thetas:
            return 0
        thetas = np.array(self._thetas)
        target = self.config.learning_target
        if target == "executed_step":
            diff = np.array(self._steps)
        else:
            aim = np.asarray(theta_end_rad, dtype=float)
            if target == "object_direction":
                aim = aim + self._centring_rad
            diff = aim - thetas
        norm = np.maximum(np.hypot(diff[:, 0], diff[:, 1]), 1e-12)[:, None]
        keep = norm[:, 0] > 1e-9
        self.learner.partial_fit(self._inputs(self._face_x, thetas[keep]), (diff / norm)[keep])
        return int(keep.sum())
