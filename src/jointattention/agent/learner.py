"""The learning module: a three-layer network trained by back-propagation (paper, III-D).

Inputs are the caregiver's face window (standardised with statistics of the faces the robot
has seen) and the head angle (scaled by the robot's own joint ranges); outputs are a motor
command in units of one step. The interface follows scikit-learn: ``partial_fit`` and
``predict`` on 2-D arrays, learned state in attributes ending in ``_``.

The arithmetic is in compiled kernels (:func:`accumulate`, :func:`forward`, :func:`sgd_rows`,
:func:`welford_update`, :func:`standardise`), which the compiled engine calls too.
"""

from __future__ import annotations

import math

import numpy as np

from .._arrays import rows
from .._jit import jit
from ..errors import ArgumentError

__all__ = ["NO_FACE_SEEN", "FaceStandardiser", "LearningModule", "accumulate", "forward",
           "sgd_rows", "sgd_update", "standardise", "welford_update"]

# transform's error before any face (the compiled loops raise it too)
NO_FACE_SEEN = "faces: the standardiser has seen no face; expected partial_fit before transform"


@jit
def welford_update(x, mean, m2, n_seen: int) -> None:
    """Add face ``x`` to the running mean and sum of squares; ``n_seen`` counts it already."""
    for i in range(len(x)):
        delta = x[i] - mean[i]
        mean[i] += delta / n_seen
        m2[i] += delta * (x[i] - mean[i])


@jit
def standardise(x, mean, m2, n_seen: int, min_std: float, out) -> None:
    """``out`` = (x - mean) / max(s.d., min_std), the s.d. of the faces seen so far."""
    for i in range(len(x)):
        out[i] = (x[i] - mean[i]) / max(math.sqrt(m2[i] / max(n_seen, 1)), min_std)


@jit
def accumulate(x, w1, first_input: int, acc) -> None:
    """``acc[j] += x . w1[j, first_input : first_input + len(x)]`` for each hidden unit j.

    Summed in four interleaved partial sums (so that the loop vectorises), the same way on
    every call: the compiled engine and the step-by-step agent both sum a face part once per
    trial, then the head angle part at each step. Two units at a time, each unit's sums in
    the same order as alone (the same bits), so that the two do not wait for each other.
    """
    n = len(x)
    n4 = n - n % 4
    end = first_input + n
    j = 0
    while j + 1 < len(acc):
        ra, rb = w1[j, first_input:end], w1[j + 1, first_input:end]
        a0 = a1 = a2 = a3 = b0 = b1 = b2 = b3 = 0.0
        for i in range(0, n4, 4):
            a0 += x[i] * ra[i]
            a1 += x[i + 1] * ra[i + 1]
            a2 += x[i + 2] * ra[i + 2]
            a3 += x[i + 3] * ra[i + 3]
            b0 += x[i] * rb[i]
            b1 += x[i + 1] * rb[i + 1]
            b2 += x[i + 2] * rb[i + 2]
            b3 += x[i + 3] * rb[i + 3]
        for i in range(n4, n):
            a0 += x[i] * ra[i]
            b0 += x[i] * rb[i]
        acc[j] += (a0 + a1) + (a2 + a3)
        acc[j + 1] += (b0 + b1) + (b2 + b3)
        j += 2
    if j < len(acc):
        row = w1[j, first_input:end]
        s0 = s1 = s2 = s3 = 0.0
        for i in range(0, n4, 4):
            s0 += x[i] * row[i]
            s1 += x[i + 1] * row[i + 1]
            s2 += x[i + 2] * row[i + 2]
            s3 += x[i + 3] * row[i + 3]
        for i in range(n4, n):
            s0 += x[i] * row[i]
        acc[j] += (s0 + s1) + (s2 + s3)


@jit
def forward(acc, b1, w2, b2, h, out) -> None:
    """Hidden units ``h = tanh(acc + b1)`` and outputs ``out = h @ w2 + b2``.

    ``acc`` is the hidden units' summed input (:func:`accumulate`).
    """
    for j in range(len(h)):
        h[j] = math.tanh(acc[j] + b1[j])
    for k in range(len(out)):
        s = 0.0
        for j in range(len(h)):
            s += h[j] * w2[j, k]
        out[k] = s + b2[k]


@jit
def sgd_update(x, y, w1, b1, w2, b2, v1, vb1, v2, vb2, learning_rate: float,
               momentum: float) -> None:
    """One back-propagation step with momentum on 0.5 |out - y|^2 for input ``x``.

    The one-row case of :func:`sgd_rows` with nothing shared.
    """
    sgd_rows(x[:0], x.reshape(1, len(x)), y.reshape(1, len(y)), w1, b1, w2, b2, v1, vb1, v2,
             vb2, learning_rate, momentum)


