"""The seam between the robot and the trial loop: what an agent is given and must offer.

Every model (the paper's bootstrap agent, the oracle, a model of your own) is an
:class:`Agent`; :func:`jointattention.experiment.trial.run_trial` drives it. The agent sees
only what the robot has: the caregiver's face window, its own head angle, the detector's
report (:class:`~jointattention.agent.detections.Detections`) and how each trial ended
(:class:`Outcome`). Which object the caregiver looks at is never given.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, NamedTuple, Protocol, runtime_checkable

import numpy as np

from .detections import Detections

__all__ = ["LM", "RANDOM", "VF", "Agent", "Body", "ModuleKernels", "Outcome"]

# The modules that may move the head (the second value of Agent.act).
VF, LM, RANDOM = "vf", "lm", "random"


@dataclass(frozen=True)
class Body:
    """What the robot knows of its own body.

    Attributes:
        image_size_px: (W, H) of its camera image.
        joint_limits_rad: ((pan_lo, pan_hi), (tilt_lo, tilt_hi)), its joint ranges.
        face_size_px: (width, height) of the caregiver's face window it keeps.
        eye_size_px: (width, height) of the window on her eyes it keeps through its fovea, or
            None if it keeps none. With one, what it keeps of a look at her (its *view*) is
            the face window's grey levels, row by row, then the eye window's: one flat array
            of :attr:`view_size` (:func:`~jointattention._arrays.views`).
    """

    image_size_px: tuple[int, int]
    joint_limits_rad: tuple[tuple[float, float], tuple[float, float]]
    face_size_px: tuple[int, int]
    eye_size_px: tuple[int, int] | None = None

    @property
    def view_size(self) -> int:
        """The grey levels of a view: the face window's, then the eye window's if it keeps one."""
        (w, h), (ew, eh) = self.face_size_px, self.eye_size_px or (0, 0)
        return w * h + ew * eh


@dataclass(frozen=True)
class Outcome:
    """How a trial ended, as the robot knows it.

    Attributes:
        fired: whether the internal evaluator (Eq. 3) found an object at the image centre.
        theta_rad: the head angle (pan, tilt) at the end.
        detections: the detector's report of the last image.
        seen: the index, in ``detections``, of the object the evaluator fired on (None if it
            did not fire).
        approved: the caregiver's evaluation, for models that are taught by her (the teacher):
            whether the object the evaluator fired on is the one she looks at. None where no
            caregiver evaluates; the paper's bootstrap model never reads it.
        caregiver_error_rad: how far from her target the robot looked, as she sees it: the
            angle, at the robot's head, between the object the evaluator fired on and her
            target (0 for her target; None where no caregiver evaluates or nothing was
            attended). The developmental model's caregiver grades the robot with it.
    """

    fired: bool
    theta_rad: np.ndarray
    detections: Detections
    seen: int | None
    approved: bool | None = None
    caregiver_error_rad: float | None = None


@runtime_checkable
class Agent(Protocol):
    """The contract of every model run by the trial loop.

    A trial is ``begin_trial``, then ``act`` once per step until the trial ends, then
    ``end_trial``. The trial loop, not the agent, evaluates each image (Eq. 3), moves the
    head within its joint limits and ends the trial; the agent learns in ``end_trial``.

    Attributes:
        learning_time_steps: steps acted so far (the paper's learning time); the runner
            stops a cell when it reaches ``experiment.n_steps``.

    A model that can be frozen (measured on other data sets without learning from them,
    :func:`jointattention.experiment.evaluate.evaluate_agent`) has a ``learning`` attribute
    too: set to False, its trials change nothing of what it learned, nor its learning time.
    """

    learning_time_steps: int

    def begin_trial(self, face_window: np.ndarray, theta_rad: np.ndarray) -> None:
        """Start a trial looking at the caregiver: its face window (H, W) and the head angle."""

    def act(self, detections: Detections, theta_rad: np.ndarray) -> tuple[np.ndarray, str]:
        """One step: the head angle change and the module that made it.

        The change is (pan, tilt) in radians; the module is :data:`VF`, :data:`LM`, :data:`RANDOM`,
        or a name of the model's own.
        """

    def end_trial(self, outcome: Outcome) -> None:
        """The trial ended: learn from it (or not)."""


class ModuleKernels(NamedTuple):
    """A learning module's part of a trial, as compiled kernels (``_jit.jit``) of its state.

    A learning module of the bootstrap agent declares them as its ``kernels`` and its state as
    ``compiled_state()`` (a named tuple of numbers and arrays, its own arrays, changed in
    place), then takes back what the kernels counted with ``sync(state)``. Its step-by-step
    methods call the same kernels; the compiled engine compiles one loop for each set of
    kernels it is handed and calls them at their place in the trial:

    - ``begin(state, face, pan, tilt, learning) -> float``: the trial starts, the caregiver's
      face (a flat view) in sight at head angle (``pan``, ``tilt``); ``learning`` is False for
      a frozen agent. It returns the evidence for the face in view (the evidence gate's
      measure; 0.0 for a module that keeps none).
    - ``command(state, pan, tilt, step_rad, rng) -> (d_pan, d_tilt)``: the module's step at
      a head angle; ``rng`` is the agent's move stream, for a module that may step at random.
    - ``direction(state, pan, tilt, step_rad) -> (d_pan, d_tilt)``: the step it would take,
      drawing nothing (the performance gate's measure).
    - ``learn(state, place, centre, seen, pan, tilt, cx, cy, gain_rad_per_px, face, rng)
      -> int``: a trial the agent learns from ended at head angle (``pan``, ``tilt``);
      ``place`` (2,) is what it aims at (the learning target), ``centre`` (m, 2) the last
      image's objects in pixels (``seen`` the attended one, ``cx``, ``cy`` the image's centre,
      ``gain_rad_per_px`` Eq. 2's gain: ``agent.moves.places_into`` finds their places);
      ``rng`` is the module's own stream. It returns how many places it learned.
    """

    begin: Any
    command: Any
    direction: Any
    learn: Any
