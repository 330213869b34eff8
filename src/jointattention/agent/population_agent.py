"""The bootstrap agent with the population-coded learning module (``learner = "population"``).

Visual attention, the evaluator, the gate and the readings are the paper's
(:class:`~.bootstrap.BootstrapAgent`); the learning module is a
:class:`~.population.PopulationCode` over the robot's own features of the face window
(:mod:`.face_features`) and the head angle at the face. At the start of a trial it reads out,
from the caregiver's face, the direction in which she looks; its command follows the line from
the face in that direction, one step at a time (back toward the line if another module moved
the head off it), as the oracle follows the true gaze line.

A trial the evaluator ends teaches the direction, from the face, of the attended object's
place (and, with ``keep = "in_view"``, of every other object in the last image). The trial
is also kept in a replay memory (the face window, the head angle at the face and the
directions taught), from which ``replay`` trials drawn at random are taught again after each
trial: more updates from each trial the robot lived through.
"""

from __future__ import annotations

import math

import numpy as np

from .._arrays import angles, windows
from .._jit import jit
from .bootstrap import BootstrapAgent, BootstrapOptions
from .face_features import face_features_into, n_features
from .learner import FaceStandardiser, standardise
from .moves import scale_angle_into, unit_step
from .population import PopulationCode
from .protocol import Body, Outcome

__all__ = ["PopulationAgent", "line_step"]


@jit
def line_step(start_pan, start_tilt, psi_rad, pan, tilt, step_rad) -> tuple[float, float]:
    """One step along the line from ``start`` in direction ``psi_rad``, from the head angle now.

    It aims one step beyond the head's projection on the line (never behind the start), so
    a head on the line moves along it and a head off it turns back toward it.
    """
    u0, u1 = math.cos(psi_rad), math.sin(psi_rad)
    s = max((pan - start_pan) * u0 + (tilt - start_tilt) * u1, 0.0) + step_rad
    return unit_step(start_pan + s * u0 - pan, start_tilt + s * u1 - tilt, step_rad)


