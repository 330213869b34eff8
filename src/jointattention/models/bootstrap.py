"""The paper's model: the bootstrap learning agent and its options.

The agent wires visual attention, self-evaluation, the gate and a learning module, which it
composes (:data:`MODULES`): the paper's network (:mod:`.network`), an episodic memory
(:mod:`.memory`) or a population code (:mod:`.population`). Options: ``[model]``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .._arrays import angles, views
from .._fields import param
from ..agent.attention import most_interesting, visual_feedback
from ..agent.detections import Detections
from ..agent.face_standardiser import FaceStandardiser
from ..agent.gates import GATES, Gate, SigmoidGate
from ..agent.moves import line_capture, random_step
from ..agent.options import AgentConfig
from ..agent.protocol import LM, RANDOM, VF, AgentKernels, Body, Outcome
from ..errors import ConfigError
from .memory.module import MemoryModule
from .memory.options import MemoryOptions
from .network.learner import LearningModule
from .network.module import NetworkModule
from .network.state import NetworkState
from .population.module import PopulationModule
from .population.options import PopulationOptions
from .registry import ModelOptions

__all__ = ["LEARNERS", "LEARNING_TARGETS", "BootstrapAgent", "BootstrapOptions"]

LEARNING_TARGETS = ("final_direction", "object_direction", "executed_step")
LEARNERS = ("backprop", "memory", "population")


@dataclass(frozen=True)
class BootstrapOptions(ModelOptions):
    """The bootstrap model's options.

    Those named in ``readings`` are where the paper is silent (docs/readings.md).
    """

    readings: ClassVar[tuple[str, ...]] = ("gate_per", "vf_fallback", "learning_target",
                                           "learn_from", "n_passes", "learning_rate", "init_scale")
    compiled: ClassVar[bool] = True

    n_hidden: int = param(7, "hidden units of the learning module (paper: 7)", lo=1, hi=1000)
    learning_rate: float = param(
        0.0003, "back-propagation step size (about 750 standardised inputs: keep it small)",
        lo=0, hi=10)
    momentum: float = param(0.5, "momentum of the back-propagation updates", lo=0, hi=0.999)
    init_scale: float = param(
        1.0, "scale of the initial weights (times 1/sqrt(fan-in))", lo=0, hi=100)
    gate: Gate = param(factory=SigmoidGate, registry=GATES,
                       help="the gate: kind (sigmoid, constant, performance, evidence) and "
                       "its parameters")
    gate_per: str = param(
        "step", "reading: the gate decides at every step, or once per trial",
        choices=("step", "trial"))
    vf_fallback: str = param(
        "random", "reading: what moves the head when the gate picks the visual controller and no "
        "object is in view: the learning module, a random step, or a sweep (a random "
        "direction drawn once per trial, so that far objects are reached)",
        choices=("lm", "random", "sweep"))
    learning_target: str = param(
        "object_direction", "reading: what each step of a successful trial is taught: the unit "
        "direction to the final gaze, to the attended object (the final gaze plus the visual "
        "controller's command that would centre it), or the step that was executed",
        choices=LEARNING_TARGETS)
    learn_from: str = param(
        "every", "reading: the module learns from every trial the evaluator ended, or only from "
        "those whose last move the visual controller made (visual attention centred the object)",
        choices=("every", "vf"))
    n_passes: int = param(
        1, "reading: back-propagation passes over a successful trial's samples", lo=1, hi=100)
    learner: str = param(
        "backprop", "the learning module: the paper's network (back-propagation), an episodic "
        "memory of where objects were found for similar faces (a lookup), or a population code "
        "of where they are found around a face (docs/generalisation.md)", choices=LEARNERS)
    memory: MemoryOptions = param(factory=MemoryOptions,
                                  help="the episodic memory's options (learner = 'memory')")
    population: PopulationOptions = param(
        factory=PopulationOptions, help="the population code's options (learner = 'population')")

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.learner != "backprop" and self.learning_target == "executed_step":
            raise ConfigError(f"learning_target = 'executed_step': the {self.learner} learner "
                              "learns places, not steps; expected 'object_direction' or "
                              f"'final_direction' with learner = '{self.learner}'")
        if self.learner != "backprop" and self.n_passes != 1:
            raise ConfigError(f"n_passes = {self.n_passes}: passes are the network's; expected "
                              f"1 with learner = '{self.learner}'")
        if self.gate.per_face and self.learner != "memory":
            raise ConfigError(f"gate kind '{self.gate.label}' follows the episodic memory's "
                              f"evidence; expected learner = 'memory', not '{self.learner}'")

    def save_refusal(self) -> str | None:
        """None: the network and the population code are saved; an episodic memory is not."""
        if self.learner == "memory":
            return "learner = 'memory' (an episodic memory is not saved)"
        return None

    @property
    def label(self) -> str:
        """``bootstrap, <gate>``, or ``bootstrap + memory, <gate>`` with the memory learner."""
        label = super().label
        return label if self.learner == "backprop" else label.replace(
            "bootstrap", f"bootstrap + {self.learner}", 1)

    def build(self, mechanisms: AgentConfig, body: Body,
              rng: np.random.Generator) -> BootstrapAgent:
        """The untrained bootstrap agent, with the learning module ``learner`` names."""
        return BootstrapAgent(self, mechanisms, body, rng)


# learner -> the learning module's class, built with the agent and the generator left after
# the agent's own streams (each module says how it splits it)
MODULES = {"backprop": lambda host, rng: NetworkModule(host),
           "memory": MemoryModule,
           "population": PopulationModule}


class BootstrapAgent(NetworkState):
    """The robot's side of the model (paper, Fig. 2).

    Args:
        options: the model's options and the readings where the paper is silent.
        mechanisms: the robot's shared mechanisms, the ``[agent]`` section (Eq. 1 weights,
            Eq. 2 gain, step length).
        body: image size, joint ranges (head angles are scaled by them for the learning
            module) and face window size.
        rng: the agent's own generator; it is split into one stream per purpose (initial
            weights, gate draws, random steps, then the learning module's), so that a change
            in one does not shift the others.

    A trial is ``begin_trial``, then ``act`` at each step, then ``end_trial``; learning
    happens in ``end_trial`` if the internal evaluator fired.

    Attributes:
        module: the learning module (``options.learner``: :class:`~.network.module.NetworkModule`,
            :class:`~.memory.module.MemoryModule` or
            :class:`~.population.module.PopulationModule`); the agent asks it for commands and
            hands it the trials to learn from.
        learner, faces: the paper's network and the face windows' running statistics (the
            network module's; a model file keeps them for every module).
        learning: whether it learns (True); a frozen agent (False) acts as at its learning
            time and changes nothing it learned: it can be measured on other data sets.
    """

    # its own part of a trial as compiled kernels (agent.protocol.AgentKernels): it sees the
    # face as it is, and a caregiver who judges approves her target only
    kernels = AgentKernels()

    def __init__(self, options: BootstrapOptions, mechanisms: AgentConfig, body: Body,
                 rng: np.random.Generator):
        self.options, self.mechanisms, self.body = options, mechanisms, body
        limits = np.asarray(body.joint_limits_rad, dtype=float)
        # head angles scaled to [-1, 1] by the joint ranges for the learning module
        self.theta_mid_rad = (limits[:, 0] + limits[:, 1]) / 2
        self.theta_half_rad = (limits[:, 1] - limits[:, 0]) / 2
        init_rng, self.gate_rng, self.move_rng = rng.spawn(3)
        n_in = body.view_size + 2
        self.learner = LearningModule(
            n_in, options.n_hidden, 2, learning_rate=options.learning_rate,
            momentum=options.momentum, init_scale=options.init_scale, rng=init_rng)
        self.faces = FaceStandardiser()
        self.learning_time_steps, self.learning = 0, True
        self.agreement_ = 0.0  # a measured gate's measure (Gate.measured)
        self._trial_module: str | None = None
        self._last_module: str | None = None
        self._thetas, self._steps = [], []  # the trial's head angles and steps, (2,) each
        self.module = MODULES[options.learner](self, rng)

    @property
    def step_rad(self) -> float:
        """Length of one step of the learning module (or a random step)."""
        return np.deg2rad(self.mechanisms.lm_step_deg)

    def gate_rate(self, learning_time_steps=None):
        """Rate of choosing the learning module at a learning time (default: now).

        A performance gate's rate now follows the measured agreement, and an evidence gate's
        the memory's evidence for this trial's face, not the time.
        """
        gate = self.options.gate
        if learning_time_steps is None and (gate.measured or gate.per_face):
            return gate.rate_of(self.module.evidence_ if gate.per_face else self.agreement_)
        t = self.learning_time_steps if learning_time_steps is None else learning_time_steps
        return gate.rate_at(t)

    # -- the learning module ---------------------------------------------------------------
    def lm_command(self, face_window: np.ndarray, theta_rad) -> np.ndarray:
        """The learning module's dtheta for a face window (its view) and head angle."""
        face = views("face_window", face_window, self.body)
        return self.module.command(face, angles("theta_rad", theta_rad))

    def lm_commands(self, face_windows: np.ndarray, thetas_rad: np.ndarray) -> np.ndarray:
        """:meth:`lm_command` for K face windows (K, H, W) (or views) and head angles (K, 2)."""
        faces = views("face_windows", face_windows, self.body, None)
        thetas = angles("thetas_rad", thetas_rad, len(faces))
        return self.module.commands(faces, thetas)

    def saved_arrays(self) -> dict[str, np.ndarray]:
        """What a model file keeps: the network and face statistics, then the module's own."""
        return {**super().saved_arrays(), **self.module.saved_arrays()}

    def saved_shapes(self) -> dict[str, tuple[int, ...]]:
        """The shape of each member of :meth:`saved_arrays`."""
        return {**super().saved_shapes(), **self.module.saved_shapes()}

    def load_arrays(self, arrays: dict[str, np.ndarray]) -> None:
        """Set the learned state from checked members of a model file."""
        super().load_arrays(arrays)
        self.module.load_arrays(arrays)

    def _measure(self, outcome: Outcome) -> None:
        """A performance gate's measure: did the module point, at the start, to the place found?"""
        gate = self.options.gate
        if not gate.measured:
            return
        u = self.module.direction(self._theta_start)
        v = self.place_of(outcome, outcome.seen) - self._theta_start
        self.agreement_ = gate.update(self.agreement_, u, v)

    def place_of(self, outcome: Outcome, i: int) -> np.ndarray:
        """Where object ``i`` of the last image is: the final head angle plus Eq. 2's command."""
        return np.asarray(outcome.theta_rad, dtype=float) + visual_feedback(
            outcome.detections, i, self.mechanisms.vf_gain_rad_per_px)

    def aim_of(self, outcome: Outcome) -> np.ndarray:
        """What a successful trial aims at: the attended object's place, or the final head angle.

        The ``object_direction`` target aims at the attended object itself, not where the head
        was when the object entered the evaluator's circle.
        """
        if self.options.learning_target == "object_direction":
            return self.place_of(outcome, outcome.seen)
        return np.asarray(outcome.theta_rad, dtype=float)

    def trial_end(self, outcome: Outcome) -> tuple:
        """A trial's end as a learning module's ``learn`` kernel takes it.

        (place, centre, seen, pan, tilt, cx, cy, gain_rad_per_px, face): what it aims at
        (:meth:`aim_of`), the last image's objects (pixels) and the attended one, the final
        head angle, the image's centre, Eq. 2's gain and the trial's face (flat)
        (:class:`~jointattention.agent.protocol.ModuleKernels`).
        """
        det, theta = outcome.detections, np.asarray(outcome.theta_rad, dtype=float)
        cx, cy = det.image_centre_px
        return (self.aim_of(outcome), np.ascontiguousarray(det.centre_px, dtype=float),
                int(outcome.seen), float(theta[0]), float(theta[1]), float(cx), float(cy),
                float(self.mechanisms.vf_gain_rad_per_px), self._face)

    def compiled_state(self, n_pixels: int) -> np.ndarray:
        """The state of its own kernels (:attr:`kernels`): none, as they keep nothing."""
        return np.zeros(0)

    def sync(self, state) -> None:
        """Take back what its own kernels changed: nothing here."""

    # -- a trial ---------------------------------------------------------------------------
    def begin_trial(self, face_window: np.ndarray, theta_rad) -> None:
        """Start a trial looking at the caregiver, whose face window (its view) the robot keeps."""
        face = views("face_window", face_window, self.body)
        self._face = np.ascontiguousarray(face, dtype=float)
        self._theta_start = angles("theta_rad", theta_rad)
        if self.learning:
            self.faces.partial_fit(face)
        self.module.begin(face, self._theta_start)
        self._thetas, self._steps = [], []
        self._trial_module = None
        if self.options.vf_fallback == "sweep":
            self._sweep = np.array(random_step(self.move_rng, self.step_rad))
        if self.options.gate_per == "trial":
            self._trial_module = LM if self.gate_rng.random() < self.gate_rate() else VF

    def act(self, det: Detections, theta_rad) -> tuple[np.ndarray, str]:
        """One step: the gate picks VF or LM; returns (dtheta, module that moved the head)."""
        o = self.options
        passed_over = self.module.observe(det, theta_rad)  # before the gate: MemoryModule.observe
        module = self._trial_module or (LM if self.gate_rng.random() < self.gate_rate() else VF)
        target = (most_interesting(det, self.mechanisms.interest_weights, passed_over)
                  if module == VF else None)
        if module == VF and target is None:
            module = LM if o.vf_fallback == "lm" else RANDOM
        if module == LM:
            target = self._captured(det, theta_rad)
        if target is not None:
            dtheta = visual_feedback(det, target, self.mechanisms.vf_gain_rad_per_px)
        elif module == LM:
            dtheta = self.module.step(theta_rad)
        elif o.vf_fallback == "sweep":
            dtheta = self._sweep.copy()
        else:
            dtheta = np.array(random_step(self.move_rng, self.step_rad))
        self._thetas.append(np.asarray(theta_rad, dtype=float))
        self._steps.append(dtheta)
        self._last_module = module
        if self.learning:
            self.learning_time_steps += 1
        return dtheta, module

    def _captured(self, det: Detections, theta_rad) -> int | None:
        """The object in view the module's line lands on (``line_capture_deg``), if any.

        :func:`~jointattention.agent.moves.line_capture` along the module's direction from
        the trial's start.
        """
        capture_rad = np.deg2rad(self.mechanisms.line_capture_deg)
        if capture_rad <= 0 or len(det.centre_px) == 0:
            return None
        u = self.module.direction(self._theta_start)
        (cx, cy), start = det.image_centre_px, self._theta_start
        i = line_capture(np.ascontiguousarray(det.centre_px, dtype=float), float(cx), float(cy),
                         float(self.mechanisms.vf_gain_rad_per_px), float(theta_rad[0]),
                         float(theta_rad[1]), float(start[0]), float(start[1]), float(u[0]),
                         float(u[1]), float(capture_rad))
        return i if i >= 0 else None

    def end_trial(self, outcome: Outcome) -> int:
        """Learn from the trial if the evaluator fired; returns what the module was taught.

        The network counts the samples taught, the other modules the places. A module that
        learns from a trial it drove that found nothing (``learns_unfound``) learns from it too.
        """
        if not self._learns(outcome):
            return self.module.learn_unfound() if self._learns_unfound(outcome) else 0
        self._measure(outcome)
        return self.module.learn(outcome, np.array(self._thetas), np.array(self._steps))

    @property
    def learns_unfound(self) -> bool:
        """Whether its module learns from a trial it drove that found nothing.

        A module says so by its ``learns_unfound`` (the population code's ``unfound``); one
        that does not say, a user's among them, does not.
        """
        return bool(getattr(self.module, "learns_unfound", False))

    def _learns_unfound(self, outcome: Outcome) -> bool:
        """Whether a trial teaches against its line: the module drove and nothing was found."""
        return (self.learning and not outcome.fired and self._last_module == LM
                and self.learns_unfound)

    def _learns(self, outcome: Outcome) -> bool:
        """Whether the trial teaches: Eq. 3 fired after a move (the last by VF if learn_from=vf)."""
        return (self.learning and outcome.fired and bool(self._thetas)
                and (self.options.learn_from == "every" or self._last_module == VF))
