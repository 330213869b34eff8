"""The paper's model: the bootstrap learning agent and its options.

The agent wires visual attention, self-evaluation, learning and the gate; its options are the
``[model]`` section with ``kind = "bootstrap"``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .._fields import param
from ..config.agent import AgentConfig
from .attention import most_interesting, visual_feedback
from .detections import Detections
from .gates import GATES, Gate, SigmoidGate
from .learner import FaceStandardiser, LearningModule
from .models import ModelOptions
from .protocol import LM, RANDOM, VF, Body, Outcome

__all__ = ["BootstrapAgent", "BootstrapOptions"]


@dataclass(frozen=True)
class BootstrapOptions(ModelOptions):
    """The bootstrap model's options.

    The last three are readings where the paper is silent (README, *The model*).
    """

    readings: ClassVar[tuple[str, ...]] = ("gate_per", "vf_fallback", "learning_target")

    n_hidden: int = param(7, "hidden units of the learning module (paper: 7)", lo=1, hi=1000)
    learning_rate: float = param(
        0.0003, "back-propagation step size (about 750 standardised inputs: keep it small)",
        lo=0, hi=10)
    momentum: float = param(0.5, "momentum of the back-propagation updates", lo=0, hi=0.999)
    init_scale: float = param(
        1.0, "scale of the initial weights (times 1/sqrt(fan-in))", lo=0, hi=100)
    gate: Gate = param(factory=SigmoidGate, registry=GATES,
                       help="the gate: kind (sigmoid, constant) and its parameters")
    gate_per: str = param(
        "step", "reading: the gate decides at every step, or once per trial",
        choices=("step", "trial"))
    vf_fallback: str = param(
        "random", "reading: what moves the head when the gate picks the visual controller and no "
        "object is in view: the learning module, or a random step", choices=("lm", "random"))
    learning_target: str = param(
        "object_direction", "reading: what each step of a successful trial is taught: the unit "
        "direction to the final gaze, to the attended object (the final gaze plus the visual "
        "controller's command that would centre it), or the step that was executed",
        choices=("final_direction", "object_direction", "executed_step"))

    def build(self, agent: AgentConfig, body: Body, rng: np.random.Generator) -> BootstrapAgent:
        """The untrained bootstrap agent."""
        return BootstrapAgent(self, agent, body, rng)


class BootstrapAgent:
    """The robot's side of the model (paper, Fig. 2).

    Args:
        options: the model's options and the readings where the paper is silent.
        agent: the robot's shared mechanisms (Eq. 1 weights, Eq. 2 gain, step length).
        body: image size, joint ranges (head angles are scaled by them for the learning
            module) and face window size.
        rng: the agent's own generator (initial weights, gate draws, random steps).

    A trial is ``begin_trial``, then ``act`` at each step, then ``end_trial``; learning
    happens in ``end_trial`` if the internal evaluator fired.
    """

    def __init__(self, options: BootstrapOptions, agent: AgentConfig, body: Body,
                 rng: np.random.Generator):
        self.options, self.agent, self.body = options, agent, body
        limits = np.asarray(body.joint_limits_rad, dtype=float)
        self._theta_mid, self._theta_half = limits.mean(axis=1), np.ptp(limits, axis=1) / 2
        self.rng = rng
        n_in = body.face_size_px[0] * body.face_size_px[1] + 2
        self.learner = LearningModule(
            n_in, options.n_hidden, 2, learning_rate=options.learning_rate,
            momentum=options.momentum, init_scale=options.init_scale, rng=rng)
        self.faces = FaceStandardiser()
        self.learning_time_steps = 0
        self._trial_module: str | None = None
        self._thetas: list[np.ndarray] = []
        self._steps: list[np.ndarray] = []

    @property
    def step_rad(self) -> float:
        """Length of one step of the learning module (or a random step)."""
        return np.deg2rad(self.agent.lm_step_deg)

    def gate_rate(self, learning_time_steps=None):
        """Rate of choosing the learning module at a learning time (default: now)."""
        t = self.learning_time_steps if learning_time_steps is None else learning_time_steps
        return self.options.gate.rate_at(t)

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
        if self.options.gate_per == "trial":
            self._trial_module = LM if self.rng.random() < self.gate_rate() else VF

    def act(self, det: Detections, theta_rad) -> tuple[np.ndarray, str]:
        """One step: the gate picks VF or LM; returns (dtheta, module that moved the head)."""
        o = self.options
        module = self._trial_module or (LM if self.rng.random() < self.gate_rate() else VF)
        target = most_interesting(det, self.agent.interest_weights) if module == VF else None
        if module == VF and target is None:
            module = LM if o.vf_fallback == "lm" else RANDOM
        if module == VF:
            dtheta = visual_feedback(det, target, self.agent.vf_gain_rad_per_px)
        elif module == LM:
            dtheta = self._lm(self._face_x, theta_rad)
        else:
            angle = self.rng.uniform(0, 2 * np.pi)
            dtheta = self.step_rad * np.array([np.cos(angle), np.sin(angle)])
        self._thetas.append(np.asarray(theta_rad, dtype=float))
        self._steps.append(dtheta)
        self.learning_time_steps += 1
        return dtheta, module

    def end_trial(self, outcome: Outcome) -> int:
        """Learn from the trial if the evaluator fired; returns the number of samples taught.

        The ``object_direction`` target aims at the attended object itself: the final head
        angle plus the visual controller's command (Eq. 2) that would centre it, not where
        the head was when the object entered the evaluator's circle.
        """
        if not outcome.fired or not self._thetas:
            return 0
        thetas = np.array(self._thetas)
        target = self.options.learning_target
        if target == "executed_step":
            diff = np.array(self._steps)
        else:
            aim = np.asarray(outcome.theta_rad, dtype=float)
            if target == "object_direction":
                aim = aim + visual_feedback(outcome.detections, outcome.seen,
                                            self.agent.vf_gain_rad_per_px)
            diff = aim - thetas
        norm = np.maximum(np.hypot(diff[:, 0], diff[:, 1]), 1e-12)[:, None]
        keep = norm[:, 0] > 1e-9
        self.learner.partial_fit(self._inputs(self._face_x, thetas[keep]), (diff / norm)[keep])
        return int(keep.sum())
