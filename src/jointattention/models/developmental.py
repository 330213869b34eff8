"""The developmental model: the teacher helped by functional development.

After Nagai, Asada and Hosoda (2006), "Learning for joint attention helped by functional
development", Advanced Robotics 20(10). The robot learns from the caregiver's evaluation, as
the teacher does (:mod:`.teacher`), with two developments:

- **the caregiver's adaptive evaluation**: she approves a trial whose attended object lies
  within her criterion of her target (the angle at the robot's head,
  :attr:`~.protocol.Outcome.caregiver_error_rad`), and she narrows the criterion, from easy to
  hard, as the robot improves: after each trial while her rate of approving exceeds a level;
- **visual development**: the robot sees the caregiver's face window through a Gaussian blur
  whose width falls with learning time, from blurred to sharp.

The paper publishes neither schedule: the criterion's start, level, window and narrowing, and
the blur's width and duration are our readings, each an option (docs/neighbours.md). With
``criterion_start_deg = 0`` and ``blur_start_px = 0`` the model is the teacher. Everything else
(visual attention, the gate, the learning module, what a trial teaches) is the bootstrap
model's. Both kernels (:func:`blur_into`, :func:`caregiver_update`) are shared with the compiled
engine.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .._arrays import windows
from .._fields import param
from .._jit import jit
from ..agent.options import AgentConfig
from ..agent.protocol import Body, Outcome
from ..errors import ConfigError
from .teacher import TeacherAgent, TeacherOptions

__all__ = ["DevelopmentalAgent", "DevelopmentalOptions", "blur_into", "blur_px",
           "caregiver_update"]


@dataclass(frozen=True)
class DevelopmentalOptions(TeacherOptions):
    """The developmental model's options: the teacher's, and the two developments (readings).

    The claims tell its variants apart by all six readings of the developments.
    """

    compiled: ClassVar[bool] = True

    readings: ClassVar[tuple[str, ...]] = (
        *TeacherOptions.readings, "criterion_start_deg", "criterion_level",
        "criterion_window_trials", "criterion_shrink", "blur_start_px", "blur_sharp_steps")

    criterion_start_deg: float = param(
        20.0, "reading: the caregiver's first criterion: she approves a trial whose attended "
        "object lies within this angle of her target, seen from the robot's head (0: her "
        "target only, as the teacher)", lo=0, hi=180)
    criterion_level: float = param(
        0.5, "reading: she narrows her criterion after each trial while her rate of approving "
        "the robot's trials is above this", lo=0, hi=1)
    criterion_window_trials: float = param(
        100.0, "reading: the trials her rate of approving averages over (its time constant)",
        lo=1, hi=1e7)
    criterion_shrink: float = param(
        0.995, "reading: the factor by which she narrows her criterion after such a trial",
        lo=0, hi=1)
    blur_start_px: float = param(
        2.0, "reading: s.d. of the Gaussian blur of the face window at the start, in "
        "face-window pixels (0: no visual development)", lo=0, hi=50)
    blur_sharp_steps: float = param(
        150_000.0, "reading: the learning time at which the face window is sharp; the blur's "
        "s.d. falls linearly until then", lo=1, hi=1e10)

    def caregiver_inputs(self, face_size_px) -> tuple:
        """The caregiver judges by a criterion that adapts, and the face window sharpens."""
        return (True, True, self.criterion_level, self.criterion_window_trials,
                self.criterion_shrink, self.blur_start_px, self.blur_sharp_steps, *face_size_px)

    def build(self, mechanisms: AgentConfig, body: Body,
              rng: np.random.Generator) -> DevelopmentalAgent:
        """The untrained developmental agent."""
        return DevelopmentalAgent(self, mechanisms, body, rng)


@jit
def blur_px(start_px: float, sharp_steps: float, learning_time_steps: float) -> float:
    """The blur's s.d. at a learning time: linear from ``start_px`` to 0 at ``sharp_steps``."""
    return start_px * max(0.0, 1.0 - learning_time_steps / sharp_steps)


@jit
def blur_into(face, width: int, height: int, sigma_px: float, tmp, out) -> None:
    """``out`` = the face window (flat, row-major (height, width)) blurred by a Gaussian.

    Separable, three s.d. wide, borders repeated; a copy for ``sigma_px`` of 0. ``tmp`` is
    scratch of the face's size.
    """
    if sigma_px <= 0.0:
        for i in range(len(face)):  # element by element: quicker for numba to compile
            out[i] = face[i]
        return
    radius = int(math.ceil(3.0 * sigma_px))
    weights = np.empty(2 * radius + 1)
    for k in range(-radius, radius + 1):
        weights[k + radius] = math.exp(-0.5 * (k / sigma_px) ** 2)
    weights /= weights.sum()
    for y in range(height):  # along rows
        for x in range(width):
            s = 0.0
            for k in range(-radius, radius + 1):
                s += weights[k + radius] * face[y * width + min(max(x + k, 0), width - 1)]
            tmp[y * width + x] = s
    for y in range(height):  # along columns
        for x in range(width):
            s = 0.0
            for k in range(-radius, radius + 1):
                s += weights[k + radius] * tmp[min(max(y + k, 0), height - 1) * width + x]
            out[y * width + x] = s


