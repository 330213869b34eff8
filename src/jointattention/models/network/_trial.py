"""The network module's compiled kernels: a trial's start, its commands and its learning.

:class:`~.module.NetworkModule` (the step-by-step agent) and the compiled engine's loop call
the same kernels on the same arrays (:class:`NetworkArrays`), so both engines learn the same
bits. :data:`KERNELS` are its part of a trial
(:class:`~jointattention.agent.protocol.ModuleKernels`): the compiled loop is handed them.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..._jit import jit
from ...agent.face_standardiser import standardise
from ...agent.moves import learning_samples, scale_angle_into
from ...agent.protocol import ModuleKernels
from ._backprop import face_part, sgd_rows_from
from .command import network_command

__all__ = ["KERNELS", "NetworkArrays", "network_begin", "network_command_of",
           "network_direction", "network_learn"]


class NetworkArrays(NamedTuple):
    """The network's options, weights and scratch, as the kernels take them.

    The arrays are the agent's own (its network's weights and momentum terms and its face
    statistics, changed in place); ``counters`` holds the updates made (see
    :meth:`~.module.NetworkModule.compiled_state`).
    """

    theta_mid_rad: np.ndarray  # the head angle's scaling to [-1, 1]
    theta_half_rad: np.ndarray
    min_std: float  # of the face statistics
    learning_rate: float
    momentum: float
    n_passes: int  # back-propagation passes over a trial's samples
    executed_step: bool  # learn toward the steps taken (learning_target = "executed_step")
    w1: np.ndarray
    b1: np.ndarray
    w2: np.ndarray
    b2: np.ndarray
    v1: np.ndarray
    vb1: np.ndarray
    v2: np.ndarray
    vb2: np.ndarray
    face_mean: np.ndarray  # the agent's face statistics (FaceStandardiser), shared
    face_m2: np.ndarray
    faces_seen: np.ndarray  # (1,): their count, FaceStandardiser.seen
    counters: np.ndarray  # (1,): updates made
    face_x: np.ndarray  # the trial's face, standardised
    face_acc: np.ndarray  # its part of the hidden units' input (fixed for the trial)
    acc: np.ndarray  # scratch: the hidden units' input, outputs, output, scaled angle
    hidden: np.ndarray
    out: np.ndarray
    scaled: np.ndarray


@jit
def network_begin(s, face, face_id, pan, tilt, learning) -> float:
    """The trial starts: the face, standardised by the agent's statistics, fixed for it.

    Its part of the hidden units' input is summed once (the weights change only at the
    trial's end). The network keeps no evidence: 0.0.
    """
    standardise(face, s.face_mean, s.face_m2, s.faces_seen[0], s.min_std, s.face_x)
    face_part(s.face_x, s.w1, s.face_acc)
    return 0.0


@jit(inline=True)  # into the compiled loop: its arrays not counted in and out at every step
def network_direction(s, pan, tilt, step_rad) -> tuple[float, float]:
    """The network's command at a head angle (:func:`~.command.network_command`)."""
    return network_command(s.face_acc, pan, tilt, s.w1, s.b1, s.w2, s.b2, s.theta_mid_rad,
                           s.theta_half_rad, step_rad, s.acc, s.scaled, s.hidden, s.out)


@jit(inline=True)
def network_command_of(s, pan, tilt, step_rad, rng) -> tuple[float, float]:
    """The module's step: :func:`network_direction` (it draws nothing from ``rng``)."""
    return network_direction(s, pan, tilt, step_rad)


@jit
def network_learn(s, place, centre, seen, pan, tilt, cx, cy, gain_rad_per_px, face, thetas,
                  steps, rng) -> int:
    """Teach each of the trial's steps toward ``place`` (or its own step); returns how many.

    ``n_passes`` back-propagation passes over the samples, the face every sample's input
    (shared inputs: :func:`~._backprop.sgd_rows_from`).
    """
    n_steps = len(thetas)
    y, angles_x = np.empty((n_steps, 2)), np.empty((n_steps, 2))
    keep = learning_samples(thetas, steps, place, s.executed_step, y)
    n_kept = 0
    for k in range(n_steps):  # the kept steps' scaled head angles and aims, in order
        if keep[k]:
            scale_angle_into(thetas[k, 0], thetas[k, 1], s.theta_mid_rad, s.theta_half_rad,
                             angles_x[n_kept], 0)
            y[n_kept, 0], y[n_kept, 1], n_kept = y[k, 0], y[k, 1], n_kept + 1
    for p in range(s.n_passes):
        if p > 0:  # face_acc, the face's part summed at the trial's start, is stale
            face_part(s.face_x, s.w1, s.face_acc)
        sgd_rows_from(s.face_acc, s.face_x, angles_x[:n_kept], y[:n_kept], s.w1, s.b1, s.w2,
                      s.b2, s.v1, s.vb1, s.v2, s.vb2, s.learning_rate, s.momentum)
        s.counters[0] += n_kept
    return n_kept


KERNELS = ModuleKernels(network_begin, network_command_of, network_direction, network_learn)
