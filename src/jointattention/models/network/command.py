"""The network's command: the direction of its output at a head angle, for one face or many.

:func:`network_command` is the module's ``command`` and ``direction`` kernels' (:mod:`._trial`,
which both engines call, inlined into the compiled loop) and its command outside a trial
(:mod:`.module`); :func:`lm_commands_into` computes it for a batch of faces (probes and
held-out measures).
"""

from __future__ import annotations

import numpy as np

from ..._jit import jit
from ...agent.face_standardiser import standardise
from ...agent.moves import scale_angle_into, unit_step
from ._backprop import accumulate, face_part, forward

__all__ = ["lm_commands_into", "network_command"]


@jit(inline=True)  # into its callers: nine arrays not counted in and out at each call
def network_command(face_acc, pan, tilt, w1, b1, w2, b2, theta_mid_rad, theta_half_rad,
                    step_rad, acc, scaled, hidden, out) -> tuple[float, float]:
    """The network's command at head angle (``pan``, ``tilt``): its output's direction.

    ``face_acc`` is the face's part of the hidden input (:func:`~.learner.face_part`); the
    head angle's is added in ``acc``. ``acc``, ``scaled``, ``hidden`` and ``out`` are
    scratch space.
    """
    for i in range(len(acc)):  # element by element: quicker for numba to compile
        acc[i] = face_acc[i]
    scale_angle_into(pan, tilt, theta_mid_rad, theta_half_rad, scaled, 0)
    accumulate(scaled, w1, w1.shape[1] - 2, acc)
    forward(acc, b1, w2, b2, hidden, out)
    return unit_step(out[0], out[1], step_rad)


@jit
def lm_commands_into(faces, thetas_rad, mean, m2, n_seen, min_std, w1, b1, w2, b2,
                     theta_mid_rad, theta_half_rad, step_rad, out) -> None:
    """The learning module's command for each face window (K, pixels) and head angle (K, 2).

    As :meth:`BootstrapAgent.lm_command` computes it, one row at a time, into ``out`` (K, 2).
    """
    n_pix = faces.shape[1]
    x, scaled = np.empty(n_pix), np.empty(2)
    face_acc, acc = np.empty(len(b1)), np.empty(len(b1))
    h, o = np.empty(len(b1)), np.empty(w2.shape[1])
    for k in range(len(faces)):
        standardise(faces[k], mean, m2, n_seen, min_std, x)
        face_part(x, w1, face_acc)
        out[k, 0], out[k, 1] = network_command(face_acc, thetas_rad[k, 0], thetas_rad[k, 1],
                                               w1, b1, w2, b2, theta_mid_rad, theta_half_rad,
                                               step_rad, acc, scaled, h, o)
