"""The paper's Fig. 6 and Fig. 7, and the learning module's angle error, drawn.

:func:`jointattention.jobs.learned.write_gaze_figures` computes what they show.
"""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
from PIL import Image

from .._files import atomic_path
from ..experiment import probes
from ._save import new_figure, save_figure

__all__ = ["PAN_DEG", "TILT_DEG", "error_figure", "fig6", "fig7"]

PAN_DEG = (-40, -20, 0, 20, 40)
TILT_DEG = (15, 0, -15, -30)
UNSEEN_DEG = 5.0  # a grid direction farther than this from every data set's is unseen


def fig6(agent, faces, thetas, commands, seen_commands, path: Path) -> dict:
    """Face windows of the grid with the module's output and the true direction.

    The output in red, the true direction in white (thin); unseen directions titled in blue.
    """
    rows, cols = faces.shape[:2]
    fig = new_figure(2.0 * cols, 1.8 * rows)
    axes = fig.subplots(rows, cols)
    errors, unseen = [], []
    for i in range(rows):
        for j in range(cols):
            ax = axes[i, j]
            face, out = faces[i, j], agent.lm_command(faces[i, j], thetas[i, j])
            h, w = face.shape
            ax.imshow(face, cmap="gray", vmin=0, vmax=255)
            centre = np.array([(w - 1) / 2, (h - 1) / 2])
            for vec, style in ((commands[i, j], dict(color="w", lw=1)),
                               (out, dict(color="r", lw=2.5))):
                d = vec / np.linalg.norm(vec) * 0.45 * h
                ax.plot(*np.array([centre, centre + [d[0], -d[1]]]).T, **style)
            near = float(np.min(probes.angle_deg(seen_commands, commands[i, j])))
            err = float(probes.angle_deg(out, commands[i, j]))
            is_unseen = near > UNSEEN_DEG
            errors.append(err)
            unseen.append(is_unseen)
            ax.set_title(f"pan {PAN_DEG[j]}, tilt {TILT_DEG[i]}\nerror {err:.0f}°",
                         fontsize=7, color="tab:blue" if is_unseen else "k")
            ax.set_xticks([])
            ax.set_yticks([])
    fig.suptitle("Learning module's output (red) and the true direction (white) on the "
                 "caregiver's face window\ntarget 0.65 m away in each direction; blue: "
                 f"no data set within {UNSEEN_DEG:.0f}°", fontsize=9)
    save_figure(fig, path, dpi=130)
    errors, unseen = np.array(errors), np.array(unseen)
    return {"grid_median_error_deg": float(np.median(errors)),
            "grid_unseen": int(unseen.sum()),
            "grid_unseen_median_error_deg": float(np.median(errors[unseen]))
            if unseen.any() else None}


def error_figure(curve: dict[int, tuple[float, float]], path: Path) -> None:
    """Median angle error against learning time, on the data sets and on held-out poses."""
    t = np.array(list(curve)) / 1e4
    train, held = np.array(list(curve.values())).T
    fig = new_figure(5.5, 3.4)
    ax = fig.subplots()
    ax.plot(t, train, "o-", label="the 125 data sets (learned from)")
    ax.plot(t, held, "s-", label="held-out poses of the same caregiver")
    ax.axhline(90, color="0.5", ls=":", label="chance (random direction)")
    ax.set_xlabel("learning time (x 10^4 steps)")
    ax.set_ylabel("median angle error (deg)")
    ax.set_ylim(0, 100)
    ax.legend(fontsize=8)
    ax.set_title("Learning module's output against the direction to the target", fontsize=9)
    save_figure(fig, path, dpi=130)


def _annotate(frame, d_th_px: float, step: int, scale: int = 2) -> np.ndarray:
    img = cv2.resize(frame.image, None, fx=scale, fy=scale, interpolation=cv2.INTER_NEAREST)
    h, w = img.shape[:2]
    centre = (w // 2, h // 2)
    cv2.circle(img, centre, int(d_th_px * scale), (255, 255, 255), 2)  # the gazing circle
    for c in frame.detections_px:
        cv2.drawMarker(img, tuple(int(v * scale) for v in c), (255, 0, 255),
                       cv2.MARKER_CROSS, 18, 2)
    tx, ty = (int(v * scale) for v in frame.target_px)
    cv2.circle(img, (tx, ty), 24, (255, 220, 0), 3)  # the caregiver's target
    text = f"step {step}" + (f": {frame.module}" if frame.module else ": fired")
    cv2.putText(img, text, (10, 30), cv2.FONT_HERSHEY_SIMPLEX, 0.9, (0, 0, 0), 4)
    cv2.putText(img, text, (10, 30), cv2.FONT_HERSHEY_SIMPLEX, 0.9, (255, 255, 255), 2)
    return img


def fig7(frames: list, d_th_px: float, png: Path, gif: Path) -> None:
    """The trial's frames (:class:`jointattention.jobs.learned.Frame`) as a strip and a GIF."""
    images = [_annotate(f, d_th_px, i) for i, f in enumerate(frames)]
    cols = min(len(images), 4)
    rows = -(-len(images) // cols)
    fig = new_figure(3.2 * cols, 2.5 * rows)
    axes = fig.subplots(rows, cols, squeeze=False)
    for ax in axes.ravel():
        ax.axis("off")
    for ax, img in zip(axes.ravel(), images, strict=False):
        ax.imshow(img)
    fig.suptitle("One trial after learning: white circle, the gazing area (d_th); magenta, "
                 "detected objects; yellow, the caregiver's target", fontsize=9)
    save_figure(fig, png, dpi=130)
    pics = [Image.fromarray(img) for img in images]
    with atomic_path(gif) as tmp:
        pics[0].save(tmp, format="GIF", save_all=True, append_images=pics[1:],
                     duration=[600] * (len(pics) - 1) + [1500], loop=0)
