"""The learning module: a three-layer network trained by back-propagation (paper, III-D).

Inputs are the caregiver's face window (standardised with statistics of the faces the robot
has seen) and the head angle (scaled by the robot's own joint ranges); outputs are a motor
command in units of one step. The interface follows scikit-learn: ``partial_fit`` and
``predict`` on 2-D arrays, learned state in attributes ending in ``_``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["FaceStandardiser", "LearningModule"]


class FaceStandardiser:
    """Per-pixel running mean and standard deviation of the faces seen (Welford)."""

    def __init__(self, min_std: float = 8.0):
        self.min_std = min_std
        self.n_seen_ = 0

    def partial_fit(self, faces: np.ndarray) -> FaceStandardiser:
        """Add the faces (n, pixels) to the running statistics."""
        for x in np.atleast_2d(np.asarray(faces, dtype=float)):
            if self.n_seen_ == 0:
                self.mean_, self.m2_ = np.zeros_like(x), np.zeros_like(x)
            self.n_seen_ += 1
            delta = x - self.mean_
            self.mean_ += delta / self.n_seen_
            self.m2_ += delta * (x - self.mean_)
        return self

    def transform(self, faces: np.ndarray) -> np.ndarray:
        """The faces standardised: minus the mean, over the s.d. (at least ``min_std``)."""
        std = np.sqrt(self.m2_ / max(self.n_seen_, 1))
        return (np.asarray(faces, dtype=float) - self.mean_) / np.maximum(std, self.min_std)


class LearningModule:
    """A 3-layer perceptron, ``n_in - n_hidden - n_out`` (paper: 752 - 7 - 2).

    Hidden units are tanh, outputs linear; training is stochastic gradient descent with
    momentum on the squared error, one update per sample.
    """

    def __init__(self, n_in: int, n_hidden: int = 7, n_out: int = 2, *,
                 learning_rate: float = 0.0003, momentum: float = 0.5, init_scale: float = 1.0,
                 rng: np.random.Generator):
        self.learning_rate, self.momentum = learning_rate, momentum
        self.w1_ = rng.normal(0, init_scale / np.sqrt(n_in), (n_in, n_hidden))
        self.b1_ = np.zeros(n_hidden)
        self.w2_ = rng.normal(0, init_scale / np.sqrt(n_hidden), (n_hidden, n_out))
        self.b2_ = np.zeros(n_out)
        self._velocity = [np.zeros_like(p) for p in self._params()]
        self.n_updates_ = 0

    def _params(self) -> list[np.ndarray]:
        return [self.w1_, self.b1_, self.w2_, self.b2_]

    def predict(self, X: np.ndarray) -> np.ndarray:
        """Outputs (n, n_out) for inputs (n, n_in)."""
        return np.tanh(np.atleast_2d(X) @ self.w1_ + self.b1_) @ self.w2_ + self.b2_

    def partial_fit(self, X: np.ndarray, Y: np.ndarray) -> LearningModule:
        """One back-propagation update per row of ``X`` toward the row of ``Y``."""
        for x, y in zip(np.atleast_2d(X), np.atleast_2d(Y), strict=True):
            h = np.tanh(x @ self.w1_ + self.b1_)
            err = h @ self.w2_ + self.b2_ - y  # d(0.5 |out - y|^2) / d out
            dh = (self.w2_ @ err) * (1 - h**2)
            grads = [np.outer(x, dh), dh, np.outer(h, err), err]
            for p, v, g in zip(self._params(), self._velocity, grads, strict=True):
                v *= self.momentum
                v -= self.learning_rate * g
                p += v
            self.n_updates_ += 1
        return self
