"""The population-coded learning module of the bootstrap agent (``learner = "population"``).

Visual attention, the evaluator, the gate and the readings are the paper's
(:class:`~.bootstrap.BootstrapAgent`, which composes this module); the module is a
:class:`~jointattention.agent.population.PopulationCode` over the robot's own features of the
face window (:mod:`jointattention.agent.face_features`) and the head angle at the face. At the
start of a trial it reads out, from the caregiver's face, the direction in which she looks; its
command follows the line from the face in that direction, one step at a time (back toward the
line if another module moved the head off it), as the oracle follows the true gaze line.

A trial the evaluator ends teaches the direction, from the face, of the attended object's
place (and, with ``keep = "in_view"``, of every other object in the last image). The trial
is also kept in a replay memory (the face window, the head angle at the face and the
directions taught), from which ``replay`` trials drawn at random are taught again after each
trial: more updates from each trial the robot lived through.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .._jit import jit
from ..agent.face_features import face_features_into, n_features
from ..agent.learner import FaceStandardiser, standardise
from ..agent.moves import scale_angle_into, unit_step
from ..agent.population import (
    PopulationCode,
    population_readout,
    population_scores_into,
    population_teach,
)
from ..agent.protocol import Outcome

__all__ = ["InputSpec", "PopulationModule", "commands_into", "line_step", "module_input_into",
           "replay_into"]


class InputSpec(NamedTuple):
    """How the module's input is made from a face window and a head angle (for the kernels)."""

    height: int
    width: int
    cell_px: int
    n_orientations: int
    pixels: bool
    hog: bool
    min_std: float  # of the features' standardiser
    theta_mid_rad: np.ndarray
    theta_half_rad: np.ndarray


@jit
def module_input_into(face, pan, tilt, spec, mean, m2, n_seen, x, tmp) -> None:
    """The module's input ``x``: the window's features, then the scaled head angle.

    The features are standardised by ``mean``, ``m2`` of ``n_seen`` faces if ``n_seen`` > 0
    (pass 0 to leave them as they are). ``tmp`` holds the features meanwhile.
    """
    n = len(x) - 2
    face_features_into(face, spec.height, spec.width, spec.cell_px, spec.n_orientations,
                       spec.pixels, spec.hog, x)
    if n_seen > 0:
        for i in range(n):
            tmp[i] = x[i]
        standardise(tmp[:n], mean, m2, n_seen, spec.min_std, x[:n])
    scale_angle_into(pan, tilt, spec.theta_mid_rad, spec.theta_half_rad, x, n)


@jit
def commands_into(faces, thetas, spec, mean, m2, n_seen, w1, b1, w2, b2, hidden_mean,
                  readout, step_rad, out) -> None:
    """The first step from each face (K, pixels) at its head angle (K, 2): ``out`` (K, 2)."""
    x, tmp = np.empty(len(w1[0])), np.empty(len(w1[0]))
    h, p, z, score = np.empty(len(b1)), np.empty(len(b2)), np.empty(len(b2)), np.empty(len(b2))
    for k in range(len(faces)):
        module_input_into(faces[k], thetas[k, 0], thetas[k, 1], spec, mean, m2, n_seen, x, tmp)
        population_scores_into(x, w1, b1, w2, b2, hidden_mean, readout, h, p, z, score)
        psi, _ = population_readout(score)
        out[k, 0], out[k, 1] = step_rad * math.cos(psi), step_rad * math.sin(psi)


@jit
def replay_into(drawn, faces, thetas, directions, counts, spec, mean, m2, n_seen, kappa, w1,
                b1, w2, b2, learning_rate, hidden_mean, hidden_rate, h, p, grad_h,
                taught) -> int:
    """Teach again the kept trials ``drawn`` (replay memory rows); the places taught."""
    x, tmp, face = np.empty(len(w1[0])), np.empty(len(w1[0])), np.empty(faces.shape[1])
    n_taught = 0
    for i in drawn:
        for j in range(len(face)):
            face[j] = faces[i, j]
        module_input_into(face, thetas[i, 0], thetas[i, 1], spec, mean, m2, n_seen, x, tmp)
        population_teach(x, directions[i, : counts[i]], kappa, w1, b1, w2, b2, learning_rate,
                         hidden_mean, hidden_rate, h, p, grad_h, taught)
        n_taught += counts[i]
    return n_taught


