"""The population code's compiled forward pass and readout (:mod:`.code` wraps them).

The hidden and output units, the readout's scores and direction: the step-by-step agent and
the batched commands call the same ones; :mod:`._teaching` holds the learning step.
"""

from __future__ import annotations

import math

import numpy as np

from ..._jit import jit

__all__ = ["EXCESS", "MODE", "RATIO", "average_face_into", "population_activate",
           "population_forward", "population_hidden_into", "population_readout",
           "population_scores_into", "scores_of_output_into"]

EXCESS, RATIO, MODE = 0, 1, 2  # the readouts (options.READOUTS), as codes


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
    """The output units' input ``z = w2 h + b2``.

    Each unit's sum runs over the hidden units in order; eight units' sums advance together,
    so no sum waits on its own last addition.
    """
    n, n8 = len(z), len(z) - len(z) % 8
    for b in range(0, n8, 8):
        s0, s1, s2, s3 = b2[b], b2[b + 1], b2[b + 2], b2[b + 3]
        s4, s5, s6, s7 = b2[b + 4], b2[b + 5], b2[b + 6], b2[b + 7]
        r0, r1, r2, r3 = w2[b], w2[b + 1], w2[b + 2], w2[b + 3]
        r4, r5, r6, r7 = w2[b + 4], w2[b + 5], w2[b + 6], w2[b + 7]
        for j in range(len(h)):
            hj = h[j]
            s0 += r0[j] * hj
            s1 += r1[j] * hj
            s2 += r2[j] * hj
            s3 += r3[j] * hj
            s4 += r4[j] * hj
            s5 += r5[j] * hj
            s6 += r6[j] * hj
            s7 += r7[j] * hj
        z[b], z[b + 1], z[b + 2], z[b + 3] = s0, s1, s2, s3
        z[b + 4], z[b + 5], z[b + 6], z[b + 7] = s4, s5, s6, s7
    for b in range(n8, n):
        s = b2[b]
        row = w2[b]
        for j in range(len(h)):
            s += row[j] * h[j]
        z[b] = s


@jit
def population_activate(h, w2, b2, p) -> None:
    """From the hidden units' summed inputs in ``h``: ``h = tanh(h)``, ``p`` = softmax."""
    for j in range(len(h)):
        h[j] = math.tanh(h[j])
    _output_into(h, w2, b2, p)
    _softmax_into(p, p)


@jit
def population_hidden_into(X, w1, b1, H) -> None:
    """The hidden units' summed inputs ``H = X w1 + b1`` of inputs ``X`` (rows), before tanh.

    ``w1`` is (n_in, n_hidden), input-major: each unit's sum runs over the inputs in order
    (the bits of summing one unit at a time), all units at once along a row of ``w1`` (the
    loop vectorises), and a row of ``w1`` serves every input of ``X`` while it is in cache.
    """
    for r in range(len(X)):
        H[r, :] = b1
    n_in = X.shape[1]
    n4 = n_in - n_in % 4
    for i in range(0, n4, 4):  # four inputs per pass over H, added one after another
        r0, r1, r2, r3 = w1[i], w1[i + 1], w1[i + 2], w1[i + 3]
        for r in range(len(X)):
            x0, x1, x2, x3, hr = X[r, i], X[r, i + 1], X[r, i + 2], X[r, i + 3], H[r]
            for j in range(len(hr)):
                hr[j] = (((hr[j] + r0[j] * x0) + r1[j] * x1) + r2[j] * x2) + r3[j] * x3
    for i in range(n4, n_in):
        row = w1[i]
        for r in range(len(X)):
            xi, hr = X[r, i], H[r]
            for j in range(len(row)):
                hr[j] += row[j] * xi


@jit
def population_forward(x, w1, b1, w2, b2, h, p) -> None:
    """Hidden units ``h = tanh(x w1 + b1)`` and the softmax ``p`` of ``w2 h + b2``.

    The sums: :func:`population_hidden_into` of the one input.
    """
    population_hidden_into(x.reshape((1, len(x))), w1, b1, h.reshape((1, len(h))))
    population_activate(h, w2, b2, p)


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
    """The readout's score of each unit for input ``x`` (``options.READOUTS``, as codes).

    ``mode``: p(direction | x). ``excess``: p(direction | x) minus p(direction | the average
    face), the softmax of the output at the running mean of the hidden units. ``ratio``: the
    difference of their logs, in which the softmax's normalisers cancel.
    """
    population_forward(x, w1, b1, w2, b2, h, p)
    if readout == EXCESS:
        average_face_into(hidden_mean, w2, b2, z)
    scores_of_output_into(h, p, w2, hidden_mean, readout, z, score)


@jit
def average_face_into(hidden_mean, w2, b2, z) -> None:
    """p(direction | the average face): the softmax of the output at ``hidden_mean``."""
    _output_into(hidden_mean, w2, b2, z)
    _softmax_into(z, z)


@jit
def scores_of_output_into(h, p, w2, hidden_mean, readout: int, average_p, score) -> None:
    """:func:`population_scores_into` from the forward pass's hidden units ``h`` and ``p``.

    ``average_p`` is :func:`average_face_into`'s (read by ``excess`` only): the same for
    every face, so batched commands compute it once.
    """
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
        for b in range(len(p)):
            score[b] = p[b] - average_p[b]
