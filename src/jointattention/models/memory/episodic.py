"""An episodic learning module: where the robot found an object, recalled by the face.

The paper's learning module regresses a direction on the face (squared error). When the
evaluator fires on one of n objects, the caregiver's target is only one of the places the robot
learns from; a squared-error learner converges to the *mean* of those places, which for 10
objects points at the distractors' average, not at the target (docs/beyond-the-paper.md).
This module looks for the *mode* instead: it keeps each self-evaluated trial as a pair (a
compact code of the face, the head angle at which the object was centred) and, for a face,
recalls the place that the trials with the most similar faces agree on beyond what every face
agrees on (the base rate, which the distractors set). All it uses is the robot's own.

The kernels (:func:`face_code_into`, :func:`memory_store`, :func:`memory_recall`) are compiled;
:class:`EpisodicMemory` is their scikit-learn-style wrapper.
"""

from __future__ import annotations

import math

import numpy as np

from ..._arrays import angles, flat, floats, rows
from ..._jit import jit
from ...errors import ArgumentError
from ._agreement import agree_forget, agree_keep, votes_of
from ._left_out import leave_out, left_out_of, near_any
from ._recall import (
    CODE_OF,
    cell_of,
    code_distances_into,
    count_around,
    face_code_into,
    link,
    near_slots,
    new_lap,
    no_links,
    same_code,
    unlink,
    weighted_kth,
)
from .options import MemoryOptions

__all__ = ["EpisodicMemory", "code_distances_into", "face_code_into",
           "left_out_of", "memory_recall", "memory_store", "no_links", "recall_at_distances"]


@jit
def memory_store(code, aim_pan_rad, aim_tilt_rad, codes, counts, links, aims, base, n_stored,
                 n_codes, lo_rad, cell_rad, radius_rad) -> int:
    """Keep a trial (face code, place) in slot ``n_stored % capacity``, forgetting its last.

    Equal face codes are kept once (``codes[:, u]``, with ``counts[u]`` trials), so that a recall
    measures each distinct face once: with the data sets' faces a few hundred codes, not every
    kept trial. ``links`` holds each slot's code and each code's slots in slot order
    (:mod:`._recall`) and how many of its code's places agree with each (:mod:`._agreement`).
    ``base`` counts, per grid cell, the kept places within the voting radius: the base rate.
    Returns the rows of ``codes`` in use.
    """
    slot, code_of, r2 = n_stored % len(aims), links[CODE_OF], radius_rad * radius_rad
    if n_stored >= len(aims):
        count_around(aims[slot, 0], aims[slot, 1], base, lo_rad, cell_rad, -1.0)
        counts[code_of[slot]] -= 1
        agree_forget(links, aims, slot, r2)
        unlink(links, slot)
    if slot == 0:
        new_lap(links, n_codes)
    u = code_of[slot - 1] if n_stored > 0 else 0  # a trial's places share its face
    if not (n_stored > 0 and counts[u] > 0 and same_code(codes[:, u], code)):
        u, free = -1, -1
        for v in range(n_codes):
            if counts[v] == 0:
                free = v if free < 0 else free
            elif same_code(codes[:, v], code):
                u = v
                break
        if u < 0:
            u = free if free >= 0 else n_codes
            n_codes = max(n_codes, u + 1)
            for j in range(len(code)):
                codes[j, u] = code[j]
    counts[u] += 1
    link(links, slot, u)
    aims[slot, 0], aims[slot, 1] = aim_pan_rad, aim_tilt_rad
    agree_keep(links, aims, slot, r2)
    count_around(aim_pan_rad, aim_tilt_rad, base, lo_rad, cell_rad, 1.0)
    return n_codes


