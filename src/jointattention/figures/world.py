"""Pictures of the live world: the robot's view and contact sheets of face windows."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from ..agent.detections import equal_area_radius
from ..world.kinematics import direction
from ..world.recording import capture_face_window, face_box
from ..world.scene import with_target
from ..world.simulator import World
from ._save import new_figure, save_figure

__all__ = ["caregiver_sheet", "face_sheet", "robot_view"]

WHITE, CYAN, YELLOW = (255, 255, 255), (40, 220, 255), (255, 230, 0)


def _annotate(world: World, image: np.ndarray, d_th_px: float, show_face: bool) -> np.ndarray:
    """Outline the objects in view (the target thicker), the face window and Eq. 3's circle."""
    out = image.copy()
    kin, state = world.kinematics, world.state
    scene = world.fast_scene()
    det = scene.observe(world.head_angle_rad)
    for j, i in enumerate(scene.visible_ids):
        c = tuple(int(round(x)) for x in det.centre_px[j])
        radius = int(round(float(equal_area_radius(det.colour_area_px[j])))) + 3
        is_target = i == state.target_index
        cv2.circle(out, c, radius, WHITE, 2 if is_target else 1, cv2.LINE_AA)
        if is_target:
            cv2.putText(out, "target", (c[0] + 8, c[1] - 8), cv2.FONT_HERSHEY_SIMPLEX, 0.4,
                        WHITE, 1, cv2.LINE_AA)
    centre = tuple(int(round(x)) for x in kin.centre_px)
    cv2.circle(out, centre, int(round(d_th_px)), CYAN, 1, cv2.LINE_AA)
    cv2.drawMarker(out, centre, CYAN, cv2.MARKER_CROSS, 8, 1)
    if show_face:
        fw = world.config.face_window
        c, h = face_box(world)
        w = h * fw.width_px / fw.height_px
        cv2.rectangle(out, (int(c[0] - w / 2), int(c[1] - h / 2)),
                      (int(c[0] + w / 2), int(c[1] + h / 2)), YELLOW, 1)
    return out


def robot_view(world: World, path: str | Path, d_th_px: float) -> Path:
    """Three panels: the room, the robot looking at the caregiver, then at its target.

    The room from behind the robot, the robot looking at the caregiver (face window boxed), and the
    robot after turning to the caregiver's target; with the internal evaluator's circle of radius
    ``d_th_px``.
    """
    overview = world.render("overview")
    world.set_head_angle(world.face_angle_rad)
    at_face = _annotate(world, world.render(), d_th_px, show_face=True)
    window = capture_face_window(world)
    world.set_head_angle(world.kinematics.centring_angles(world.state.target_pos_m))
    at_target = _annotate(world, world.render(), d_th_px, show_face=False)
    fig = new_figure(15, 3.8)
    axes = fig.subplots(1, 4, gridspec_kw={"width_ratios": [4, 4, 4, 1.6]})
    titles = ["room (experimenter's camera)", "robot looks at the caregiver",
              "robot looks at the caregiver's target", "face window"]
    for ax, img, title in zip(axes, [overview, at_face, at_target, window], titles, strict=True):
        ax.imshow(img, cmap="gray", vmin=0, vmax=255)
        ax.set_title(title, fontsize=9)
        ax.set_xticks([])
        ax.set_yticks([])
    return save_figure(fig, path)


def face_sheet(world: World, path: str | Path, pans_deg=(-40, -20, 0, 20, 40),
               tilts_deg=(18, -12, -24, -36), distance_m: float = 0.6) -> Path:
    """Face windows with the caregiver looking at targets on a grid of directions."""
    fig = new_figure(1.5 * len(pans_deg), 1.45 * len(tilts_deg))
    axes = fig.subplots(len(tilts_deg), len(pans_deg))
    base = world.state
    for r, tilt in enumerate(tilts_deg):
        for c, pan in enumerate(pans_deg):
            target = distance_m * direction(np.deg2rad(pan), np.deg2rad(tilt))
            world.set_scene(with_target(base, world.config, target))
            world.set_head_angle(world.face_angle_rad)
            ax = axes[r, c]
            ax.imshow(capture_face_window(world), cmap="gray", vmin=0, vmax=255)
            ax.set_xticks([])
            ax.set_yticks([])
            ax.set_title(f"pan {pan:+d}°, tilt {tilt:+d}°", fontsize=7)
    world.set_scene(base)
    fig.suptitle("face windows; the caregiver looks at a target in the direction shown "
                 "(as seen by the robot)", fontsize=8)
    return save_figure(fig, path)


def caregiver_sheet(world: World, path: str | Path, n: int = 64, columns: int = 8,
                    zoom: int = 3) -> Path:
    """The faces of ``n`` identities of ``world``, one new scene each (its own identity first).

    Each tile is the robot's view of the face box in colour (``zoom`` times the face window's
    size) beside the grayscale face window that a recording keeps (shown ``zoom`` times
    larger): light, room and camera effects as the scene drew them.
    """
    fw = world.config.face_window
    size = (fw.width_px * zoom, fw.height_px * zoom)
    rows = -(-n // columns)
    sheet = np.full((rows * (size[1] + 4), columns * (2 * size[0] + 8), 3), 255, np.uint8)
    for k in range(n):
        if k:
            world.reset(new_identity=True)
        world.set_head_angle(world.face_angle_rad)
        image = world.render()
        centre, height = face_box(world)
        crop = (int(round(height * fw.width_px / fw.height_px)), int(round(height)))
        colour = cv2.resize(cv2.getRectSubPix(image, crop, tuple(float(x) for x in centre)),
                            size, interpolation=cv2.INTER_AREA)
        gray = cv2.resize(capture_face_window(world, image), size,
                          interpolation=cv2.INTER_NEAREST)
        r, c = divmod(k, columns)
        y, x = r * (size[1] + 4), c * (2 * size[0] + 8)
        sheet[y:y + size[1], x:x + size[0]] = colour
        sheet[y:y + size[1], x + size[0]:x + 2 * size[0]] = gray[..., None]
    fig = new_figure(sheet.shape[1] / 100, sheet.shape[0] / 100 + 0.3)
    ax = fig.subplots()
    ax.imshow(sheet, interpolation="nearest")
    ax.set_axis_off()
    ax.set_title(f"{n} caregivers: the robot's view of each face (colour) and the face window "
                 "it keeps (grey)", fontsize=9)
    return save_figure(fig, path, dpi=100)
