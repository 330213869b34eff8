"""Image operations shared by the world's recorder and the robot: no world knowledge here."""

from __future__ import annotations

import cv2
import numpy as np

__all__ = ["face_window"]


def face_window(
    image_rgb: np.ndarray, centre_px, height_px: float, size_px: tuple[int, int] = (30, 25)
) -> np.ndarray:
    """The grayscale face window (paper: 30 x 25) cropped around ``centre_px``.

    The crop is ``height_px`` tall with the window's aspect ratio, so the face fills the
    window whatever its distance; it is then resized to ``size_px = (width, height)`` by
    area averaging. Parts of the crop outside the image repeat the border pixels.
    """
    width, height = size_px
    crop_h = max(int(round(height_px)), height)
    crop_w = max(int(round(crop_h * width / height)), width)
    gray = cv2.cvtColor(np.ascontiguousarray(image_rgb), cv2.COLOR_RGB2GRAY)
    patch = cv2.getRectSubPix(gray, (crop_w, crop_h), (float(centre_px[0]), float(centre_px[1])))
    return cv2.resize(patch, (width, height), interpolation=cv2.INTER_AREA)
