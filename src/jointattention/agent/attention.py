"""Visual attention and self-evaluation: the paper's Eq. 1, 2 and 3.

Each equation is one compiled kernel on plain arrays (the compiled engine calls them inside
its loop); the functions on :class:`~.detections.Detections` call the same kernels.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import jit
from .detections import Detections

__all__ = [
    "attended_index",
    "attended_object",
    "interest_argmax",
    "largest_feedback_rad",
    "most_interesting",
    "visual_feedback",
    "visual_feedback_rad",
]


@jit
def interest_argmax(colour_area_px, edge, motion, a1, a2, a3, passed_over=None) -> int:
    """Eq. 1: i_trg = argmax_i (a1 f_col + a2 f_edge + a3 f_mot); -1 if nothing is seen.

    The objects flagged in ``passed_over`` (a bool per object, or None) are not candidates
    (a place left out of the face's recalls, ``memory.pass_over_left_out``); -1 if no other is
    seen.
    """
    best, best_i = -np.inf, -1
    for i in range(len(colour_area_px)):
        if passed_over is not None and passed_over[i]:
            continue
        score = a1 * colour_area_px[i] + a2 * edge[i] + a3 * motion[i]
        if best_i < 0 or score > best:  # the first of equal scores, as numpy's argmax
            best, best_i = score, i
    return best_i


@jit
def visual_feedback_rad(x_px, y_px, cx_px, cy_px, gain_rad_per_px) -> tuple[float, float]:
    """Eq. 2: VF dtheta = g (x_i - c_x, y_i - c_y), as (pan, tilt).

    Image y grows downward and tilt grows upward, hence the sign of the tilt component.
    """
    return gain_rad_per_px * (x_px - cx_px), gain_rad_per_px * -(y_px - cy_px)


def largest_feedback_rad(width_px: int, height_px: int, gain_rad_per_px: float) -> float:
    """The longest move Eq. 2 makes: to an object at a corner of a W x H image."""
    return gain_rad_per_px * math.hypot((width_px - 1) / 2, (height_px - 1) / 2)


@jit
def attended_index(centre_px, cx_px, cy_px, d_th_px) -> int:
    """Eq. 3: the object within d_th of the image centre (the nearest), else -1."""
    best, best_i = np.inf, -1
    for i in range(centre_px.shape[0]):
        dist = math.hypot(centre_px[i, 0] - cx_px, centre_px[i, 1] - cy_px)
        if best_i < 0 or dist < best:
            best, best_i = dist, i
    return best_i if best_i >= 0 and best < d_th_px else -1


def _floats(a) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=float)


def most_interesting(det: Detections, weights, passed_over=None) -> int | None:
    """Eq. 1 on a detector's report (:func:`interest_argmax`); None if nothing is seen.

    ``passed_over``: a bool per detection, those not to attend (or None).
    """
    a1, a2, a3 = (float(w) for w in weights)
    i = interest_argmax(_floats(det.colour_area_px), _floats(det.edge), _floats(det.motion),
                        a1, a2, a3, passed_over)
    return None if i < 0 else i


def visual_feedback(det: Detections, i: int, gain_rad_per_px: float) -> np.ndarray:
    """Eq. 2 toward detection ``i`` (:func:`visual_feedback_rad`), as an array (pan, tilt)."""
    cx, cy = det.image_centre_px
    x, y = det.centre_px[i]
    return np.array(visual_feedback_rad(float(x), float(y), cx, cy, float(gain_rad_per_px)))


def attended_object(det: Detections, d_th_px: float) -> int | None:
    """Eq. 3 on a detector's report (:func:`attended_index`); None if no object is there.

    This is the internal evaluator: it knows that visual attention succeeded, not whether
    joint attention did.
    """
    cx, cy = det.image_centre_px
    i = attended_index(_floats(det.centre_px).reshape(-1, 2), cx, cy, float(d_th_px))
    return None if i < 0 else i
