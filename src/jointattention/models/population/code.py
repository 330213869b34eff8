"""A population-coded learning module: where, around the face, objects are found for a face.

The paper's module regresses one direction on the face (squared error): with n objects it
learns the *mean* of the directions the robot was taught, which with 10 objects points between
the distractors (docs/beyond-the-paper.md). The episodic memory finds the *mode* instead, but
it recalls the places of the faces it kept: a lookup that does not carry over to a caregiver
it never saw.

This module learns the whole distribution and reads out its mode, with a network that
generalises. Its output is a population code (as in motor and head-direction cells): one unit
per direction around the caregiver's face, ``n_bins`` of them on the circle. A softmax over
them is trained by cross-entropy on the directions, from the face, of the places the robot
found (each spread over nearby units by a von Mises kernel of ``label_width_deg``), so that it
estimates p(direction | face). Distractors fall in every direction for every face; the
caregiver's target falls in the direction she looks. The readout (``excess``) is the
direction whose probability for this face most exceeds its probability for the average face
(the module's own output at the running mean of its hidden units): the target, not the mean.

Inputs are the robot's own features of the face window (:mod:`.features`) and the head
angle at the face. The kernels (:func:`population_forward`, :func:`population_teach_rows`,
:func:`population_scores_into`, :func:`population_readout`, ...) are compiled, in
:mod:`._forward` (the forward pass and readout) and :mod:`._teaching`
(the learning step); :class:`PopulationCode` is their scikit-learn-style wrapper
(``partial_fit`` on inputs and directions, ``predict`` a direction).
"""

from __future__ import annotations

import math

import numpy as np

from ..._arrays import floats, rows
from ._forward import (
    EXCESS,
    average_face_into,
    population_activate,
    population_forward,
    population_hidden_into,
    population_readout,
    population_scores_into,
    scores_of_output_into,
)
from ._teaching import (
    average_into,
    population_teach,
    population_teach_rows,
    population_update,
    von_mises_into,
)
from .options import READOUTS, PopulationOptions

__all__ = ["EXCESS", "PopulationCode", "average_face_into",
           "population_activate", "population_forward", "population_hidden_into",
           "population_readout", "population_scores_into", "population_teach",
           "population_teach_rows", "population_update", "scores_of_output_into",
           "von_mises_into"]

class PopulationCode:
    """The population-coded network (see the module docstring).

    Args:
        n_in: input length (face features and the scaled head angle).
        options: units, learning rate, label width, readout.
        rng: draws the initial weights.

    Learned state: ``w1_`` (n_in, n_hidden: input-major, as scikit-learn's ``coefs_``),
    ``b1_``, ``w2_`` (n_bins, n_hidden), ``b2_``,
    ``averaged_`` (their running averages, which the readout uses; :meth:`average`),
    ``hidden_mean_`` (n_hidden,: the running mean of the hidden units over the inputs taught)
    and ``n_taught_`` (places taught).
    """

    def __init__(self, n_in: int, options: PopulationOptions, rng: np.random.Generator):
        self.options = options
        h, n = options.n_hidden, options.n_bins
        self.w1_ = rng.normal(0.0, 1.0 / math.sqrt(n_in), (h, n_in)).T.copy()  # draws by unit
        self.b1_ = np.zeros(h)
        self.w2_ = rng.normal(0.0, 1.0 / math.sqrt(h), (n, h))
        self.b2_ = np.zeros(n)
        self.averaged_ = [self.w1_.copy(), self.b1_.copy(), self.w2_.copy(), self.b2_.copy()]
        self.hidden_mean_ = np.zeros(h)
        self.n_taught_ = 0
        self._h, self._p, self._grad_h = np.empty(h), np.empty(n), np.empty(h)
        self._taught, self._z = np.empty(n), np.empty(n)

    @property
    def kappa(self) -> float:
        """Concentration of the von Mises kernel of ``label_width_deg``."""
        return 1.0 / math.radians(self.options.label_width_deg) ** 2

    def _readout_weights(self) -> list[np.ndarray]:
        """The weights the readout uses: the running averages, or the weights themselves."""
        if self.options.average_rate > 0:
            return self.averaged_
        return [self.w1_, self.b1_, self.w2_, self.b2_]

    def average(self) -> None:
        """Move the running averages of the weights toward the weights (once per trial)."""
        rate = float(self.options.average_rate)
        for a, w in zip(self.averaged_, (self.w1_, self.b1_, self.w2_, self.b2_), strict=True):
            average_into(a.reshape(-1), w.reshape(-1), rate)  # views: the arrays are contiguous

    @property
    def readout_code(self) -> int:
        """``options.readout`` as the kernels take it (its place in :data:`READOUTS`)."""
        return READOUTS.index(self.options.readout)

    def probabilities(self, x: np.ndarray) -> np.ndarray:
        """p(direction | input) over the units, for one input (n_in,), by the readout weights."""
        population_forward(floats("x", x, (len(self.w1_),)), *self._readout_weights(),
                           self._h, self._p)
        return self._p.copy()

    def scores(self, x: np.ndarray) -> np.ndarray:
        """The readout's score of each unit for one input (see ``options.readout``)."""
        score = np.empty(len(self.b2_))
        population_scores_into(floats("x", x, (len(self.w1_),)), *self._readout_weights(),
                               self.hidden_mean_, self.readout_code, self._h, self._p, self._z,
                               score)
        return score

    def direction(self, x: np.ndarray) -> tuple[float, float]:
        """The readout direction (rad) for one input, and its score."""
        return population_readout(self.scores(x))

    def teach(self, x: np.ndarray, directions_rad) -> None:
        """One update toward the places found in ``directions_rad`` (rad) for input ``x``."""
        self._teach(floats("x", x, (len(self.w1_),)),
                    floats("directions_rad", directions_rad, None).reshape(-1))

    def _teach(self, x: np.ndarray, directions_rad: np.ndarray) -> None:
        """:meth:`teach` on checked arrays: ``x`` (n_in,) and ``directions_rad`` 1-D floats."""
        population_teach(x, directions_rad, self.kappa, *self.teach_arrays())
        self.n_taught_ += len(directions_rad)

    def teach_arrays(self) -> tuple:
        """What :func:`population_teach` takes after the input, directions and ``kappa``."""
        o = self.options
        return (self.w1_, self.b1_, self.w2_, self.b2_, float(o.learning_rate),
                self.hidden_mean_, float(o.hidden_rate), self._h, self._p, self._grad_h,
                self._taught, float(o.belief), self._z)

    def partial_fit(self, X: np.ndarray, Y: np.ndarray) -> PopulationCode:
        """One update per row: inputs ``X`` (n, n_in), one direction (rad) each ``Y`` (n,).

        The running averages move once per row.
        """
        X = rows("X", X, len(self.w1_))
        for x, y in zip(X, floats("Y", Y, (len(X),)), strict=True):
            self.teach(x, [y])
            self.average()
        return self

    def predict(self, X: np.ndarray) -> np.ndarray:
        """The readout direction (rad) for each row of ``X`` (n, n_in), (n,)."""
        return np.array([self.direction(x)[0] for x in rows("X", X, len(self.w1_))])