@jit
def line_step(start_pan, start_tilt, psi_rad, pan, tilt, step_rad) -> tuple[float, float]:
    """One step along the line from ``start`` in direction ``psi_rad``, from the head angle now.

    It aims one step beyond the head's projection on the line (never behind the start), so
    a head on the line moves along it and a head off it turns back toward it.
    """
    u0, u1 = math.cos(psi_rad), math.sin(psi_rad)
    s = max((pan - start_pan) * u0 + (tilt - start_tilt) * u1, 0.0) + step_rad
    return unit_step(start_pan + s * u0 - pan, start_tilt + s * u1 - tilt, step_rad)


class PopulationModule:
    """The bootstrap agent's learning module as a population code.

    Args:
        host: the bootstrap agent it serves (its body, options, head-angle scaling, step
            length and the trial's places).
        rng: the generator left after the agent's streams: split once more, for the
            population code's initial weights and the replay draws.

    It answers :class:`~.network.NetworkModule`'s calls.

    Attributes:
        population: the learning module.
        direction_rad_: the direction read out for the current trial's face.
        replay_faces_, replay_thetas_, replay_directions_, replay_counts_: the replay memory
            (face windows, head angles at the face, directions taught, how many each).
        n_kept_: trials kept in it so far (forgotten ones included).
    """

    MAX_PLACES = 20  # places taught per trial at most (objects in a scene: 20)

    def __init__(self, host, rng: np.random.Generator):
        self.host = host
        options, body = host.options, host.body
        init_rng, self.replay_rng = rng.spawn(2)
        o = options.population
        self._parts = (o.features != "hog", o.features != "pixels")
        self.n_features = n_features(body.face_size_px, o.cell_px, o.n_orientations,
                                     *self._parts)
        self.population = PopulationCode(self.n_features + 2, o, init_rng)
        self.feature_stats = FaceStandardiser(min_std=1e-3)  # with ``standardise``
        w, h = body.face_size_px
        self.spec = InputSpec(h, w, o.cell_px, o.n_orientations, *self._parts,
                              float(self.feature_stats.min_std),
                              np.asarray(host.theta_mid_rad, float),
                              np.asarray(host.theta_half_rad, float))
        self._no_stats = np.zeros(self.n_features)
        self.direction_rad_ = 0.0
        self.replay_faces_ = np.zeros((o.replay_capacity, h * w), np.uint8)
        self.replay_thetas_ = np.zeros((o.replay_capacity, 2))
        self.replay_directions_ = np.zeros((o.replay_capacity, self.MAX_PLACES))
        self.replay_counts_ = np.zeros(o.replay_capacity, np.int64)
        self.n_kept_ = 0

    def saved_arrays(self) -> dict[str, np.ndarray]:
        """The population code's members of a model file (``population_*``).

        The population code's weights are those its readout uses (the running averages, with
        ``average_rate`` > 0): a model file holds what the module does, not how it learns.
        """
        w1, b1, w2, b2 = self.population._readout_weights()
        f = self.feature_stats
        return {"population_w1": w1, "population_b1": b1,
                "population_w2": w2, "population_b2": b2,
                "population_hidden_mean": self.population.hidden_mean_,
                **({"population_feature_mean": f.mean_, "population_feature_m2": f.m2_,
                    "population_feature_n_seen": np.array(f.n_seen_)}
                   if self.host.options.population.standardise else {})}

    def saved_shapes(self) -> dict[str, tuple[int, ...]]:
        """The shape of each member of :meth:`saved_arrays`."""
        p, n = self.population, self.n_features
        return {"population_w1": p.w1_.shape,
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
        p.averaged_ = [a.copy() for a in (p.w1_, p.b1_, p.w2_, p.b2_)]
        if self.host.options.population.standardise:
            f = self.feature_stats
            f.mean_ = arrays["population_feature_mean"].astype(float)
            f.m2_ = arrays["population_feature_m2"].astype(float)
            f.n_seen_ = int(arrays["population_feature_n_seen"])

    def _stats(self) -> tuple:
        """The features' standardiser as the kernels take it: mean, m2, faces seen.

        0 faces seen (no standardising) without ``standardise`` or before the first face.
        """
        f = self.feature_stats
        if not self.host.options.population.standardise or not f.n_seen_:
            return self._no_stats, self._no_stats, 0
        return f.mean_, f.m2_, f.n_seen_

    def _features(self, window: np.ndarray, theta_rad: np.ndarray, fit: bool = False
                  ) -> np.ndarray:
        """The module's input: a checked window's features (H * W floats) and the head angle.

        The head angle (2,) is scaled by the joint ranges. With ``standardise`` the face
        features are standardised by their running statistics; ``fit`` adds this face's
        features to those statistics first.
        """
        x, tmp = np.empty(self.n_features + 2), np.empty(self.n_features + 2)
        pan, tilt = float(theta_rad[0]), float(theta_rad[1])
        if fit and self.host.options.population.standardise:
            module_input_into(window, pan, tilt, self.spec, self._no_stats, self._no_stats, 0,
                              x, tmp)
            self.feature_stats.partial_fit(x[: self.n_features])
        module_input_into(window, pan, tilt, self.spec, *self._stats(), x, tmp)
        return x

    def begin(self, face: np.ndarray, theta_rad: np.ndarray) -> None:
        """Read out the direction for the caregiver's face (a checked flat window)."""
        self._x = self._features(face, theta_rad, fit=self.host.learning)
        self._face, self._theta_start = face, theta_rad
        self.direction_rad_, _ = self.population.direction(self._x)

    def step(self, theta_rad) -> np.ndarray:
        """A step along the line from the face in the direction read out."""
        s = self._theta_start
        return np.array(line_step(s[0], s[1], self.direction_rad_, float(theta_rad[0]),
                                  float(theta_rad[1]), self.host.step_rad))

    def direction(self, theta_rad) -> np.ndarray:
        """The step along the line (it draws nothing): the gate's measure."""
        return self.step(theta_rad)

    def learn(self, outcome: Outcome, thetas: np.ndarray, steps: np.ndarray) -> int:
        """Teach the directions of the places found; returns how many.

        Then keep the trial in the replay memory and teach ``replay`` trials drawn from it.
        """
        host = self.host
        places = [host.aim_of(outcome)]
        if host.options.population.keep == "in_view":
            places += [host.place_of(outcome, i) for i in range(len(outcome.detections))
                       if i != outcome.seen]
        d = np.array(places[: self.MAX_PLACES]) - self._theta_start
        directions = np.arctan2(d[:, 1], d[:, 0])
        self.population._teach(self._x, directions)
        self._keep(directions)
        self._replay()
        self.population.average()
        return len(directions)

    def command(self, face: np.ndarray, theta_rad: np.ndarray) -> np.ndarray:
        """The first step from the face, for a checked flat face window and the head angle."""
        return self.commands(np.reshape(face, (1, -1)), np.reshape(theta_rad, (1, 2)))[0]

    def commands(self, faces: np.ndarray, thetas: np.ndarray) -> np.ndarray:
        """:meth:`command` for K checked flat face windows and head angles, (K, 2)."""
        out = np.empty((len(faces), 2))
        p = self.population
        commands_into(np.ascontiguousarray(faces, float), np.ascontiguousarray(thetas, float),
                      self.spec, *self._stats(), *p._readout_weights(), p.hidden_mean_,
                      p.readout_code, float(self.host.step_rad), out)
        return out

    def _keep(self, directions: np.ndarray) -> None:
        """Keep the trial in the replay memory, forgetting the oldest when it is full."""
        slot = self.n_kept_ % len(self.replay_counts_)
        self.replay_faces_[slot] = np.clip(np.rint(self._face), 0, 255).ravel()
        self.replay_thetas_[slot] = self._theta_start
        self.replay_directions_[slot, : len(directions)] = directions
        self.replay_counts_[slot] = len(directions)
        self.n_kept_ += 1

    def _replay(self) -> None:
        """Teach ``replay`` trials drawn at random from the replay memory."""
        n = min(self.n_kept_, len(self.replay_counts_))
        drawn = self.replay_rng.integers(n, size=self.host.options.population.replay)
        p = self.population
        # the memory holds checked windows and angles: no door to pass again
        p.n_taught_ += replay_into(drawn, self.replay_faces_, self.replay_thetas_,
                                   self.replay_directions_, self.replay_counts_, self.spec,
                                   *self._stats(), p.kappa, *p.teach_arrays())
