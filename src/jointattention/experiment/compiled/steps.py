"""The parts of a trial that both compiled loops share: drawing it, one look, its record.

:mod:`._loop` (the bootstrap family) and :mod:`._rl_loop` (an agent whose whole trial is its
own kernels: the reinforcement learner) call them in the order of the step-by-step path's draws
(:func:`~.cells.random_scene`, then :class:`~.trial.SceneTrial`'s looks).
"""

from __future__ import annotations

import numpy as np

from ..._jit import jit
from ...agent.attention import attended_index
from ...world.fast import detect_into, draw_index, draw_objects
from ...world.kinematics import rotation_into
from ..trial import END_FIRED, end_after_look

__all__ = ["draw_trial", "look", "look_arrays", "look_camera", "record_trial"]


@jit
def look_arrays(n: int):
    """A look's arrays for ``n`` objects: the head's rotation and what the detector reports.

    (rotation, centre, seen_area, seen_edge, ids); :func:`look` fills them.
    """
    return (np.empty((3, 3)), np.empty((n, 2)), np.empty(n), np.empty(n),
            np.empty(n, dtype=np.int64))


@jit
def look_camera(world, d_th_px: float):
    """What a look needs of the camera: (offset_m, focal_px, width_px, height_px, d_th_px).

    Taken from ``world`` once per loop: numba counts each array a compiled function is handed
    in and out at every call (``NRT_incref``, ``NRT_decref``), and the world holds seven.
    """
    return world.offset_m, world.focal_px, world.width_px, world.height_px, d_th_px


@jit
def draw_trial(world, trials_rng, shuffle_rng, obj_pos, obj_rad, edge) -> tuple[int, int, int]:
    """A trial's data set, objects and face: (data set k, the target, the face's data set).

    The objects go into ``obj_pos``, ``obj_rad`` and ``edge``. The target is -1 if they
    could not be placed (then no face is drawn).
    """
    k = draw_index(trials_rng, len(world.faces))
    target = draw_objects(trials_rng, world.target_m[k], world.face_m[k], world.face_radius_m,
                          world.region, world.offset_m, world.limits_rad, obj_pos, obj_rad, edge)
    if target < 0:
        return k, target, k
    return k, target, draw_index(shuffle_rng, len(world.faces)) if world.shuffle_faces else k


@jit
def look(obj_pos, obj_rad, edge, pan, tilt, camera, limit_hit, n_steps, max_steps,
         arrays) -> tuple[int, int, int, int]:
    """One look at head angle (pan, tilt): (detections, the centre's, the end, the attended).

    ``camera`` is :func:`look_camera`'s. The detections (how many) fill ``arrays``
    (:func:`look_arrays`); the centre's is the detection within the camera's ``d_th_px`` of the
    image centre (Eq. 3; -1 if none); the end is :func:`~.trial.end_after_look`'s; the attended
    is the experimenter's id of the object the evaluator fired on (-1 if it did not).
    """
    offset_m, focal_px, width_px, height_px, d_th_px = camera
    rot, centre, seen_area, seen_edge, ids = arrays
    rotation_into(pan, tilt, rot)
    m = detect_into(obj_pos, obj_rad, edge, rot, offset_m, focal_px, width_px, height_px,
                    centre, seen_area, seen_edge, ids)
    seen = attended_index(centre[:m], (width_px - 1) / 2, (height_px - 1) / 2, d_th_px)
    end = end_after_look(seen, limit_hit, n_steps, max_steps)
    return m, seen, end, ids[seen] if end == END_FIRED else -1


@jit(inline=True)
def record_trial(records, c, start, n_steps, n_lm, n_random, attended, target, end) -> None:
    """A trial's row of :data:`~._loop.COLUMNS` (``c[1]``: the rows so far); one more counted."""
    r = c[1]
    records[0, r], records[1, r], records[2, r], records[3, r] = start, n_steps, n_lm, n_random
    records[4, r], records[5, r], records[6, r] = attended, target, end
    c[1] += 1
