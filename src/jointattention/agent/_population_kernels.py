"""The population code's compiled kernels (:mod:`.population` is their wrapper).

The forward pass, the cross-entropy step, the readout's scores and direction, and the running
averages: the step-by-step agent and the batched commands call the same ones.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import jit

__all__ = ["EXCESS", "MODE", "RATIO", "average_face_into", "average_into",
           "population_activate", "population_forward", "population_hidden_into",
           "population_readout", "population_scores_into", "population_teach",
           "population_teach_rows", "population_update", "scores_of_output_into",
           "von_mises_into"]

EXCESS, RATIO, MODE = 0, 1, 2  # the readouts (population.READOUTS), as codes


@jit
def von_mises_into(psi_rad: float, kappa: float, weight: float, out) -> None:
    """Add ``weight`` times a von Mises bump at ``psi_rad`` (summing to 1 over the units)."""
    n = len(out)
    bump = np.empty(n)  # each unit's exp once (the sum needs them all before the first share)
    total = 0.0
    for b in range(n):
        bump[b] = math.exp(kappa * (math.cos(2 * math.pi * b / n - psi_rad) - 1.0))
        total += bump[b]
    for b in range(n):
        out[b] += weight * bump[b] / total


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
def _backward_into(taught, n_taught: float, b1, w2, b2, learning_rate: float, h, p,
                   grad_h) -> None:
    """The output layer's and ``b1``'s step; in ``grad_h`` the step at each unit's input.

    The gradient of the summed cross-entropy of ``n_taught`` places (``taught``: the sum of
    their spread directions) at the output units' input is ``n_taught p - taught``.
    """
    grad_h[:] = 0.0
    for b in range(len(p)):
        g = n_taught * p[b] - taught[b]
        row = w2[b]
        for j in range(len(h)):
            grad_h[j] += g * row[j]
            row[j] -= learning_rate * g * h[j]
        b2[b] -= learning_rate * g
    for j in range(len(h)):
        grad_h[j] = grad_h[j] * (1.0 - h[j] * h[j]) * learning_rate
        b1[j] -= grad_h[j]


@jit
def _w1_step(x, grad_h, w1, x_next, h_next) -> None:
    """``w1 -= outer(x, grad_h)``; with ``x_next``, ``h_next += x_next w1`` in the same pass.

    The pass over ``w1`` (the network's bulk) then also sums the next input's hidden units
    with the new weights, in the order :func:`population_forward` sums them.
    """
    if x_next is None:
        for i in range(len(x)):
            xi, row = x[i], w1[i]
            for j in range(len(grad_h)):
                row[j] -= grad_h[j] * xi
    else:
        for i in range(len(x)):
            xi, xn, row = x[i], x_next[i], w1[i]
            for j in range(len(grad_h)):
                w = row[j] - grad_h[j] * xi
                row[j] = w
                h_next[j] += w * xn


@jit
def _last_w1_step(x, grad_h, w1, averaged, rate: float) -> None:
    """``w1 -= outer(x, grad_h)``, and the running average moves toward the new ``w1``.

    :func:`average_into`'s ``a += rate (w - a)`` in the same pass (the same bits).
    """
    for i in range(len(x)):
        xi, row, avg = x[i], w1[i], averaged[i]
        for j in range(len(grad_h)):
            w = row[j] - grad_h[j] * xi
            row[j] = w
            avg[j] += rate * (w - avg[j])


@jit
def population_update(x, taught, n_taught: float, w1, b1, w2, b2, learning_rate: float, h, p,
                      grad_h) -> None:
    """One gradient step on the summed cross-entropy of ``n_taught`` places for input ``x``.

    ``taught`` is the sum of their spread directions (:func:`_backward_into`).
    """
    population_forward(x, w1, b1, w2, b2, h, p)
    _backward_into(taught, n_taught, b1, w2, b2, learning_rate, h, p, grad_h)
    _w1_step(x, grad_h, w1, None, None)


@jit
def population_teach_rows(X, directions_rad, counts, kappa: float, w1, b1, w2, b2,
                          learning_rate: float, hidden_mean, hidden_rate: float, h, p, grad_h,
                          taught, averaged_w1, average_rate: float) -> int:
    """One update per row of ``X`` toward its places, in order; returns the places taught.

    Row r's places are ``directions_rad[r, :counts[r]]``, each spread by a von Mises bump of
    concentration ``kappa`` (a row without places is skipped); the running mean of the hidden
    units moves toward each input's at ``hidden_rate``. Each update's pass over ``w1`` also
    sums the next row's hidden units (:func:`_w1_step`): one pass per update, not two, with
    the bits of one row at a time. With ``averaged_w1`` (else None), the last update's pass
    also moves that running average of ``w1`` once, at ``average_rate``.
    """
    rows = np.flatnonzero(counts > 0)
    if len(rows) == 0:
        if averaged_w1 is not None:
            average_into(averaged_w1.reshape(-1), w1.reshape(-1), average_rate)
        return 0
    h_next = np.empty(len(h))
    population_forward(X[rows[0]], w1, b1, w2, b2, h, p)
    n_taught = 0
    for k in range(len(rows)):
        r = rows[k]
        taught[:] = 0.0
        for d in range(counts[r]):
            von_mises_into(directions_rad[r, d], kappa, 1.0, taught)
        n_taught += counts[r]
        _backward_into(taught, float(counts[r]), b1, w2, b2, learning_rate, h, p, grad_h)
        for j in range(len(h)):
            hidden_mean[j] += hidden_rate * (h[j] - hidden_mean[j])
        if k + 1 == len(rows) and averaged_w1 is not None:
            _last_w1_step(X[r], grad_h, w1, averaged_w1, average_rate)
        elif k + 1 == len(rows):
            _w1_step(X[r], grad_h, w1, None, None)
        else:
            h_next[:] = b1
            _w1_step(X[r], grad_h, w1, X[rows[k + 1]], h_next)
            h[:] = h_next
            population_activate(h, w2, b2, p)
    return n_taught


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


@jit
def population_teach(x, directions_rad, kappa: float, w1, b1, w2, b2, learning_rate: float,
                     hidden_mean, hidden_rate: float, h, p, grad_h, taught) -> None:
    """One update toward the places found in ``directions_rad`` for input ``x``.

    :func:`population_teach_rows` of one row.
    """
    population_teach_rows(x.reshape(1, -1), directions_rad.reshape(1, -1),
                          np.array([len(directions_rad)]), kappa, w1, b1, w2, b2,
                          learning_rate, hidden_mean, hidden_rate, h, p, grad_h, taught,
                          None, 0.0)


@jit
def average_into(averaged, weights, rate: float) -> None:
    """Move the running averages toward the weights: ``a += rate (w - a)`` (flat arrays)."""
    for i in range(len(averaged)):
        averaged[i] += rate * (weights[i] - averaged[i])