class PopulationAgent(BootstrapAgent):
    """The bootstrap agent whose learning module is a population code.

    Args are :class:`~.bootstrap.BootstrapAgent`'s; ``rng`` is split once more, after the
    bootstrap agent's streams, for the population code's initial weights and the replay draws.

    Attributes:
        population: the learning module.
        direction_rad_: the direction read out for the current trial's face.
        replay_faces_, replay_thetas_, replay_directions_, replay_counts_: the replay memory
            (face windows, head angles at the face, directions taught, how many each).
        n_kept_: trials kept in it so far (forgotten ones included).
    """

    MAX_PLACES = 20  # places taught per trial at most (objects in a scene: 20)

    def __init__(self, options: BootstrapOptions, agent, body: Body, rng: np.random.Generator):
        super().__init__(options, agent, body, rng)
        init_rng, self.replay_rng = rng.spawn(2)
        o = options.population
        self._parts = (o.features != "hog", o.features != "pixels")
        self.n_features = n_features(body.face_size_px, o.cell_px, o.n_orientations,
                                     *self._parts)
        self.population = PopulationCode(self.n_features + 2, o, init_rng)
        self.feature_stats = FaceStandardiser(min_std=1e-3)  # with ``standardise``
        self.direction_rad_ = 0.0
        w, h = body.face_size_px
        self.replay_faces_ = np.zeros((o.replay_capacity, h * w), np.uint8)
        self.replay_thetas_ = np.zeros((o.replay_capacity, 2))
        self.replay_directions_ = np.zeros((o.replay_capacity, self.MAX_PLACES))
        self.replay_counts_ = np.zeros(o.replay_capacity, np.int64)
        self.n_kept_ = 0

    def saved_arrays(self) -> dict[str, np.ndarray]:
        """The bootstrap agent's members and the population code's (``population_*``).

        The population code's weights are those its readout uses (the running averages, with
        ``average_rate`` > 0): a model file holds what the module does, not how it learns.
        """
        w1, b1, w2, b2 = self.population._readout_weights()
        f = self.feature_stats
        return {**super().saved_arrays(), "population_w1": w1, "population_b1": b1,
                "population_w2": w2, "population_b2": b2,
                "population_hidden_mean": self.population.hidden_mean_,
                **({"population_feature_mean": f.mean_, "population_feature_m2": f.m2_,
                    "population_feature_n_seen": np.array(f.n_seen_)}
                   if self.options.population.standardise else {})}

    def saved_shapes(self) -> dict[str, tuple[int, ...]]:
        """The shape of each member of :meth:`saved_arrays`."""
        p, n = self.population, self.n_features
        return {**super().saved_shapes(), "population_w1": p.w1_.shape,
                "population_b1": p.b1_.shape, "population_w2": p.w2_.shape,
                "population_b2": p.b2_.shape, "population_hidden_mean": p.hidden_mean_.shape,
                **({"population_feature_mean": (n,), "population_feature_m2": (n,),
                    "population_feature_n_seen": ()} if self.options.population.standardise
                   else {})}

    def load_arrays(self, arrays: dict[str, np.ndarray]) -> None:
        """Set the learned state from checked members of a model file."""
        super().load_arrays(arrays)
        p = self.population
        p.w1_, p.b1_, p.w2_, p.b2_, p.hidden_mean_ = (
            arrays[f"population_{k}"].astype(float)
            for k in ("w1", "b1", "w2", "b2", "hidden_mean"))
        p.averaged_ = [a.copy() for a in (p.w1_, p.b1_, p.w2_, p.b2_)]
        if self.options.population.standardise:
            f = self.feature_stats
            f.mean_ = arrays["population_feature_mean"].astype(float)
            f.m2_ = arrays["population_feature_m2"].astype(float)
            f.n_seen_ = int(arrays["population_feature_n_seen"])

    def features(self, face_window: np.ndarray, theta_rad, *, fit: bool = False) -> np.ndarray:
        """The module's input: the face window's features and the head angle, scaled.

        With ``standardise`` the face features are standardised by their running statistics;
        ``fit`` adds this face's features to those statistics first.
        """
        window = windows("face_window", face_window, self.body.face_size_px).ravel()
        return self._features(window, angles("theta_rad", theta_rad), fit)

    def _features(self, window: np.ndarray, theta_rad: np.ndarray, fit: bool = False
                  ) -> np.ndarray:
        """:meth:`features` of a checked window (H * W floats) and head angle (2,)."""
        o = self.options.population
        w, h = self.body.face_size_px
        x = np.empty(self.n_features + 2)
        face = x[: self.n_features]
        face_features_into(window, h, w, o.cell_px, o.n_orientations, *self._parts, x)
        if o.standardise:
            f = self.feature_stats
            if fit:
                f.partial_fit(face)
            if f.n_seen_:
                standardise(face.copy(), f.mean_, f.m2_, f.n_seen_, f.min_std, face)
        scale_angle_into(float(theta_rad[0]), float(theta_rad[1]), self.theta_mid_rad,
                         self.theta_half_rad, x, self.n_features)
        return x

    def lm_command(self, face_window: np.ndarray, theta_rad) -> np.ndarray:
        """The module's first step from the face, for a face window and the head angle there."""
        psi, _ = self.population.direction(self.features(face_window, theta_rad))
        return self.step_rad * np.array([math.cos(psi), math.sin(psi)])

    def lm_commands(self, face_windows: np.ndarray, thetas_rad: np.ndarray) -> np.ndarray:
        """:meth:`lm_command` for K face windows (K, H, W) and head angles (K, 2), (K, 2)."""
        faces = windows("face_windows", face_windows, self.body.face_size_px, None)
        thetas = angles("thetas_rad", thetas_rad, len(faces))
        return np.array([self.lm_command(f, t) for f, t in zip(faces, thetas, strict=True)]
                        ).reshape(-1, 2)

    def begin_trial(self, face_window: np.ndarray, theta_rad) -> None:
        """Read out the direction for the caregiver's face, then start as the paper does."""
        self._x = self.features(face_window, theta_rad, fit=self.learning)
        self._face = np.asarray(face_window)
        self.direction_rad_, _ = self.population.direction(self._x)
        super().begin_trial(face_window, theta_rad)

    def _lm(self, face_part, theta_rad) -> np.ndarray:
        """A step along the line from the face in the direction read out."""
        s = self._theta_start
        return np.array(line_step(s[0], s[1], self.direction_rad_, float(theta_rad[0]),
                                  float(theta_rad[1]), self.step_rad))

    def _lm_direction(self, theta_rad) -> np.ndarray:
        return self._lm(None, theta_rad)

    def end_trial(self, outcome: Outcome) -> int:
        """Teach the directions of the places found if the evaluator fired; returns how many.

        Then keep the trial in the replay memory and teach ``replay`` trials drawn from it.
        """
        if not self._learns(outcome):
            return 0
        self._measure(outcome)
        places = [self._aim(outcome)]
        if self.options.population.keep == "in_view":
            places += [self._place_of(outcome, i) for i in range(len(outcome.detections))
                       if i != outcome.seen]
        d = np.array(places[: self.MAX_PLACES]) - self._theta_start
        directions = np.arctan2(d[:, 1], d[:, 0])
        self.population._teach(self._x, directions)
        self._keep(directions)
        self._replay()
        self.population.average()
        return len(directions)

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
        for i in self.replay_rng.integers(n, size=self.options.population.replay):
            # the memory holds checked windows and angles: no door to pass again
            x = self._features(self.replay_faces_[i].astype(float), self.replay_thetas_[i])
            self.population._teach(x, self.replay_directions_[i, : self.replay_counts_[i]])
