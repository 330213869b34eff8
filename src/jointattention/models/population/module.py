"""The population-coded learning module of the bootstrap agent (``learner = "population"``).

Visual attention, the evaluator, the gate and the readings are the paper's
(:class:`~..bootstrap.BootstrapAgent`, which composes this module); the module is a
:class:`~.code.PopulationCode` over the robot's own features of the face window
(:mod:`.features`) and the head angle at the face. At the
start of a trial it reads out, from the caregiver's face, the direction in which she looks; its
command follows the line from the face in that direction, one step at a time (back toward the
line if another module moved the head off it), as the oracle follows the true gaze line.

A trial the evaluator ends teaches the direction, from the face, of the attended object's
place (and, with ``keep = "in_view"``, of every other object in the last image). The trial
is also kept in a replay memory (the face window's features, the head angle at the face and
the directions taught), from which ``replay`` trials drawn at random are taught again after each
trial: more updates from each trial the robot lived through.
"""

from __future__ import annotations

import numpy as np

from ...agent.face_standardiser import FaceStandardiser
from ...agent.moves import MAX_PLACES
from ...agent.protocol import Outcome
from ._trial import (
    KERNELS,
    InputSpec,
    PopulationArrays,
    commands_into,
    line_step,
    population_learn,
    trial_begin,
    unfound_learn,
)
from .code import PopulationCode
from .features import n_features

__all__ = ["PopulationModule", "line_step"]


def _parts(o) -> tuple[bool, bool]:
    """Whether the features hold the grey levels, and the gradient histogram (``o.features``)."""
    return o.features != "hog", o.features != "pixels"