@jit
def memory_recall(code, codes, counts, links, aims, base, n_stored, n_codes, lo_rad,
                  cell_rad, k_nearest, radius_rad, left_out, out) -> tuple[float, float]:
    """The place recalled for a face code, into ``out``; returns its support and its evidence.

    The trials of the k nearest face codes (ties included) vote, each with the weight
    exp(-d^2 / d_k^2) of its face's distance d (d_k: the k-th nearest), so that the face's own
    trials outvote a similar face's. Each of their places counts the weight of the places
    within ``radius_rad`` of it, less what the base rate predicts for so much weight. The
    winner's neighbours are averaged (weighted) into ``out``. Its excess over the base rate is
    its evidence, in trials (the face's own trials weigh 1 each), and the support is the
    evidence as a fraction of the weight recalled (0: nothing beyond chance; 1: all agree);
    (-1, 0) with no memory. The places within ``radius_rad`` of ``left_out`` (m, 2) do not
    win (:mod:`._left_out`); (-1, 0) if none is left. Distances are measured once per
    distinct code (:func:`memory_store`, :func:`code_distances_into`).
    """
    d2 = np.empty((1, n_codes))  # no codes while nothing is kept: recall_at_distances says so
    code_distances_into(code.reshape(1, len(code)), codes, n_codes, d2)
    return recall_at_distances(d2[0], counts, links, aims, base, n_stored, n_codes, lo_rad,
                               cell_rad, k_nearest, radius_rad, left_out, out)


@jit
def recall_at_distances(d2u, counts, links, aims, base, n_stored, n_codes, lo_rad, cell_rad,
                        k_nearest, radius_rad, left_out, out) -> tuple[float, float]:
    """:func:`memory_recall` of a face code whose distances to the codes are ``d2u``."""
    n = min(n_stored, len(aims))
    if n == 0:
        return -1.0, 0.0
    d2_k = weighted_kth(d2u, counts[:n_codes], min(k_nearest, n))
    near = near_slots(links, counts, d2u, d2_k, n_codes)  # in slot order, as the sums go
    n_near = len(near)
    d2 = np.empty(n_near)
    for b in range(n_near):
        d2[b] = d2u[links[CODE_OF, near[b]]]
    weight = np.exp(-d2 / max(d2_k, 1e-300))
    total, r2 = weight.sum(), radius_rad * radius_rad
    votes = np.empty(n_near)
    votes_of(near, weight, links, aims, radius_rad, votes)
    best, best_a = -np.inf, 0
    for a in range(n_near):
        if len(left_out) and near_any(aims[near[a], 0], aims[near[a], 1], left_out, r2):
            continue
        ci, cj = cell_of(aims[near[a], 0], aims[near[a], 1], lo_rad, cell_rad, base.shape)
        excess = votes[a] - total * base[ci, cj] / n
        if excess > best:  # the first of equal votes
            best, best_a = excess, a
    if best == -np.inf:  # every place near a face's left-out ones
        return -1.0, 0.0
    pa, ta = aims[near[best_a], 0], aims[near[best_a], 1]
    s0 = s1 = kept = 0.0
    for b in range(n_near):
        if (aims[near[b], 0] - pa) ** 2 + (aims[near[b], 1] - ta) ** 2 < r2:
            s0 += weight[b] * aims[near[b], 0]
            s1 += weight[b] * aims[near[b], 1]
            kept += weight[b]
    out[0], out[1] = s0 / kept, s1 / kept
    return best / total, best


