"""The seam between the robot and the trial loop: what an agent is given and must offer.

Every model (the paper's bootstrap agent, the oracle, a model of your own) is an
:class:`Agent`; :func:`jointattention.experiment.trial.run_trial` drives it. The agent sees
only what the robot has: the caregiver's face window, its own head angle, the detector's
report (:class:`~jointattention.agent.detections.Detections`) and how each trial ended
(:class:`Outcome`). Which object the caregiver looks at is never given.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass
from typing import Any, NamedTuple, Protocol, runtime_checkable

import numpy as np

from .._jit import jit
from ..errors import ConfigError
from .detections import Detections

__all__ = ["LM", "RANDOM", "VF", "Agent", "AgentKernels", "Body", "ModuleKernels", "Outcome",
           "TrialKernels", "freeze", "judge_target", "no_observe", "no_passed_over",
           "see_as_is"]

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


@jit(inline=True)  # into the compiled loop: the module's arrays not counted in and out
def no_observe(state, pan, tilt, step_rad, centre, cx, cy, gain_rad_per_px, learning) -> float:
    """``observe`` of a module that makes nothing of a step's view and keeps no evidence: 0.0."""
    return 0.0


@jit(inline=True)
def no_passed_over(state, pan, tilt, centre, cx, cy, gain_rad_per_px, learning, passed) -> bool:
    """``passed_over`` of a module that lets visual attention take any object: False."""
    return False


class ModuleKernels(NamedTuple):
    """A learning module's part of a trial, as compiled kernels (``_jit.jit``) of its state.

    A learning module of the bootstrap agent declares them as its ``kernels``, its state as
    ``compiled_state(n_faces)`` (a named tuple of numbers and arrays, its own arrays, changed
    in place; ``n_faces``: how many distinct faces the run shows, 0 if unknown) and the stream
    its ``learn`` kernel draws from as ``learn_rng``; it takes back what the kernels counted
    with ``sync(state)``. Its step-by-step methods call the same kernels; the compiled engine
    compiles one loop for each set of kernels it is handed and calls them at their place in
    the trial:

    - ``begin(state, face, face_id, pan, tilt, learning) -> float``: the trial starts, the
      caregiver's face (a flat view) in sight at head angle (``pan``, ``tilt``); ``face_id``
      is which of the run's ``n_faces`` faces it is (equal ids: equal faces, so a module may
      keep what it computed of one), -1 if unknown; ``learning`` is False for a frozen
      agent. It returns the evidence for the face in view (the evidence gate's measure; 0.0
      for a module that keeps none).
    - ``observe(state, pan, tilt, step_rad, centre, cx, cy, gain_rad_per_px, learning)
      -> float``: a step's view before the gate chooses (``centre`` (m, 2): the objects
      detected, in pixels; ``cx``, ``cy`` the image's centre; ``gain_rad_per_px`` Eq. 2's
      gain); it returns the evidence for the face now. Default :func:`no_observe`.
    - ``passed_over(state, pan, tilt, centre, cx, cy, gain_rad_per_px, learning, passed)
      -> bool``: whether visual attention passes over some of the objects detected, then
      flagged in ``passed`` (a bool per object); False: it may take any. Default
      :func:`no_passed_over`.
    - ``command(state, pan, tilt, step_rad, rng) -> (d_pan, d_tilt)``: the module's step at
      a head angle; ``rng`` is the agent's move stream, for a module that may step at random.
    - ``direction(state, pan, tilt, step_rad) -> (d_pan, d_tilt)``: the step it would take,
      drawing nothing (the performance gate's measure).
    - ``learn(state, place, centre, seen, pan, tilt, cx, cy, gain_rad_per_px, face, thetas,
      steps, rng) -> int``: a trial the agent learns from ended at head angle (``pan``,
      ``tilt``); ``place`` (2,) is what it aims at (the learning target), ``centre`` (m, 2)
      the last image's objects in pixels (``seen`` the attended one: ``agent.moves.places_into``
      finds their places), ``thetas`` and ``steps`` (n, 2) the trial's head angles and the
      steps taken from them; ``rng`` is ``learn_rng``. It returns how many places or samples
      it learned. A module whose ``learns_unfound`` is True is also called, with ``seen``
      -1 and ``place`` unset, for a trial it drove last that ended with nothing found.
    """

    begin: Any
    command: Any
    direction: Any
    learn: Any
    observe: Any = no_observe
    passed_over: Any = no_passed_over


