"""The ``jointattention follow`` overlay: a frame with what the saved model made of it.

The face window's box (green), the face finder's landmarks where it gives them (yellow:
BlazeFace's eyes, nose, mouth and ears), the window itself magnified in the corner with the
module's direction drawn from its centre (red, as in the paper's Fig. 6), below it what a model
that reads the eyes read of them (its eye window or socket patches), and from the image
centre the line along which the head will turn (red arrow; pan right is image right, tilt up
is image up).
"""

from __future__ import annotations

import cv2
import numpy as np

from .follower import Look

__all__ = ["draw_look"]

GREEN, RED, WHITE, BLACK = (0, 230, 0), (255, 40, 40), (255, 255, 255), (0, 0, 0)
YELLOW = (255, 220, 0)


def _text(out: np.ndarray, text: str, org: tuple[int, int], scale: float, thick: int) -> None:
    cv2.putText(out, text, org, cv2.FONT_HERSHEY_SIMPLEX, scale, BLACK, 3 * thick)
    cv2.putText(out, text, org, cv2.FONT_HERSHEY_SIMPLEX, scale, WHITE, thick)


def draw_look(frame_rgb: np.ndarray, look: Look | None) -> np.ndarray:
    """The frame with the face window, the window magnified and the command's line drawn."""
    out = np.ascontiguousarray(frame_rgb).copy()
    h, w = out.shape[:2]
    thick, scale = max(1, min(h, w) // 240), max(0.35, min(h, w) / 700)
    if look is None:
        _text(out, "no face found", (8, int(24 * scale * 1.6)), scale, thick)
        return out
    wh, ww = look.window.shape
    crop_h = max(int(round(look.face.height_px)), wh)
    crop_w = max(int(round(crop_h * ww / wh)), ww)
    cx, cy = look.face.centre_px
    cv2.rectangle(out, (int(cx - crop_w / 2), int(cy - crop_h / 2)),
                  (int(cx + crop_w / 2), int(cy + crop_h / 2)), GREEN, 2 * thick)
    if look.face.landmarks_px is not None:
        for x, y in look.face.landmarks_px:
            cv2.circle(out, (int(round(x)), int(round(y))), 2 * thick, YELLOW, -1)
    direction = np.array([look.command_rad[0], -look.command_rad[1]])
    direction = direction / max(float(np.hypot(*direction)), 1e-12)
    centre = np.array([w / 2, h / 2])
    tip = centre + direction * 0.35 * min(h, w)
    cv2.arrowedLine(out, tuple(int(v) for v in centre), tuple(int(v) for v in tip), RED,
                    2 * thick, tipLength=0.12)
    # the window, magnified to a quarter of the frame's height, in the top-left corner
    zoom = max(1, int(h / 4 / wh))
    inset = cv2.cvtColor(cv2.resize(look.window, (ww * zoom, wh * zoom),
                                    interpolation=cv2.INTER_NEAREST), cv2.COLOR_GRAY2RGB)
    ic = np.array([ww * zoom / 2, wh * zoom / 2])
    cv2.line(inset, tuple(int(v) for v in ic),
             tuple(int(v) for v in ic + direction * 0.45 * wh * zoom), RED, max(1, zoom // 3))
    iy = min(h - inset.shape[0], int(30 * scale * 1.6))
    out[iy:iy + inset.shape[0], :inset.shape[1]] = inset[:, :w]
    if look.eyes is not None:  # what the model read of the eyes, as wide, below the window
        eh, ew = look.eyes.shape
        size = (inset.shape[1], max(1, round(eh * inset.shape[1] / ew)))
        eyes = cv2.cvtColor(cv2.resize(look.eyes, size, interpolation=cv2.INTER_NEAREST),
                            cv2.COLOR_GRAY2RGB)
        ey = iy + inset.shape[0]
        rows = min(eyes.shape[0], h - ey)
        out[ey:ey + rows, :eyes.shape[1]] = eyes[:rows, :w]
    dpan, dtilt = np.rad2deg(look.command_rad)
    _text(out, f"command: pan {dpan:+.1f} deg, tilt {dtilt:+.1f} deg",
          (8, int(20 * scale * 1.6)), scale, thick)
    return out
