"""The learning module's arithmetic: its forward pass and back-propagation (paper, III-D).

Compiled kernels over plain arrays, which :class:`~.learner.LearningModule`, the step-by-step
agent and the compiled engine's loop all call (:mod:`.learner` is their public door). Imports
only the plumbing.
"""

from __future__ import annotations

import math

import numpy as np

from ..._jit import jit

__all__ = ["accumulate", "face_part", "forward", "sgd_rows", "sgd_rows_from", "sgd_update"]


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
def face_part(x, w1, acc) -> None:
    """``acc[j] = x . w1[j, :len(x)]``: the first inputs' part of each hidden unit's input.

    :func:`accumulate` from zero. For a trial's face it is fixed for the trial, as the
    weights change only at its end.
    """
    for j in range(len(acc)):  # element by element: quicker for numba to compile
        acc[j] = 0.0
    accumulate(x, w1, 0, acc)


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
    shared_w1 = np.empty(len(b1))
    face_part(shared, w1, shared_w1)
    sgd_rows_from(shared_w1, shared, rest, Y, w1, b1, w2, b2, v1, vb1, v2, vb2, learning_rate,
                  momentum)


@jit
def sgd_rows_from(shared_w1, shared, rest, Y, w1, b1, w2, b2, v1, vb1, v2, vb2,
                  learning_rate: float, momentum: float) -> None:
    """:func:`sgd_rows`, given ``shared_w1``: the hidden units' input from the shared part.

    That is :func:`face_part` of ``shared``, which the compiled loop has summed at the
    trial's start (the weights change only at its end).
    """
    n_hidden, n_out = w2.shape
    n_s = len(shared)
    work = np.zeros(5 * n_hidden + 2 * n_out)  # one allocation: a call may be one row
    face_w, face_v = shared_w1, work[:n_hidden]  # w1_0 . f, v1_0 . f
    c, d = work[n_hidden:2 * n_hidden], work[2 * n_hidden:3 * n_hidden]
    acc, h = work[3 * n_hidden:4 * n_hidden], work[4 * n_hidden:5 * n_hidden]
    out, err = work[5 * n_hidden:5 * n_hidden + n_out], work[5 * n_hidden + n_out:]
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