class PopulationModule:
    """The bootstrap agent's learning module as a population code.

    Args:
        host: the bootstrap agent it serves (its body, options, head-angle scaling, step
            length and the trial's places).
        rng: the generator left after the agent's streams: split once more, for the
            population code's initial weights and the replay draws.

    It answers :class:`~..network.module.NetworkModule`'s calls, and declares its part of a
    trial as compiled kernels (:attr:`kernels`, over :meth:`compiled_state`; see
    :class:`~jointattention.agent.protocol.ModuleKernels`): its :meth:`begin`, :meth:`step`
    and :meth:`direction` call them too.

    Attributes:
        population: the learning module.
        direction_rad_: the direction read out for the current trial's face.
        replay_features_, replay_thetas_, replay_directions_, replay_counts_: the replay
            memory (the features of each face window, kept in whole grey levels, not
            standardised; head angles at the face; directions taught, how many each).
        n_kept_: trials kept in it so far (forgotten ones included).
    """

    MAX_PLACES = MAX_PLACES  # places taught per trial at most (objects in a scene: 20)
    kernels = KERNELS  # its part of a trial, for the compiled engine

    def __init__(self, host, rng: np.random.Generator):
        self.host = host
        options, body = host.options, host.body
        init_rng, self.replay_rng = rng.spawn(2)
        o = options.population
        self.n_features = self.view_features(o, body.face_size_px, body.eye_size_px)
        self.population = PopulationCode(self.n_features + 2, o, init_rng)
        self.feature_stats = FaceStandardiser(min_std=1e-3)  # with ``standardise``
        self.feature_stats.statistics(self.n_features)  # its arrays, which the kernels fill
        (w, h), (ew, eh) = body.face_size_px, body.eye_size_px or (0, 0)
        self.spec = InputSpec(h, w, eh, ew, o.cell_px, o.n_orientations, *_parts(o),
                              float(self.feature_stats.min_std),
                              np.asarray(host.theta_mid_rad, float),
                              np.asarray(host.theta_half_rad, float))
        n_in = self.n_features + 2
        self._x, self._features = np.empty(n_in), np.empty(self.n_features)
        self._score = np.empty(o.n_bins)
        self._trial, self._places = np.zeros(3), np.empty((self.MAX_PLACES, 2))
        self._replay_memory(0)  # sized when learning first needs it: a loaded model never does
        self.n_kept_ = 0

    def _replay_memory(self, capacity: int) -> None:
        """Make the replay memory's arrays, ``capacity`` trials long (zeros)."""
        self.replay_features_ = np.zeros((capacity, self.n_features))
        self.replay_thetas_ = np.zeros((capacity, 2))
        self.replay_directions_ = np.zeros((capacity, self.MAX_PLACES))
        self.replay_counts_ = np.zeros(capacity, np.int64)

    @staticmethod
    def view_features(o, face_size_px: tuple[int, int],
                      eye_size_px: tuple[int, int] | None = None) -> int:
        """The features of a view under population options ``o``.

        Each window's (:func:`~jointattention.models.population.features.n_features`): the face's,
        then the eyes' if kept.
        """
        return sum(n_features(size, o.cell_px, o.n_orientations, *_parts(o))
                   for size in (face_size_px, eye_size_px) if size)

    @classmethod
    def replay_bytes(cls, n_features: int, capacity: int) -> int:
        """The bytes of a full replay memory (see :meth:`_replay_memory`)."""
        return capacity * (n_features + 2 + cls.MAX_PLACES + 1) * 8

    def learning_only(self) -> tuple[np.ndarray, ...]:
        """The arrays that only learning reads (the replay memory): a frozen copy needs none."""
        return (self.replay_features_, self.replay_thetas_, self.replay_directions_,
                self.replay_counts_)

    def saved_arrays(self) -> dict[str, np.ndarray]:
        """The population code's members of a model file (``population_*``).

        The population code's weights are those its readout uses (the running averages, with
        ``average_rate`` > 0): a model file holds what the module does, not how it learns.
        """
        w1, b1, w2, b2 = self.population._readout_weights()
        f = self.feature_stats
        return {"population_w1": w1.T, "population_b1": b1,  # by hidden unit, as saved.py says
                "population_w2": w2, "population_b2": b2,
                "population_hidden_mean": self.population.hidden_mean_,
                **({"population_feature_mean": f.mean_, "population_feature_m2": f.m2_,
                    "population_feature_n_seen": np.array(f.n_seen_)}
                   if self.host.options.population.standardise else {})}

    def saved_shapes(self) -> dict[str, tuple[int, ...]]:
        """The shape of each member of :meth:`saved_arrays`."""
        p, n = self.population, self.n_features
        return {"population_w1": p.w1_.shape[::-1],
                "population_b1": p.b1_.shape, "population_w2": p.w2_.shape,
                "population_b2": p.b2_.shape, "population_hidden_mean": p.hidden_mean_.shape,
                **({"population_feature_mean": (n,), "population_feature_m2": (n,),
                    "population_feature_n_seen": ()} if self.host.options.population.standardise
                   else {})}

    def load_arrays(self, arrays: dict[str, np.ndarray]) -> None:
        """Set the population code's learned state from checked members of a model file."""
        p = self.population
        p.w1_, p.b1_, p.w2_, p.b2_, p.hidden_mean_ = (
            arrays[f"population_{k}"].astype(float)
            for k in ("w1", "b1", "w2", "b2", "hidden_mean"))
        p.w1_ = p.w1_.T.copy()  # input-major in memory (PopulationCode)
        p.averaged_ = [a.copy() for a in (p.w1_, p.b1_, p.w2_, p.b2_)]
        if self.host.options.population.standardise:
            f = self.feature_stats
            f.mean_ = arrays["population_feature_mean"].astype(float)
            f.m2_ = arrays["population_feature_m2"].astype(float)
            f.n_seen_ = int(arrays["population_feature_n_seen"])

    def arrays(self, n_faces: int = 0) -> PopulationArrays:
        """The module's state as the kernels take it (its own arrays; see ``sync``).

        It keeps nothing by face id: ``n_faces`` is not read.
        """
        o, p, f = self.host.options.population, self.population, self.feature_stats
        if self.host.learning and len(self.replay_counts_) < o.replay_capacity:
            self._replay_memory(o.replay_capacity)  # nothing kept yet: it was never learning
        return PopulationArrays(
            self.spec, p.kappa, float(o.learning_rate), float(o.hidden_rate),
            float(o.average_rate), p.readout_code, bool(o.standardise),
            o.keep == "in_view", int(o.replay), float(o.belief), p.w1_, p.b1_, p.w2_, p.b2_,
            *p.averaged_, *p._readout_weights(), p.hidden_mean_, f.mean_, f.m2_,
            self.replay_features_, self.replay_thetas_, self.replay_directions_,
            self.replay_counts_, self._x, self._features, p._h, p._p, p._grad_h, p._taught, p._z,
            self._score, np.array([self.n_kept_, p.n_taught_, f.n_seen_], np.int64),
            self._trial, self._places)

    compiled_state = arrays  # the state its kernels take

    @property
    def learn_rng(self) -> np.random.Generator:
        """The stream its ``learn`` kernel draws the replayed trials from."""
        return self.replay_rng

    @property
    def direction_rad_(self) -> float:
        """The direction read out for the current trial's face."""
        return float(self._trial[0])

    def sync(self, arrays: PopulationArrays) -> None:
        """Take back the counters the kernels moved (trials kept, places taught, faces fitted)."""
        self.n_kept_, self.population.n_taught_, self.feature_stats.n_seen_ = (
            int(c) for c in arrays.counters)

    def begin(self, face: np.ndarray, theta_rad: np.ndarray) -> None:
        """Read out the direction for the caregiver's face (a checked flat window)."""
        self._face = face
        a = self.arrays()
        trial_begin(a, face, -1, float(theta_rad[0]), float(theta_rad[1]), self.host.learning)
        self.sync(a)

    def observe(self, det, theta_rad) -> None:
        """Nothing: the module makes nothing of a step's view, and attention may take any."""

    def step(self, theta_rad) -> np.ndarray:
        """A step along the line from the face in the direction read out."""
        t = self._trial  # trial_direction's, without packing the state at every step
        return np.array(line_step(t[1], t[2], t[0], float(theta_rad[0]), float(theta_rad[1]),
                                  self.host.step_rad))

    def direction(self, theta_rad) -> np.ndarray:
        """The step along the line (it draws nothing): the gate's measure."""
        return self.step(theta_rad)

    def learn(self, outcome: Outcome, thetas: np.ndarray, steps: np.ndarray) -> int:
        """Teach the directions of the places found; returns how many.

        Then keep the trial in the replay memory and teach ``replay`` trials drawn from it
        (the kernel the compiled engine calls, :func:`~._trial.trial_learn`).
        """
        a = self.arrays()
        n = self.kernels.learn(a, *self.host.trial_end(outcome),
                               np.ascontiguousarray(thetas, dtype=float),
                               np.ascontiguousarray(steps, dtype=float), self.learn_rng)
        self.sync(a)
        return n

    @property
    def learns_unfound(self) -> bool:
        """Whether a trial it drove that found nothing teaches it (``population.unfound``)."""
        return bool(self.host.options.population.unfound)

    def learn_unfound(self) -> int:
        """Teach against the line of a trial that found nothing (:func:`~._trial.unfound_learn`).

        For the trial :meth:`begin` started; the compiled engine calls the same kernel through
        ``learn`` with no object seen.
        """
        a = self.arrays()
        n = unfound_learn(a, self._face, self.learn_rng)
        self.sync(a)
        return n

    def learn_places(self, places_rad: np.ndarray) -> int:
        """:meth:`learn` of the places found (n, 2), for the trial :meth:`begin` started."""
        a = self.arrays()
        n = population_learn(a, places_rad, self._face, float(self._trial[1]),
                             float(self._trial[2]), self.replay_rng)
        self.sync(a)
        return n

    def command(self, face: np.ndarray, theta_rad: np.ndarray) -> np.ndarray:
        """The first step from the face, for a checked flat face window and the head angle."""
        return self.commands(np.reshape(face, (1, -1)), np.reshape(theta_rad, (1, 2)))[0]

    def commands(self, faces: np.ndarray, thetas: np.ndarray) -> np.ndarray:
        """:meth:`command` for K checked flat face windows and head angles, (K, 2)."""
        out, a = np.empty((len(faces), 2)), self.arrays()
        commands_into(np.ascontiguousarray(faces, float), np.ascontiguousarray(thetas, float),
                      self.spec, a.feature_mean, a.feature_m2, a.counters[2] * a.standardise,
                      a.readout_w1, a.readout_b1, a.readout_w2, a.readout_b2, a.hidden_mean,
                      a.readout, float(self.host.step_rad), out)
        return out
