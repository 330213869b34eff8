"""The paper's learning module: a three-layer network trained by back-propagation (III-D).

Inputs are the caregiver's face window (standardised with statistics of the faces the robot
has seen, :mod:`jointattention.agent.face_standardiser`) and the head angle (scaled by the
robot's own joint ranges); outputs are a motor command in units of one step. The interface
follows scikit-learn: ``partial_fit`` and ``predict`` on 2-D arrays, learned state in
attributes ending in ``_``.

The arithmetic is in compiled kernels, which the compiled engine calls too:
:mod:`._backprop` (:func:`accumulate`, :func:`forward`, :func:`sgd_rows`), which this module
is the door to.
"""

from __future__ import annotations

import numpy as np

from ..._arrays import rows
from ...errors import ArgumentError
from ._backprop import (
    accumulate,
    face_part,
    forward,
    sgd_rows,
    sgd_rows_from,
    sgd_update,
)

__all__ = ["LearningModule", "accumulate", "face_part", "forward", "sgd_rows", "sgd_rows_from",
           "sgd_update"]

class LearningModule:
    """A 3-layer perceptron, ``n_in - n_hidden - n_out`` (paper: 752 - 7 - 2).

    Hidden units are tanh, outputs linear; training is stochastic gradient descent with
    momentum on the squared error, one update per sample (:func:`sgd_rows`). Learned state:
    ``w1_`` (n_hidden, n_in), one row of input weights per hidden unit; ``b1_``; ``w2_``
    (n_hidden, n_out); ``b2_``; ``velocity_`` (their momentum terms); ``n_updates_``.
    """

    def __init__(self, n_in: int, n_hidden: int = 7, n_out: int = 2, *,
                 learning_rate: float = 0.0003, momentum: float = 0.5, init_scale: float = 1.0,
                 rng: np.random.Generator):
        self.learning_rate, self.momentum = learning_rate, momentum
        self.w1_ = rng.normal(0, init_scale / np.sqrt(n_in), (n_hidden, n_in))
        self.b1_ = np.zeros(n_hidden)
        self.w2_ = rng.normal(0, init_scale / np.sqrt(n_hidden), (n_hidden, n_out))
        self.b2_ = np.zeros(n_out)
        self.velocity_ = [np.zeros_like(p) for p in self._params()]
        self.n_updates_ = 0

    def _params(self) -> list[np.ndarray]:
        return [self.w1_, self.b1_, self.w2_, self.b2_]

    def predict(self, X: np.ndarray) -> np.ndarray:
        """Outputs (n, n_out) for inputs (n, n_in)."""
        X = rows("X", X, self.w1_.shape[1])
        n_hidden, n_out = self.w2_.shape
        out, h = np.empty((len(X), n_out)), np.empty(n_hidden)
        for x, o in zip(X, out, strict=True):
            acc = np.empty(n_hidden)
            face_part(x, self.w1_, acc)
            forward(acc, self.b1_, self.w2_, self.b2_, h, o)
        return out

    def partial_fit(self, X: np.ndarray, Y: np.ndarray, *,
                    shared_inputs: int = 0) -> LearningModule:
        """One back-propagation update per row of ``X`` toward the row of ``Y``, in order.

        ``shared_inputs``: how many first inputs every row shares (a trial's face), which
        :func:`sgd_rows` updates in closed form.
        """
        X = rows("X", X, self.w1_.shape[1])
        Y = rows("Y", Y, self.w2_.shape[1], len(X))
        if not 0 <= shared_inputs <= X.shape[1]:
            raise ArgumentError(f"shared_inputs: {shared_inputs}; expected 0 to {X.shape[1]}")
        shared = X[0, :shared_inputs] if len(X) else np.zeros(shared_inputs)
        if np.any(X[:, :shared_inputs] != shared):
            raise ArgumentError(f"X: rows differ in their first {shared_inputs} inputs; "
                                "expected shared_inputs to count inputs every row shares")
        sgd_rows(np.ascontiguousarray(shared), np.ascontiguousarray(X[:, shared_inputs:]), Y,
                 *self._params(), *self.velocity_, float(self.learning_rate),
                 float(self.momentum))
        self.n_updates_ += len(X)
        return self
