"""The eye window a robot cuts from a camera frame of its own: where BlazeFace puts the eyes.

A model that reads the caregiver's eyes learned from eye windows that the simulator cut
(:func:`jointattention.world.recording.eye_window_at`). On a camera frame the robot places
the window itself: BlazeFace's two eye landmarks give the eyes' midpoint and their distance,
and a field ``span`` eye distances wide around the midpoint is cut and resampled to the window.

BlazeFace sees a whole frame shrunk to 128 pixels, where the eyes are a few pixels apart. A
second look, at a square :data:`SECOND_LOOK_FACES` face boxes wide around the face it found,
places them about twice as close to the eyeballs' centres on the people world's views
(``tests/test_eye_windows.py`` holds it closer; ``docs/results/people/eye_placement.md``
gives its error and what each placement costs an eye model).

Layer 2 (the robot's parts): imports only the plumbing and its sibling modules.
"""

from __future__ import annotations

import numpy as np

from .blazeface import BlazeFace

__all__ = ["SECOND_LOOK_FACES", "eye_landmarks", "eye_window_of"]

# The second look's side in face boxes: 1.5 and 3 boxes placed the eyes a median 0.084 and
# 0.089 eye distances off, 2 boxes 0.076 (96 people-world views).
SECOND_LOOK_FACES = 2.0


def eye_landmarks(net: BlazeFace, frame_rgb: np.ndarray) -> tuple[np.ndarray, float] | None:
    """The midpoint of the caregiver's eyes and their distance, in pixels of ``frame_rgb``.

    BlazeFace finds the face in the frame, then looks again at a square around it
    (:data:`SECOND_LOOK_FACES` face boxes wide, padded with black where it leaves the frame)
    and gives its two eye landmarks. None if it finds no face in either look.
    """
    found = net.detect(frame_rgb)
    if not found:
        return None
    x, y, w, h = found[0].box_px
    side = max(1, int(round(SECOND_LOOK_FACES * max(w, h))))
    x0, y0 = int(round(x + w / 2 - side / 2)), int(round(y + h / 2 - side / 2))
    crop = np.zeros((side, side, 3), np.uint8)
    fh, fw = frame_rgb.shape[:2]
    sx, sy = max(x0, 0), max(y0, 0)
    ex, ey = min(x0 + side, fw), min(y0 + side, fh)
    crop[sy - y0:ey - y0, sx - x0:ex - x0] = frame_rgb[sy:ey, sx:ex]
    close = net.detect(crop)
    if not close:
        return None
    eyes = close[0].landmarks_px[:2] + (x0, y0)
    return eyes.mean(axis=0), float(np.linalg.norm(eyes[0] - eyes[1]))


def eye_window_of(grey: np.ndarray, centre_px, distance_px: float, size_px: tuple[int, int],
                  span: float) -> np.ndarray:
    """The eye window of ``size_px`` (width, height) cut from a grey frame around the eyes.

    The field is ``span`` times ``distance_px`` wide, centred at ``centre_px`` (sub-pixel), of
    the window's aspect; it is averaged down to the window where the frame holds more pixels
    than the window, and interpolated up where fewer (as the simulator's fovea, no finer than
    its sensor). Returns (height, width) uint8.
    """
    import cv2

    width, height = size_px
    field_w = max(1, int(round(span * distance_px)))
    field_h = max(1, int(round(field_w * height / width)))
    # in floats, rounded once at the end: a sub-pixel cut rounded to uint8 shifts every grey
    # level alike, by up to half a level
    field = cv2.getRectSubPix(np.ascontiguousarray(grey, np.float32), (field_w, field_h),
                              (float(centre_px[0]), float(centre_px[1])))
    shrink = field_w >= width
    window = cv2.resize(field, (width, height),
                        interpolation=cv2.INTER_AREA if shrink else cv2.INTER_LINEAR)
    return np.clip(np.rint(window), 0, 255).astype(np.uint8)
