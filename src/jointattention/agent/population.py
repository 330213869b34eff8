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

Inputs are the robot's own features of the face window (:mod:`.face_features`) and the head
angle at the face. Kernels :func:`population_forward`, :func:`population_update` and
:func:`population_readout` are compiled; :class:`PopulationCode` is their scikit-learn-style
wrapper (``partial_fit`` on inputs and directions, ``predict`` a direction).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._arrays import floats, rows
from .._fields import Section, param
from .._jit import jit

__all__ = ["READOUTS", "PopulationCode", "PopulationOptions", "population_forward",
           "population_readout", "population_update", "von_mises_into"]

READOUTS = ("excess", "ratio", "mode")


@dataclass(frozen=True)
class PopulationOptions(Section):
    """The population code's options (``[model.population]``, with ``learner = "population"``)."""

    n_bins: int = param(72, "output units: directions around the face, evenly on the circle",
                        lo=8, hi=720)
    n_hidden: int = param(128, "hidden units (tanh) between the face features and the output",
                          lo=1, hi=1024)
    learning_rate: float = param(0.02, "step size of the cross-entropy gradient, per place "
                                 "taught", lo=0, hi=10)
    label_width_deg: float = param(
        5.0, "s.d. of the von Mises kernel that spreads a taught direction over nearby units",
        lo=0.1, hi=90)
    features: str = param(
        "pixels+hog", "the face's features: its contrast-normalised grey levels, a histogram "
        "of its gradient orientations, or both", choices=("pixels+hog", "pixels", "hog"))
    cell_px: int = param(5, "side of a cell of the gradient-orientation histogram (pixels)",
                         lo=2, hi=64)
    n_orientations: int = param(12, "signed orientation bins per histogram cell", lo=2, hi=36)
    standardise: bool = param(
        False, "centre and scale each feature by its running mean and s.d. over the faces "
        "seen (the histogram's features are all positive: uncentred inputs slow learning)")
    readout: str = param(
        "excess", "how the direction is read out: where p(direction | face) most exceeds "
        "p(direction | the average face) (excess), where its log does (ratio), or the plain "
        "mode of p(direction | face) (mode: no base rate)", choices=READOUTS)
    average_rate: float = param(
        0.002, "rate of the running average of the weights, per trial taught, that the "
        "readout uses (Polyak averaging: the noise of the last steps averaged out; 0: the "
        "weights themselves)", lo=0, hi=1)
    hidden_rate: float = param(0.01, "rate of the running mean of the hidden units over the "
                               "faces taught (the average face of the readout)", lo=0, hi=1)
    keep: str = param(
        "in_view", "places taught when the evaluator fires: the attended object's, or every "
        "object's in view then (the target is often in view when a distractor is attended)",
        choices=("attended", "in_view"))
    replay: int = param(8, "updates on trials drawn from the replay memory after each trial "
                        "taught (0: none)", lo=0, hi=100)
    replay_capacity: int = param(20_000, "trials the replay memory keeps (the oldest is "
                                 "forgotten)", lo=1, hi=10_000_000)


@jit
def von_mises_into(psi_rad: float, kappa: float, weight: float, out) -> None:
    """Add ``weight`` times a von Mises bump at ``psi_rad`` (summing to 1 over the units)."""
    n = len(out)
    total = 0.0
    for b in range(n):
        total += math.exp(kappa * (math.cos(2 * math.pi * b / n - psi_rad) - 1.0))
    for b in range(n):
        out[b] += weight * math.exp(kappa * (math.cos(2 * math.pi * b / n - psi_rad) - 1.0)) / total


@jit
def _softmax_into(z, p) -> None:
    top = -np.inf
    for b in range(len(z)):
        top = max(top, z[b])
    total = 0.0
    for b in range(len(z)):
        p[b] = math.exp(z[b] - top)
        total += p[b]
    for b in range(len(z)):
        p[b] /= total


@jit
def _output_into(h, w2, b2, z) -> None:
    """The output units' input ``z = w2 h + b2``."""
    for b in range(len(z)):
        s = b2[b]
        row = w2[b]
        for j in range(len(h)):
            s += row[j] * h[j]
        z[b] = s


@jit
def population_forward(x, w1, b1, w2, b2, h, p) -> None:
    """Hidden units ``h = tanh(w1 x + b1)`` and the softmax ``p`` of ``w2 h + b2``.

    Four hidden units at a time: each unit's sum runs over the inputs in the same order as
    one at a time (the same bits), but the four sums do not wait for each other.
    """
    n4 = len(h) - len(h) % 4
    for j in range(0, n4, 4):
        r0, r1, r2, r3 = w1[j], w1[j + 1], w1[j + 2], w1[j + 3]
        s0, s1, s2, s3 = b1[j], b1[j + 1], b1[j + 2], b1[j + 3]
        for i in range(len(x)):
            s0 += r0[i] * x[i]
            s1 += r1[i] * x[i]
            s2 += r2[i] * x[i]
            s3 += r3[i] * x[i]
        h[j], h[j + 1], h[j + 2], h[j + 3] = (math.tanh(s0), math.tanh(s1), math.tanh(s2),
                                              math.tanh(s3))
    for j in range(n4, len(h)):
        s = b1[j]
        row = w1[j]
        for i in range(len(x)):
            s += row[i] * x[i]
        h[j] = math.tanh(s)
    _output_into(h, w2, b2, p)
    _softmax_into(p, p)