class EpisodicMemory:
    """Self-evaluated trials, kept as (face code, place) and recalled by face (see module).

    Args:
        n_in: pixels of a face window.
        options: code length, neighbours, voting radius, capacity.
        limits_rad: the head's joint ranges ((pan lo, hi), (tilt lo, hi)); the base rate is
            counted on a grid over them (a margin of 0.2 rad each side).
        rng: draws the face code's projection.

    Learned state: ``aims_`` (the kept trials' places), ``codes_`` (their distinct face codes,
    the first ``n_codes_`` columns: (code length, capacity), entry-major so that a recall
    measures every code at once), ``counts_`` (trials per code), ``links_`` (each trial's code,
    each code's trials in slot order, their agreement: :mod:`._recall`), ``base_`` (the base
    rate's grid), ``n_stored_`` (trials kept so far, forgotten ones included); with
    ``leave_out_empty``, ``left_codes_`` and ``left_aims_`` (the places left out of a face's
    recalls, with its code: :mod:`._left_out`) and ``n_left_`` (places left out so far).
    """

    def __init__(self, n_in: int, options: MemoryOptions, limits_rad, rng: np.random.Generator):
        self.options = options
        self.projection = rng.normal(0.0, 1.0 / math.sqrt(options.code_dims),
                                     (options.code_dims, n_in)).T.copy()  # (pixels, code)
        limits = np.asarray(limits_rad, dtype=float)
        self.lo_rad = limits[:, 0] - 0.2
        self.cell_rad = self.radius_rad / 2
        shape = np.ceil((limits[:, 1] + 0.2 - self.lo_rad) / self.cell_rad).astype(int) + 1
        self.codes_ = np.zeros((options.code_dims, options.capacity))
        self.counts_ = np.zeros(options.capacity, np.int64)
        self.links_ = no_links(options.capacity)
        self.aims_ = np.zeros((options.capacity, 2))
        self.base_ = np.zeros(tuple(shape))
        self.n_stored_ = self.n_codes_ = self.n_left_ = 0
        n_left = options.capacity if options.leave_out_empty else 1  # 1: the kernels' types
        self.left_codes_ = np.zeros((options.code_dims, n_left))
        self.left_aims_ = np.zeros((n_left, 2))

    @property
    def radius_rad(self) -> float:
        """The voting radius."""
        return math.radians(self.options.radius_deg)

    def code(self, face_window) -> np.ndarray:
        """The compact code of a face window."""
        face = flat("face_window", face_window, len(self.projection))
        out = np.empty(self.options.code_dims)
        face_code_into(face, self.projection, out)
        return out

    def store(self, code: np.ndarray, aim_rad) -> None:
        """Keep one trial: the face's code and the place (pan, tilt) where it found an object."""
        code = floats("code", code, (self.options.code_dims,))
        pan, tilt = angles("aim_rad", aim_rad)
        self.n_codes_ = memory_store(code, float(pan), float(tilt), *self.kept_arrays(),
                                     self.lo_rad, self.cell_rad, self.radius_rad)
        self.n_stored_ += 1

    def kept_arrays(self) -> tuple:
        """The kept trials as the kernels take them, with ``n_stored_`` and ``n_codes_``."""
        return (self.codes_, self.counts_, self.links_, self.aims_, self.base_,
                self.n_stored_, self.n_codes_)

    def left_arrays(self) -> tuple:
        """The places left out of faces' recalls as the kernels take them, with ``n_left_``."""
        return self.left_codes_, self.left_aims_, self.n_left_

    def left_out(self, code: np.ndarray) -> np.ndarray:
        """The places left out of a face code's recalls, (m, 2)."""
        code = floats("code", code, (self.options.code_dims,))
        return left_out_of(code, *self.left_arrays())

    def leave_out(self, code: np.ndarray, aim_rad) -> None:
        """Leave a place (pan, tilt) out of a face code's recalls (``leave_out_empty``)."""
        if not self.options.leave_out_empty:
            raise ArgumentError("leave_out: this memory leaves nothing out; expected "
                                "memory.leave_out_empty = true")
        code, aim_rad = floats("code", code, (self.options.code_dims,)), angles("aim_rad", aim_rad)
        self.n_left_ = leave_out(code, float(aim_rad[0]), float(aim_rad[1]),
                                 *self.left_arrays())

    def recall(self, code: np.ndarray) -> tuple[np.ndarray | None, float]:
        """The place recalled for a face code and its support; (None, -1) with no memory."""
        return self.recall_evidence(code)[:2]

    def recall_evidence(self, code: np.ndarray) -> tuple[np.ndarray | None, float, float]:
        """:meth:`recall`, and the place's evidence in trials (:func:`memory_recall`)."""
        code, out = floats("code", code, (self.options.code_dims,)), np.empty(2)
        support, evidence = memory_recall(code, *self.kept_arrays(), self.lo_rad,
                                          self.cell_rad, self.options.k_nearest,
                                          self.radius_rad, self.left_out(code), out)
        return (None if support < 0 else out), support, evidence

    def partial_fit(self, X: np.ndarray, Y: np.ndarray) -> EpisodicMemory:
        """Keep each row's trial: face windows ``X`` (n, pixels), places ``Y`` (n, 2)."""
        X = rows("X", X, len(self.projection))
        for x, y in zip(X, angles("Y", Y, len(X)), strict=True):
            self.store(self.code(x), y)
        return self

    def predict(self, X: np.ndarray) -> np.ndarray:
        """The place recalled for each face window (n, pixels), (n, 2); NaN with no memory."""
        X = rows("X", X, len(self.projection))
        out = np.full((len(X), 2), np.nan)
        for row, x in zip(out, X, strict=True):
            aim, _ = self.recall(self.code(x))
            if aim is not None:
                row[:] = aim
        return out
