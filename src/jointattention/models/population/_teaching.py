"""The population code's compiled learning step (:mod:`.code` is its wrapper).

The von Mises spread of a taught direction, the cross-entropy step and its passes over ``w1``
(each also summing the next row's hidden units, or moving the running average), and the
running averages. The forward pass is in :mod:`._forward`.
"""

from __future__ import annotations

import math

import numpy as np

from ..._jit import jit
from ._forward import average_face_into, population_activate, population_forward

__all__ = ["average_into", "belief_weights_into", "population_teach", "population_teach_rows",
           "population_update", "von_mises_into"]


@jit
def _bump(b: int, n: int, psi_rad: float, kappa: float) -> float:
    """Unit ``b`` of ``n``'s share of a von Mises bump at ``psi_rad``, not normalised."""
    return math.exp(kappa * (math.cos(2 * math.pi * b / n - psi_rad) - 1.0))


@jit
def von_mises_into(psi_rad: float, kappa: float, weight: float, out) -> None:
    """Add ``weight`` times a von Mises bump at ``psi_rad`` (summing to 1 over the units)."""
    n = len(out)
    bump = np.empty(n)  # each unit's exp once (the sum needs them all before the first share)
    total = 0.0
    for b in range(n):
        bump[b] = _bump(b, n, psi_rad, kappa)
        total += bump[b]
    for b in range(n):
        out[b] += weight * bump[b] / total


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

    :func:`average_into`'s step in the same pass.
    """
    for i in range(len(x)):
        xi, row, avg = x[i], w1[i], averaged[i]
        for j in range(len(grad_h)):
            w = row[j] - grad_h[j] * xi
            row[j] = w
            avg[j] = _toward(avg[j], w, rate)


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
def belief_weights_into(directions_rad, count: int, kappa: float, p, z, belief: float,
                        weights) -> None:
    """Each place's weight in an update: ``(1 - belief) + belief * count * r / sum(r)``.

    ``r`` is the place's excess ratio, p(direction | face) / p(direction | the average face),
    each spread by the place's von Mises bump (``p``, ``z``: both softmaxes over the units).
    The weights sum to ``count``, so an update's size is that of equal weights.
    """
    n = len(p)
    total = 0.0
    for d in range(count):
        num = den = 0.0
        for b in range(n):
            bump = _bump(b, n, directions_rad[d], kappa)
            num += bump * p[b]
            den += bump * z[b]
        weights[d] = num / den
        total += weights[d]
    for d in range(count):
        weights[d] = (1.0 - belief) + belief * count * weights[d] / total


@jit
def population_teach_rows(X, directions_rad, counts, kappa: float, w1, b1, w2, b2,
                          learning_rate: float, hidden_mean, hidden_rate: float, h, p, grad_h,
                          taught, belief: float, z, averaged_w1, average_rate: float) -> int:
    """One update per row of ``X`` toward its places, in order; returns the places taught.

    Row r's places are ``directions_rad[r, :counts[r]]``, each spread by a von Mises bump of
    concentration ``kappa`` (a row without places is skipped), each weighted by the network's
    belief in it (:func:`belief_weights_into`; ``z`` its scratch) when ``belief`` > 0; the
    running mean of the hidden units moves toward each input's at ``hidden_rate``. Each
    update's pass over ``w1`` also sums the next row's hidden units (:func:`_w1_step`): one
    pass per update, not two, with the bits of one row at a time. With ``averaged_w1`` (else
    None), the last update's pass also moves that running average of ``w1`` once, at
    ``average_rate``.
    """
    rows = np.flatnonzero(counts > 0)
    if len(rows) == 0:
        if averaged_w1 is not None:
            average_into(averaged_w1.reshape(-1), w1.reshape(-1), average_rate)
        return 0
    h_next, weights = np.empty(len(h)), np.empty(directions_rad.shape[1])
    population_forward(X[rows[0]], w1, b1, w2, b2, h, p)
    n_taught = 0
    for k in range(len(rows)):
        r = rows[k]
        taught[:] = 0.0
        if belief > 0.0:  # the place's weight, by the network at this row's input
            average_face_into(hidden_mean, w2, b2, z)
            belief_weights_into(directions_rad[r], counts[r], kappa, p, z, belief, weights)
        for d in range(counts[r]):
            von_mises_into(directions_rad[r, d], kappa, weights[d] if belief > 0.0 else 1.0,
                           taught)
        n_taught += counts[r]
        _backward_into(taught, float(counts[r]), b1, w2, b2, learning_rate, h, p, grad_h)
        for j in range(len(h)):
            hidden_mean[j] = _toward(hidden_mean[j], h[j], hidden_rate)
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
def population_teach(x, directions_rad, kappa: float, w1, b1, w2, b2, learning_rate: float,
                     hidden_mean, hidden_rate: float, h, p, grad_h, taught, belief: float,
                     z) -> None:
    """One update toward the places found in ``directions_rad`` for input ``x``.

    :func:`population_teach_rows` of one row.
    """
    population_teach_rows(x.reshape(1, -1), directions_rad.reshape(1, -1),
                          np.array([len(directions_rad)]), kappa, w1, b1, w2, b2,
                          learning_rate, hidden_mean, hidden_rate, h, p, grad_h, taught,
                          belief, z, None, 0.0)


@jit
def average_into(averaged, weights, rate: float) -> None:
    """Move the running averages toward the weights: ``a += rate (w - a)`` (flat arrays)."""
    for i in range(len(averaged)):
        averaged[i] = _toward(averaged[i], weights[i], rate)


@jit
def _toward(a: float, w: float, rate: float) -> float:
    """A running average ``a`` moved toward ``w`` (Polyak averaging)."""
    return a + rate * (w - a)