@jit
def population_update(x, taught, n_taught: float, w1, b1, w2, b2, learning_rate: float, h, p,
                      grad_h) -> None:
    """One gradient step on the summed cross-entropy of ``n_taught`` places for input ``x``.

    ``taught`` is the sum of their spread directions; the gradient at the output units' input
    is ``n_taught p - taught``.
    """
    population_forward(x, w1, b1, w2, b2, h, p)
    grad_h[:] = 0.0
    for b in range(len(p)):
        g = n_taught * p[b] - taught[b]
        row = w2[b]
        for j in range(len(h)):
            grad_h[j] += g * row[j]
            row[j] -= learning_rate * g * h[j]
        b2[b] -= learning_rate * g
    for j in range(len(h)):
        g = grad_h[j] * (1.0 - h[j] * h[j]) * learning_rate
        row = w1[j]
        for i in range(len(x)):
            row[i] -= g * x[i]
        b1[j] -= g


@jit
def population_readout(score) -> tuple[float, float]:
    """The direction (rad) of the largest ``score`` over the units, and that score.

    The direction is the circular mean of the best unit and its two neighbours on each side,
    weighted by how far their scores exceed the fifth best (finer than a unit).
    """
    n = len(score)
    best = 0
    for b in range(n):
        if score[b] > score[best]:
            best = b
    floor = np.sort(score)[max(n - 5, 0)]
    s = c = 0.0
    for d in range(-2, 3):
        b = (best + d) % n
        w = max(score[b] - floor, 0.0) + 1e-12
        angle = 2 * math.pi * b / n
        s += w * math.sin(angle)
        c += w * math.cos(angle)
    return math.atan2(s, c), score[best]


class PopulationCode:
    """The population-coded network (see the module docstring).

    Args:
        n_in: input length (face features and the scaled head angle).
        options: units, learning rate, label width, readout.
        rng: draws the initial weights.

    Learned state: ``w1_`` (n_hidden, n_in), ``b1_``, ``w2_`` (n_bins, n_hidden), ``b2_``,
    ``averaged_`` (their running averages, which the readout uses; :meth:`average`),
    ``hidden_mean_`` (n_hidden,: the running mean of the hidden units over the inputs taught)
    and ``n_taught_`` (places taught).
    """

    def __init__(self, n_in: int, options: PopulationOptions, rng: np.random.Generator):
        self.options = options
        h, n = options.n_hidden, options.n_bins
        self.w1_ = rng.normal(0.0, 1.0 / math.sqrt(n_in), (h, n_in))
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
        rate = self.options.average_rate
        for a, w in zip(self.averaged_, (self.w1_, self.b1_, self.w2_, self.b2_), strict=True):
            a += rate * (w - a)

    def probabilities(self, x: np.ndarray) -> np.ndarray:
        """p(direction | input) over the units, for one input (n_in,), by the readout weights."""
        population_forward(floats("x", x, (self.w1_.shape[1],)), *self._readout_weights(),
                           self._h, self._p)
        return self._p.copy()

    def scores(self, x: np.ndarray) -> np.ndarray:
        """The readout's score of each unit for one input (see ``options.readout``)."""
        p = self.probabilities(x)
        readout = self.options.readout
        if readout == "mode":
            return p
        _, _, w2, b2 = self._readout_weights()
        _output_into(self.hidden_mean_, w2, b2, self._z)
        if readout == "ratio":  # log p - log p(average face): the normalisers do not matter
            return w2 @ self._h - w2 @ self.hidden_mean_
        _softmax_into(self._z, self._z)
        return p - self._z

    def direction(self, x: np.ndarray) -> tuple[float, float]:
        """The readout direction (rad) for one input, and its score."""
        return population_readout(self.scores(x))

    def teach(self, x: np.ndarray, directions_rad) -> None:
        """One update toward the places found in ``directions_rad`` (rad) for input ``x``."""
        self._teach(floats("x", x, (self.w1_.shape[1],)),
                    floats("directions_rad", directions_rad, None).reshape(-1))

    def _teach(self, x: np.ndarray, directions_rad: np.ndarray) -> None:
        """:meth:`teach` on checked arrays: ``x`` (n_in,) and ``directions_rad`` 1-D floats."""
        if len(directions_rad) == 0:
            return
        self._taught[:] = 0.0
        for psi in directions_rad:
            von_mises_into(float(psi), self.kappa, 1.0, self._taught)
        population_update(x, self._taught,
                          float(len(directions_rad)), self.w1_, self.b1_, self.w2_, self.b2_,
                          float(self.options.learning_rate), self._h, self._p, self._grad_h)
        self.hidden_mean_ += self.options.hidden_rate * (self._h - self.hidden_mean_)
        self.n_taught_ += len(directions_rad)

    def partial_fit(self, X: np.ndarray, Y: np.ndarray) -> PopulationCode:
        """One update per row: inputs ``X`` (n, n_in), one direction (rad) each ``Y`` (n,).

        The running averages move once per row.
        """
        X = rows("X", X, self.w1_.shape[1])
        for x, y in zip(X, floats("Y", Y, (len(X),)), strict=True):
            self.teach(x, [y])
            self.average()
        return self

    def predict(self, X: np.ndarray) -> np.ndarray:
        """The readout direction (rad) for each row of ``X`` (n, n_in), (n,)."""
        return np.array([self.direction(x)[0] for x in rows("X", X, self.w1_.shape[1])])
