"""Visual attention and self-evaluation: the paper's Eq. 1, 2 and 3."""

from __future__ import annotations

import numpy as np

from .detections import Detections

__all__ = ["attended_object", "most_interesting", "visual_feedback"]


def most_interesting(det: Detections, weights) -> int | None:
    """Eq. 1: i_trg = argmax_i (a1 f_col + a2 f_edge + a3 f_mot); None if nothing is seen."""
    if len(det) == 0:
        return None
    a1, a2, a3 = weights
    return int(np.argmax(a1 * det.colour_area_px + a2 * det.edge + a3 * det.motion))


def visual_feedback(det: Detections, i: int, gain_rad_per_px: float) -> np.ndarray:
    """Eq. 2: VF dtheta = g (x_i - c_x, y_i - c_y), as (pan, tilt).

    Image y grows downward and tilt grows upward, hence the sign of the tilt component.
    """
    dx, dy = det.centre_px[i] - det.image_centre_px
    return gain_rad_per_px * np.array([dx, -dy])


def attended_object(det: Detections, d_th_px: float) -> int | None:
    """Eq. 3: the object within d_th of the image centre (the nearest), else None.

    This is the internal evaluator: it knows that visual attention succeeded, not whether
    joint attention did.
    """
    if len(det) == 0:
        return None
    dist = np.hypot(*(det.centre_px - det.image_centre_px).T)
    i = int(np.argmin(dist))
    return i if dist[i] < d_th_px else None
