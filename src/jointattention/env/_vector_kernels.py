"""The native vector environment's kernels: start the episodes that start, step the running.

Both work on every sub-environment's arrays at once (one row each), with the package's one
scene draw (:func:`~jointattention.world.fast.draw_objects`), head move and end of a look
(:func:`~jointattention.experiment.trial.move_head`, ``end_after_look``).
"""

from __future__ import annotations

import numpy as np

from .._jit import jit
from ..agent.attention import attended_index
from ..experiment.trial import RUNNING, end_after_look, move_head
from ..world.fast import detect_into, draw_index, draw_objects
from ..world.kinematics import rotation_into
from ._looks import _rows_into

__all__ = ["rows_all", "start_all", "step_all"]


@jit
def start_all(rngs, which, targets_m, faces_m, face_radius_m, region, offset_m, limits_rad,
              theta_face_rad, lo, hi, pos, radius, edge, face_k, target, theta, n_steps, end,
              attended, limit_hit) -> int:
    """Start the episodes of ``which``, each from its own generator ``rngs[i]``.

    As the single environment starts one: a data set drawn (the runner's ``random_scene``),
    its scene (:func:`~jointattention.world.fast.draw_objects`), the head at the caregiver's
    face. Returns -1, or the first sub-environment whose objects could not be placed.
    """
    for j in range(len(which)):
        i = which[j]
        rng = rngs[i]
        k = draw_index(rng, len(targets_m))
        t = draw_objects(rng, targets_m[k], faces_m[k], face_radius_m, region, offset_m,
                         limits_rad, pos[i], radius[i], edge[i])
        if t < 0:
            return i
        face_k[i], target[i] = k, t
        for d in range(2):
            theta[i, d] = min(max(theta_face_rad[k, d], lo[d]), hi[d])
        n_steps[i], end[i], attended[i], limit_hit[i] = 0, RUNNING, -1, False
    return -1


@jit
def step_all(theta, dtheta, lo, hi, pos, radius, edge, n_objects, offset_m, focal_px, width_px,
              height_px, d_th_px, max_steps, n_steps, end, limit_hit, attended, seen, n_det,
              centre, area, seen_edge, ids):
    """One step of every running episode: move (Eq. 2's command), look, evaluate (Eq. 3)."""
    cx, cy = (width_px - 1) / 2, (height_px - 1) / 2
    rot = np.empty((3, 3))
    for i in range(theta.shape[0]):
        if end[i] != RUNNING:
            continue
        theta[i, 0], theta[i, 1], hit = move_head(theta[i, 0], theta[i, 1], dtheta[i, 0],
                                                  dtheta[i, 1], lo[0], hi[0], lo[1], hi[1])
        n_steps[i] += 1
        limit_hit[i] = hit
        n = n_objects
        rotation_into(theta[i, 0], theta[i, 1], rot)
        m = detect_into(pos[i, :n], radius[i, :n], edge[i, :n], rot, offset_m, focal_px,
                        width_px, height_px, centre[i], area[i], seen_edge[i], ids[i])
        n_det[i] = m
        s = attended_index(centre[i, :m], cx, cy, d_th_px)
        seen[i] = s
        end[i] = end_after_look(s, hit, n_steps[i], max_steps)
        if s >= 0:
            attended[i] = ids[i, s]


@jit
def rows_all(centre, area, edge, n_det, low, high, out) -> None:
    """Every sub-environment's detection rows into ``out`` (zeros), as ``detection_rows``."""
    motion = np.zeros(area.shape[1])  # the fast world's objects do not move
    for i in range(len(n_det)):
        m = n_det[i]
        _rows_into(centre[i, :m], area[i, :m], edge[i, :m], motion[:m], low, high, out[i])