@jit
def see_as_is(state, face, learning_time_steps, out) -> bool:
    """``see`` of an agent that sees the face window as it is: False (``out`` not written)."""
    return False


@jit
def judge_target(state, fired, on_target, error_rad, learning) -> bool:
    """``judge`` of a caregiver who approves her target only: the evaluator fired on it."""
    return fired and on_target


class AgentKernels(NamedTuple):
    """A bootstrap agent's own part of a trial beyond its learning module, as compiled kernels.

    The agent declares them as its ``kernels``, its state as ``compiled_state(n_pixels)`` (a
    named tuple of numbers and arrays, changed in place; ``n_pixels``: a face window's) and
    takes back what they changed with ``sync(state)``. Its step-by-step methods call the same
    kernels:

    - ``see(state, face, learning_time_steps, out) -> bool``: the face window (flat) as the
      robot sees it at a learning time, into ``out``; False if it sees the face as it is
      (``out`` not written). Default :func:`see_as_is`.
    - ``judge(state, fired, on_target, error_rad, learning) -> bool``: whether the caregiver
      approves a trial: the evaluator ``fired`` on an object, ``on_target`` if it is the one
      she looks at, ``error_rad`` the angle between the two at the robot's head (inf where
      unknown); a learning agent's caregiver may update what she judges by. A taught model
      learns only from the trials she approves (``ModelOptions.taught``). Default
      :func:`judge_target`.
    """

    see: Any = see_as_is
    judge: Any = judge_target


class TrialKernels(NamedTuple):
    """An agent's whole part of a trial, as compiled kernels of its state: no gate, no module.

    An agent whose every step is its own choice (the reinforcement learner,
    :mod:`jointattention.models.rl`) declares them as its ``kernels``, its state as
    ``compiled_state(n_pixels)`` (a named tuple of its options and its own arrays, changed in
    place; ``n_pixels``: a face window's) and the stream ``act`` draws from as ``act_rng``.
    Its ``begin_trial``, ``act`` and ``end_trial`` call the same kernels; the compiled engine
    compiles one loop for each set (``experiment/compiled/_rl_loop.loop_for``) and keeps the
    learning time itself:

    - ``begin(state, face, learning) -> bool``: the trial starts, the caregiver's face (a
      flat view) in sight; ``learning`` is False for a frozen agent. False if it cannot act
      on the face: a frozen agent that has seen no face to standardise it by
      (:data:`~jointattention.agent.face_standardiser.NO_FACE_SEEN`).
    - ``act(state, pan, tilt, rng) -> (d_pan, d_tilt, lm)``: one step at head angle (``pan``,
      ``tilt``): the head angle's change, and whether it is a step of the agent's learned
      command (module :data:`LM` in the trial records; any other step is the agent's own,
      neither :data:`LM` nor :data:`RANDOM`); ``rng`` is ``act_rng``.
    - ``learn(state, fired, pan, tilt)``: a learning agent's trial ended at head angle
      (``pan``, ``tilt``), the evaluator ``fired`` on an object or not.
    """

    begin: Any
    act: Any
    learn: Any


def freeze(agent):
    """A copy of ``agent`` that learns nothing (``learning = False``); ``agent`` is untouched.

    What only learning reads (a learning module's ``learning_only()``: the population code's
    replay memory, 178 MB when full) is not copied: the copy holds empty arrays in its place.
    """
    if not hasattr(agent, "learning"):
        raise ConfigError(f"{type(agent).__name__}: this model cannot be frozen (it has no "
                          "'learning' switch); expected a model of the package's registry")
    unread = getattr(getattr(agent, "module", None), "learning_only", tuple)()
    frozen = copy.deepcopy(agent, {id(a): a[:0].copy() for a in unread})
    frozen.learning = False
    return frozen
