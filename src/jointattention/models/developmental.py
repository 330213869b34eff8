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
from typing import ClassVar, NamedTuple

import numpy as np

from .._arrays import windows
from .._fields import param
from .._jit import jit
from ..agent.options import AgentConfig
from ..agent.protocol import AgentKernels, Body, Outcome
from ..errors import ConfigError
from .teacher import TeacherAgent, TeacherOptions

__all__ = ["KERNELS", "DevelopmentArrays", "DevelopmentalAgent", "DevelopmentalOptions",
           "blur_into", "blur_px", "caregiver_update", "development_judge", "development_see"]


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


class DevelopmentArrays(NamedTuple):
    """The developments' options, her criterion and the blur's scratch, as the kernels take them."""

    criterion_level: float  # caregiver_update's
    criterion_window_trials: float
    criterion_shrink: float
    blur_start_px: float  # the visual development (0: none)
    blur_sharp_steps: float
    face_width_px: int
    face_height_px: int
    caregiver: np.ndarray  # (2,): her criterion (rad) and rate of approving, changed in place
    tmp: np.ndarray  # the blur's scratch, a face window's pixels


@jit
def development_see(s, face, learning_time_steps, out) -> bool:
    """The face window through the blur at a learning time, into ``out`` (as the robot sees it).

    False without visual development (``blur_start_px`` 0): the face as it is.
    """
    if s.blur_start_px <= 0:
        return False
    blur_into(face, s.face_width_px, s.face_height_px,
              blur_px(s.blur_start_px, s.blur_sharp_steps, learning_time_steps), s.tmp, out)
    return True


@jit
def development_judge(s, fired, on_target, error_rad, learning) -> bool:
    """She approves her target, or an object within her criterion of it; then she updates it.

    Learning, her criterion and rate of approving move (:func:`caregiver_update`).
    """
    approved = fired and (on_target or error_rad <= s.caregiver[0])
    if learning:
        s.caregiver[0], s.caregiver[1] = caregiver_update(
            approved, s.caregiver[0], s.caregiver[1], s.criterion_level,
            s.criterion_window_trials, s.criterion_shrink)
    return approved


KERNELS = AgentKernels(development_see, development_judge)


class DevelopmentalAgent(TeacherAgent):
    """The teacher with the caregiver's adaptive criterion and the robot's visual development.

    Its developments are its own part of a trial as compiled kernels (:data:`KERNELS`, over
    :meth:`compiled_state`), which :meth:`see` and the caregiver's judgement call too.

    Attributes:
        criterion_rad_: the caregiver's criterion now.
        approved_rate_: her running rate of approving the robot's trials.
    """

    kernels = KERNELS

    def __init__(self, options: DevelopmentalOptions, mechanisms: AgentConfig, body: Body,
                 rng: np.random.Generator):
        if body.eye_size_px is not None:  # it blurs the face window as an image
            raise ConfigError("the developmental model sees the face window only; expected a "
                              "world without an eye window ([world.eye_window] 0 x 0)")
        super().__init__(options, mechanisms, body, rng)
        self.criterion_rad_ = math.radians(options.criterion_start_deg)
        self.approved_rate_ = 0.0

    def compiled_state(self, n_pixels: int) -> DevelopmentArrays:
        """The state of its kernels (:data:`KERNELS`): the developments' options, her criterion."""
        o, (w, h) = self.options, self.body.face_size_px
        return DevelopmentArrays(
            float(o.criterion_level), float(o.criterion_window_trials),
            float(o.criterion_shrink), float(o.blur_start_px), float(o.blur_sharp_steps), w, h,
            np.array([self.criterion_rad_, self.approved_rate_]), np.empty(n_pixels))

    def sync(self, state: DevelopmentArrays) -> None:
        """Take back her criterion and rate of approving, which the kernels moved."""
        self.criterion_rad_, self.approved_rate_ = (float(v) for v in state.caregiver)

    def blur_px(self, learning_time_steps: float | None = None) -> float:
        """The blur's s.d. (face-window pixels) at a learning time (default: now)."""
        o = self.options
        t = self.learning_time_steps if learning_time_steps is None else learning_time_steps
        return blur_px(o.blur_start_px, o.blur_sharp_steps, float(t))

    def see(self, face_window: np.ndarray) -> np.ndarray:
        """The face window as the robot sees it now, (H, W) floats."""
        w, h = self.body.face_size_px
        flat = np.ascontiguousarray(windows("face_window", face_window, (w, h)).reshape(-1),
                                    dtype=float)
        out = np.empty_like(flat)
        if not self.kernels.see(self.compiled_state(len(flat)), flat,
                                float(self.learning_time_steps), out):
            out[:] = flat
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
        error, state = outcome.caregiver_error_rad, self.compiled_state(0)
        approved = self.kernels.judge(state, bool(outcome.fired), super()._judge(outcome),
                                      math.inf if error is None else float(error), True)
        self.sync(state)
        return bool(approved)
