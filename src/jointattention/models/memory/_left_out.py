"""Places the episodic memory leaves out of a face's recalls (``memory.leave_out_empty``).

A data set's target does not move. So when the head reaches the place the memory recalled
for a face (within one step of it) and no object is near the view's centre (within the voting
radius, in pixels through Eq. 2's gain), that place is not the face's target: the memory
leaves it out of that face's recalls from then on, and the place that agrees most among the
others is recalled instead (:func:`~.episodic.recall_at_distances`). Everything it uses is the
robot's own: its recall, its head angle and its detections.

The places are kept with the face's code in a ring as long as the memory's capacity (the
oldest forgotten first), and a face finds its own by its exact code: a face that recurs pixel
for pixel, as a data set's does. A face seen through noise seldom recurs exactly, and then
nothing is left out.

With ``memory.pass_over_left_out``, visual attention also passes over an object that lies at a
place left out of the face's recalls (:func:`passed_over_into`): the target is never there, so
the object is a distractor. A face whose target lies far from the distractors, which visual
attention alone seldom reaches, is then searched beyond the places already found wanting.
With ``memory.drop_left_out`` the memory does not keep such a place when the evaluator fires
(:func:`drop_left_out_from`): it would only be a distractor's vote.
"""

from __future__ import annotations

import numpy as np

from ..._jit import jit
from ...agent.attention import visual_feedback_rad
from ._recall import same_code

__all__ = ["drop_left_out_from", "empty_arrival", "leave_out", "left_out_into", "left_out_of",
           "near_any", "passed_over_into"]


@jit
def empty_arrival(aim_pan_rad, aim_tilt_rad, pan_rad, tilt_rad, step_rad, centre_px, cx, cy,
                  radius_px) -> bool:
    """Whether the head is within a step of the recalled place with no object near the centre.

    ``centre_px`` (m, 2): the detected objects' centres; ``(cx, cy)``: the view's centre.
    """
    if (pan_rad - aim_pan_rad) ** 2 + (tilt_rad - aim_tilt_rad) ** 2 >= step_rad * step_rad:
        return False
    return not near_any(cx, cy, centre_px, radius_px * radius_px)


@jit
def leave_out(code, pan_rad, tilt_rad, left_codes, left_aims, n_left: int) -> int:
    """Leave a place out of the recalls of face ``code``; returns the places left out so far.

    Slot ``n_left % capacity`` of ``left_codes`` (code length, capacity: entry-major, as the
    memory's codes) and ``left_aims`` (capacity, 2), forgetting the oldest when full.
    """
    slot = n_left % len(left_aims)
    for j in range(len(code)):
        left_codes[j, slot] = code[j]
    left_aims[slot, 0], left_aims[slot, 1] = pan_rad, tilt_rad
    return n_left + 1


@jit
def left_out_of(code, left_codes, left_aims, n_left: int) -> np.ndarray:
    """The places left out of face ``code``'s recalls, (m, 2)."""
    out = np.empty((min(n_left, len(left_aims)), 2))
    return out[:left_out_into(code, left_codes, left_aims, n_left, out)]


@jit
def left_out_into(code, left_codes, left_aims, n_left: int, out) -> int:
    """:func:`left_out_of` into the first rows of ``out`` (as long as ``left_aims``); how many."""
    m = 0
    for s in range(min(n_left, len(left_aims))):
        if same_code(left_codes[:, s], code):
            out[m, 0], out[m, 1] = left_aims[s, 0], left_aims[s, 1]
            m += 1
    return m


@jit
def near_any(pan_rad, tilt_rad, places, r2) -> bool:
    """Whether a place is closer than ``sqrt(r2)`` to any of ``places`` (m, 2)."""
    for i in range(len(places)):
        if (pan_rad - places[i, 0]) ** 2 + (tilt_rad - places[i, 1]) ** 2 < r2:
            return True
    return False


@jit
def passed_over_into(centre_px, cx, cy, gain_rad_per_px, pan_rad, tilt_rad, left_out,
                     radius_rad, out) -> None:
    """Which detections visual attention passes over: ``out[i]``, a bool per detection.

    A detection's place is the head angle plus Eq. 2's step to it (``centre_px`` (m, 2), the
    view's centre ``(cx, cy)``); it is passed over if it lies within ``radius_rad`` of one of
    the face's places ``left_out`` (k, 2).
    """
    r2 = radius_rad * radius_rad
    for i in range(len(centre_px)):
        d_pan, d_tilt = visual_feedback_rad(centre_px[i, 0], centre_px[i, 1], cx, cy,
                                            gain_rad_per_px)
        out[i] = near_any(pan_rad + d_pan, tilt_rad + d_tilt, left_out, r2)


@jit
def drop_left_out_from(places, n: int, left_out, radius_rad) -> int:
    """Drop those of the first ``n`` ``places`` (rows, 2) within ``radius_rad`` of ``left_out``.

    The others move to the front, in order; returns how many they are.
    """
    r2, kept = radius_rad * radius_rad, 0
    for i in range(n):
        if not near_any(places[i, 0], places[i, 1], left_out, r2):
            places[kept, 0], places[kept, 1] = places[i, 0], places[i, 1]
            kept += 1
    return kept