@jit
def _blur_rows_into(faces, width: int, height: int, sigma_px: float, out) -> None:
    """:func:`blur_into` for each flat face window of ``faces`` (K, H * W), into ``out``."""
    tmp = np.empty(faces.shape[1])
    for k in range(len(faces)):
        blur_into(faces[k], width, height, sigma_px, tmp, out[k])


@jit
def caregiver_update(approved: bool, criterion_rad: float, rate: float, level: float,
                     window_trials: float, shrink: float) -> tuple[float, float]:
    """Her criterion and rate of approving after a trial: the rate averages, she narrows."""
    rate = rate + ((1.0 if approved else 0.0) - rate) / window_trials
    if rate > level:
        criterion_rad = criterion_rad * shrink
    return criterion_rad, rate


class DevelopmentalAgent(TeacherAgent):
    """The teacher with the caregiver's adaptive criterion and the robot's visual development.

    Attributes:
        criterion_rad_: the caregiver's criterion now.
        approved_rate_: her running rate of approving the robot's trials.
    """

    def __init__(self, options: DevelopmentalOptions, mechanisms: AgentConfig, body: Body,
                 rng: np.random.Generator):
        if body.eye_size_px is not None:  # it blurs the face window as an image
            raise ConfigError("the developmental model sees the face window only; expected a "
                              "world without an eye window ([world.eye_window] 0 x 0)")
        super().__init__(options, mechanisms, body, rng)
        self.criterion_rad_ = math.radians(options.criterion_start_deg)
        self.approved_rate_ = 0.0

    def caregiver_state(self) -> tuple[float, float]:
        """Her criterion (rad) and rate of approving, which the compiled engine carries."""
        return self.criterion_rad_, self.approved_rate_

    def set_caregiver_state(self, criterion_rad: float, approved_rate: float) -> None:
        """Take back her criterion and rate from the compiled engine."""
        self.criterion_rad_, self.approved_rate_ = float(criterion_rad), float(approved_rate)

    def blur_px(self, learning_time_steps: float | None = None) -> float:
        """The blur's s.d. (face-window pixels) at a learning time (default: now)."""
        o = self.options
        t = self.learning_time_steps if learning_time_steps is None else learning_time_steps
        return blur_px(o.blur_start_px, o.blur_sharp_steps, float(t))

    def see(self, face_window: np.ndarray) -> np.ndarray:
        """The face window as the robot sees it now, (H, W) floats."""
        w, h = self.body.face_size_px
        flat = windows("face_window", face_window, (w, h)).reshape(-1)
        out = np.empty_like(flat)
        blur_into(flat, w, h, self.blur_px(), np.empty_like(flat), out)
        return out.reshape(h, w)

    def begin_trial(self, face_window: np.ndarray, theta_rad) -> None:
        """Start the trial on the face window as the robot sees it now."""
        super().begin_trial(self.see(face_window), theta_rad)

    def lm_command(self, face_window: np.ndarray, theta_rad) -> np.ndarray:
        """The learning module's command on the face window as the robot sees it now."""
        return super().lm_command(self.see(face_window), theta_rad)

    def lm_commands(self, face_windows: np.ndarray, thetas_rad: np.ndarray) -> np.ndarray:
        """:meth:`lm_command` for K face windows (K, H, W) and head angles (K, 2)."""
        faces = windows("face_windows", face_windows, self.body.face_size_px, None)
        flat = np.ascontiguousarray(faces.reshape(len(faces), -1))
        seen = np.empty_like(flat)  # in one compiled loop: the held-out measures see 16,000
        w, h = self.body.face_size_px
        _blur_rows_into(flat, w, h, self.blur_px(), seen)
        return super().lm_commands(seen.reshape(faces.shape), thetas_rad)

    def _judge(self, outcome: Outcome) -> bool:
        """The caregiver grades the trial by her criterion, then updates it.

        She approves her target, or an object within her criterion of it (where the trial
        tells her error), then updates her criterion (:func:`caregiver_update`). The teacher's
        ``end_trial`` asks once per trial.
        """
        error = outcome.caregiver_error_rad
        approved = super()._judge(outcome) or (
            outcome.fired and error is not None and error <= self.criterion_rad_)
        o = self.options
        self.criterion_rad_, self.approved_rate_ = caregiver_update(
            approved, self.criterion_rad_, self.approved_rate_, o.criterion_level,
            o.criterion_window_trials, o.criterion_shrink)
        return approved
