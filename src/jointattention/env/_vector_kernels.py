"""The modes without images' kernels: start episodes, check moves, step and write the looks.

Each works on every sub-environment's arrays at once (one row each): the native vector
environment's, and the single environment's (a vector of one: :mod:`._fast_trial`). They use
the package's one scene draw (:func:`~jointattention.world.fast.draw_objects`), head move and
end of a look (:func:`~jointattention.experiment.trial.move_head`, ``end_after_look``).
:func:`step_all` also writes the step's observations and ``info`` arrays, as
:func:`~._observation.scaled`, :func:`~._observation.detection_rows` and
:func:`~._observation.info_of` build them for a
:class:`~jointattention.experiment.trial.SceneTrial`: a step is one compiled call, not a dozen
small numpy ones (``tests/test_env_modes.py`` checks the two agree).
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import jit
from ..agent.attention import attended_index
from ..experiment.trial import END_FIRED, END_LIMIT, END_STEPS, RUNNING, end_after_look, move_head
from ..world.fast import detect_into, draw_index, draw_objects
from ..world.kinematics import rotation_into, separation_rad
from ._observation import _rows_into, _scale_rows_into

__all__ = ["CAM", "FLAGS", "HOLD", "NOT_FINITE", "STATE", "STEP", "clip_moves", "start_all",
           "start_step_all", "step_all"]

# The columns of a sub-environment's row of ``state`` (int64).
STATE = ("n_steps", "end", "limit_hit", "attended", "seen", "n_detections", "target", "face_k")
_N_STEPS, _END, _LIMIT, _ATTENDED, _SEEN, _N_DET, _TARGET, _FACE_K = range(len(STATE))
# The entries of ``cam`` (float64): joint limits, the camera, Eq. 3's radius, the head angle's
# scaling (v2: the joint ranges' middle and half widths).
CAM = ("lo_pan", "lo_tilt", "hi_pan", "hi_tilt", "offset_x", "offset_y", "offset_z",
       "focal_px", "width_px", "height_px", "d_th_px", "mid_pan", "mid_tilt", "half_pan",
       "half_tilt")
# What step_all does with a sub-environment that did not just start (those that did look once,
# without a move): write its look as it stands, or step it if its episode runs.
HOLD, STEP = 0, 2
# The rows of step_all's ``flags_out`` (bool) before Gymnasium's masks, which it sets True:
# terminated or truncated is the vector environment's next restart.
FLAGS = ("fired", "limit_hit", "terminated", "truncated", "ended")
NOT_FINITE = -2  # start_step_all's answer when an action is not finite (nothing is done)


@jit
def start_all(rngs, starts, targets_m, faces_m, face_radius_m, region, offset_m, limits_rad,
              theta_face_rad, cam, pos, radius, edge, state, theta) -> int:
    """Start the episodes where ``starts`` is true, each from its own generator ``rngs[i]``.

    As the single environment starts one: a data set drawn (the runner's ``random_scene``),
    its scene (:func:`~jointattention.world.fast.draw_objects`), the head at the caregiver's
    face. Returns -1, or the first sub-environment whose objects could not be placed.
    """
    for i in range(len(starts)):
        if not starts[i]:
            continue
        rng = rngs[i]
        k = draw_index(rng, len(targets_m))
        t = draw_objects(rng, targets_m[k], faces_m[k], face_radius_m, region, offset_m,
                         limits_rad, pos[i], radius[i], edge[i])
        if t < 0:
            return i
        state[i, _FACE_K], state[i, _TARGET] = k, t
        for d in range(2):
            theta[i, d] = min(max(theta_face_rad[k, d], cam[d]), cam[2 + d])
        state[i, _N_STEPS], state[i, _END], state[i, _ATTENDED] = 0, RUNNING, -1
        state[i, _LIMIT] = 0
    return -1


@jit
def clip_moves(actions, low, high, scale, out) -> bool:
    """``out`` = ``actions`` clipped to [``low``, ``high``] times ``scale``; False if not finite.

    numpy's ``np.clip(actions, low, high) * scale`` in float64, without its calls' overhead;
    nothing is written unless every action is finite.
    """
    for i in range(actions.shape[0]):
        for d in range(2):
            if not math.isfinite(actions[i, d]):
                return False
    for i in range(actions.shape[0]):
        for d in range(2):
            out[i, d] = min(max(float(actions[i, d]), float(low[d])), float(high[d])) * scale[d]
    return True


@jit(inline=True)  # into step_all: no arrays counted in and out per sub-environment
def _write_look(i, m, theta, looks, face_k, faces, bounds, scaled, with_rows, width_px,
                height_px, cam, head_out, face_out, rows_out, centre_out, det_out) -> None:
    """Sub-environment ``i``'s observation and padded detections, as the single env's.

    The head angle rounded to float32, then (v2) scaled in float64 and rounded again
    (:func:`~._observation.scaled`); the detection rows rounded then clipped
    (:func:`~._observation.detection_rows`), then (v2) scaled by the same kernel.
    """
    for d in range(2):
        angle = np.float32(theta[i, d])
        if scaled:
            angle = np.float32((np.float64(angle) - cam[11 + d]) / cam[13 + d])
        head_out[i, d] = angle
    if faces.shape[0] > 0:
        for j in range(faces.shape[1]):
            face_out[i, j] = faces[face_k, j]
    for r in range(centre_out.shape[1]):
        inside = r < m
        centre_out[i, r, 0] = looks[i, r, 0] if inside else 0.0
        centre_out[i, r, 1] = looks[i, r, 1] if inside else 0.0
        det_out[0, i, r] = looks[i, r, 2] if inside else 0.0
        det_out[1, i, r] = looks[i, r, 3] if inside else 0.0
        det_out[2, i, r] = 0.0  # the fast world's objects do not move
    if not with_rows:
        return
    rows = rows_out[i]
    rows[:] = 0
    _rows_into(looks[i, :m, :2], looks[i, :m, 2], looks[i, :m, 3], det_out[2, i, :m],
               bounds[0], bounds[1], rows)
    if scaled:
        _scale_rows_into(rows, width_px, height_px, bounds[2], bounds[3])


@jit
def step_all(starts, then, dtheta, cam, max_steps, pos, radius, edge, state, theta, looks, faces,
             bounds, scaled, with_rows, head_out, face_out, rows_out, centre_out, det_out,
             ints_out, flags_out, floats_out) -> float:
    """Look once at each episode that ``starts``, step or hold the others; write what each shows.

    ``then``: :data:`STEP` or :data:`HOLD`. A step: move (Eq. 2's command ``dtheta``), look,
    evaluate (Eq. 3), end. ``looks`` keeps each one's detections (centre x, y, colour area,
    edge). Then, per sub-environment: the observation (``head_out``, ``face_out`` from
    ``faces`` if it has rows, ``rows_out`` if ``with_rows``; ``scaled`` as v2), and ``info``'s
    arrays: the detections padded to 20 rows (``centre_out``, ``det_out``: area, edge,
    motion), ``ints_out`` (n_detections, seen, attended, target), ``flags_out`` (:data:`FLAGS`;
    rows after them set True: Gymnasium's masks) and ``floats_out`` (intrinsic and external
    reward, the caregiver's error). Returns the first sub-environment's caregiver error (-1 if
    it did not fire), for the single environment.
    """
    width_px, height_px, d_th_px = cam[8], cam[9], cam[10]
    cx, cy = (width_px - 1) / 2, (height_px - 1) / 2
    n = pos.shape[1]
    rot, ids = np.empty((3, 3)), np.empty(n, np.int64)
    offset_m = cam[4:7]
    # the faces as rows of pixels: copied so, at the speed of numpy's copy (a 3-d loop: 7x slower)
    faces = faces.reshape(faces.shape[0], faces.shape[1] * faces.shape[2])
    face_out = face_out.reshape(face_out.shape[0], face_out.shape[1] * face_out.shape[2])
    first_error = -1.0
    for i in range(theta.shape[0]):
        was_running = state[i, _END] == RUNNING
        moved = not starts[i] and then == STEP and was_running
        if starts[i] or moved:
            hit = False
            if moved:
                theta[i, 0], theta[i, 1], hit = move_head(
                    theta[i, 0], theta[i, 1], dtheta[i, 0], dtheta[i, 1], cam[0], cam[2],
                    cam[1], cam[3])
                state[i, _N_STEPS] += 1
            rotation_into(theta[i, 0], theta[i, 1], rot)
            m = detect_into(pos[i], radius[i], edge[i], rot, offset_m, cam[7], width_px,
                            height_px, looks[i, :, :2], looks[i, :, 2], looks[i, :, 3], ids)
            s = attended_index(looks[i, :m, :2], cx, cy, d_th_px)
            state[i, _N_DET], state[i, _SEEN], state[i, _LIMIT] = m, s, hit
            end = end_after_look(s, hit, state[i, _N_STEPS], max_steps)
            if not moved:  # a start's look: it may fire, nothing else ends it
                end = END_FIRED if end == END_FIRED else RUNNING
            state[i, _END] = end
            if s >= 0:
                state[i, _ATTENDED] = ids[s]
        end = state[i, _END]
        fired = end == END_FIRED
        flags_out[0, i], flags_out[1, i] = fired, state[i, _LIMIT] != 0
        flags_out[2, i] = moved and (fired or end == END_LIMIT)
        flags_out[3, i] = moved and end == END_STEPS
        flags_out[4, i] = flags_out[2, i] or flags_out[3, i]
        for r in range(5, flags_out.shape[0]):
            flags_out[r, i] = True
        m, attended, target = state[i, _N_DET], state[i, _ATTENDED], state[i, _TARGET]
        ints_out[0, i], ints_out[1, i] = m, state[i, _SEEN] if fired else -1
        ints_out[2, i], ints_out[3, i] = attended, target
        error = separation_rad(pos[i, attended], pos[i, target]) if fired else -1.0
        floats_out[0, i] = 1.0 if fired else 0.0
        floats_out[1, i] = 1.0 if fired and attended == target else 0.0
        floats_out[2, i] = error
        if i == 0:
            first_error = error
        _write_look(i, m, theta, looks, state[i, _FACE_K], faces, bounds, scaled, with_rows,
                    width_px, height_px, cam, head_out, face_out, rows_out, centre_out,
                    det_out)
    return first_error


@jit
def start_step_all(rngs, targets_m, faces_m, face_radius_m, region, offset_m, limits_rad,
                   theta_face_rad, starts, then, actions, clip, dtheta, cam, max_steps, pos,
                   radius, edge, state, theta, looks, faces, bounds, scaled, with_rows, head_out,
                   face_out, rows_out, centre_out, det_out, ints_out, flags_out,
                   floats_out) -> int:
    """The native vector environment's step: the moves, :func:`start_all`, :func:`step_all`.

    One compiled call instead of three: each call's thirty-odd arguments are typed and unboxed
    anew. ``actions`` are clipped to ``clip``'s first two rows and scaled by its third into
    ``dtheta`` (:func:`clip_moves`); :data:`NOT_FINITE` if one is not, and nothing is done.
    Else :func:`start_all`'s value, and the step if every start placed its objects.
    """
    if not clip_moves(actions, clip[0], clip[1], clip[2], dtheta):
        return NOT_FINITE
    failed = start_all(rngs, starts, targets_m, faces_m, face_radius_m, region, offset_m,
                       limits_rad, theta_face_rad, cam, pos, radius, edge, state, theta)
    if failed < 0:
        step_all(starts, then, dtheta, cam, max_steps, pos, radius, edge, state, theta, looks,
                 faces, bounds, scaled, with_rows, head_out, face_out, rows_out, centre_out,
                 det_out, ints_out, flags_out, floats_out)
    return failed