@jit
def sgd_rows(shared, rest, Y, w1, b1, w2, b2, v1, vb1, v2, vb2, learning_rate: float,
             momentum: float) -> None:
    """One back-propagation step with momentum per row ``t``, input ``(shared, rest[t])``.

    The paper's update (III-D): ``v = momentum v - rate dL/dw``, ``w += v``, on
    ``L = 0.5 |out - y|^2``, row after row. The rows of a trial share its face (``shared``,
    750 of 752 inputs), so the weights on those inputs are not written row by row: after
    ``t`` rows ``v1 = momentum^t v1_0 - c f`` and ``w1 = w1_0 + s v1_0 - d f``, where ``f`` is
    the shared input, ``s`` the sum of ``momentum^k`` (k = 1..t) and ``c``, ``d`` one number
    per hidden unit. Each row's hidden input on the shared part is then ``w1_0 . f +
    s v1_0 . f - d |f|^2``, and one pass at the end writes the shared weights: the cost of a
    row is that of its own inputs. The same arithmetic as row by row up to rounding; with
    nothing shared, the same bits as one call per row.
    """
    n_hidden, n_out = w2.shape
    n_s = len(shared)
    work = np.zeros(6 * n_hidden + 2 * n_out)  # one allocation: a call may be one row
    face_w, face_v = work[:n_hidden], work[n_hidden:2 * n_hidden]  # w1_0 . f, v1_0 . f
    c, d = work[2 * n_hidden:3 * n_hidden], work[3 * n_hidden:4 * n_hidden]
    acc, h = work[4 * n_hidden:5 * n_hidden], work[5 * n_hidden:6 * n_hidden]
    out, err = work[6 * n_hidden:6 * n_hidden + n_out], work[6 * n_hidden + n_out:]
    accumulate(shared, w1, 0, face_w)
    accumulate(shared, v1, 0, face_v)
    ff = 0.0
    for i in range(n_s):
        ff += shared[i] * shared[i]
    decay, s = 1.0, 0.0  # momentum^t and the sum of momentum^k, k = 1..t
    for t in range(len(rest)):
        x = rest[t]
        for j in range(n_hidden):
            acc[j] = (face_w[j] + s * face_v[j]) - d[j] * ff
        accumulate(x, w1, n_s, acc)
        forward(acc, b1, w2, b2, h, out)
        for k in range(n_out):
            err[k] = out[k] - Y[t, k]  # d(0.5 |out - y|^2) / d out
        decay *= momentum
        s += decay
        for j in range(n_hidden):
            back = 0.0
            for k in range(n_out):
                back += w2[j, k] * err[k]
            rate_dh = learning_rate * (back * (1 - h[j] * h[j]))  # the step times dL/d acc_j
            c[j] = c[j] * momentum + rate_dh
            d[j] += c[j]
            v_row, w_row = v1[j, n_s:], w1[j, n_s:]  # views: indexed at an offset, the loop
            for i in range(len(x)):                  # ran half as fast (not vectorised)
                v_row[i] = v_row[i] * momentum - rate_dh * x[i]
                w_row[i] += v_row[i]
            vb1[j] = vb1[j] * momentum - rate_dh
            b1[j] += vb1[j]
            for k in range(n_out):
                v2[j, k] = v2[j, k] * momentum - learning_rate * (h[j] * err[k])
        for j in range(n_hidden):  # after the loop above has used w2 for every unit
            for k in range(n_out):
                w2[j, k] += v2[j, k]
        for k in range(n_out):
            vb2[k] = vb2[k] * momentum - learning_rate * err[k]
            b2[k] += vb2[k]
    if len(rest) > 0:
        for j in range(n_hidden):
            v_row, w_row, cj, dj = v1[j, :n_s], w1[j, :n_s], c[j], d[j]
            for i in range(n_s):
                v0 = v_row[i]
                w_row[i] += s * v0 - dj * shared[i]
                v_row[i] = decay * v0 - cj * shared[i]


class FaceStandardiser:
    """Per-pixel running mean and standard deviation of the faces seen (Welford)."""

    def __init__(self, min_std: float = 8.0):
        self.min_std = min_std
        self.n_seen_ = 0

    def partial_fit(self, faces: np.ndarray) -> FaceStandardiser:
        """Add the faces (n, pixels) to the running statistics."""
        faces = rows("faces", faces, len(self.mean_) if self.n_seen_ else None)
        for x in faces:
            if self.n_seen_ == 0:
                self.mean_, self.m2_ = np.zeros_like(x), np.zeros_like(x)
            self.n_seen_ += 1
            welford_update(np.ascontiguousarray(x), self.mean_, self.m2_, self.n_seen_)
        return self

    def transform(self, faces: np.ndarray) -> np.ndarray:
        """The faces standardised: minus the mean, over the s.d. (at least ``min_std``)."""
        if not self.n_seen_:
            raise ArgumentError(NO_FACE_SEEN)
        x = rows("faces", faces, len(self.mean_))
        out = np.empty_like(x)
        for row, o in zip(x, out, strict=True):
            standardise(row, self.mean_, self.m2_, self.n_seen_, float(self.min_std), o)
        return out if np.ndim(faces) == 2 else out[0]

    def statistics(self, n_pixels: int) -> tuple[np.ndarray, np.ndarray]:
        """``mean_`` and ``m2_``, which the compiled loops update in place.

        Zeros of ``n_pixels`` before the first face.
        """
        if self.n_seen_ == 0:
            self.mean_, self.m2_ = np.zeros(n_pixels), np.zeros(n_pixels)
        return self.mean_, self.m2_


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
            acc = np.zeros(n_hidden)
            accumulate(x, self.w1_, 0, acc)
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
