"""The population code's compiled kernels (:mod:`.population` is their wrapper).

The forward pass, the cross-entropy step, the readout's scores and direction, and the running
averages: the step-by-step agent and the batched commands call the same ones.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import jit

__all__ = ["EXCESS", "MODE", "RATIO", "average_into", "population_forward",
           "population_readout", "population_scores_into", "population_teach",
           "population_update", "von_mises_into"]

EXCESS, RATIO, MODE = 0, 1, 2  # the readouts (population.READOUTS), as codes


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


@jit
def population_scores_into(x, w1, b1, w2, b2, hidden_mean, readout: int, h, p, z,
                           score) -> None:
    """The readout's score of each unit for input ``x`` (``population.READOUTS``, as codes).

    ``mode``: p(direction | x). ``excess``: p(direction | x) minus p(direction | the average
    face), the softmax of the output at the running mean of the hidden units. ``ratio``: the
    difference of their logs, in which the softmax's normalisers cancel.
    """
    population_forward(x, w1, b1, w2, b2, h, p)
    if readout == MODE:
        for b in range(len(p)):
            score[b] = p[b]
    elif readout == RATIO:
        for b in range(len(p)):
            s = t = 0.0
            row = w2[b]
            for j in range(len(h)):
                s += row[j] * h[j]
                t += row[j] * hidden_mean[j]
            score[b] = s - t
    else:
        _output_into(hidden_mean, w2, b2, z)
        _softmax_into(z, z)
        for b in range(len(p)):
            score[b] = p[b] - z[b]


@jit
def population_teach(x, directions_rad, kappa: float, w1, b1, w2, b2, learning_rate: float,
                     hidden_mean, hidden_rate: float, h, p, grad_h, taught) -> None:
    """One update toward the places found in ``directions_rad`` for input ``x``.

    Each direction is spread by a von Mises bump of concentration ``kappa``; the running mean
    of the hidden units moves toward this input's at ``hidden_rate``.
    """
    if len(directions_rad) == 0:
        return
    taught[:] = 0.0
    for psi in directions_rad:
        von_mises_into(psi, kappa, 1.0, taught)
    population_update(x, taught, float(len(directions_rad)), w1, b1, w2, b2, learning_rate,
                      h, p, grad_h)
    for j in range(len(h)):
        hidden_mean[j] += hidden_rate * (h[j] - hidden_mean[j])


@jit
def average_into(averaged, weights, rate: float) -> None:
    """Move the running averages toward the weights: ``a += rate (w - a)`` (flat arrays)."""
    for i in range(len(averaged)):
        averaged[i] += rate * (weights[i] - averaged[i])
