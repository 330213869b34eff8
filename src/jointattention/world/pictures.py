"""Pictures of the live world: the robot's view and a contact sheet of face windows."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from .recording import capture_face_window
from .scene import _direction, with_target
from .simulator import World

__all__ = ["face_sheet", "robot_view"]


def _annotate(world: World, image: np.ndarray, d_th_px: float, face_box: bool) -> np.ndarray:
    """Outline objects (the target thicker), the face window and the gazing circle."""
    out = image.copy()
    kin, state = world.kinematics, world.state
    p = world.project()
    for i in np.flatnonzero(p.in_view):
        c = tuple(int(round(x)) for x in p.centre_px[i])
        thick = 2 if i == state.target_index else 1
        cv2.circle(out, c, int(round(p.radius_px[i])) + 3, (255, 255, 255), thick, cv2.LINE_AA)
        if i == state.target_index:
            cv2.putText(
                out,
                "target",
                (c[0] + 8, c[1] - 8),
                cv2.FONT_HERSHEY_SIMPLEX,
                0.4,
                (255, 255, 255),
                1,
                cv2.LINE_AA,
            )
    centre = tuple(int(round(x)) for x in kin.centre_px)
    cv2.circle(out, centre, int(round(d_th_px)), (40, 220, 255), 1, cv2.LINE_AA)
    cv2.drawMarker(out, centre, (40, 220, 255), cv2.MARKER_CROSS, 8, 1)
    if face_box:
        fw = world.config.face_window
        theta = world.head_angle_rad
        c = kin.project(state.head_pos_m, theta)[0][0]
        r = kin.apparent_radius_px(state.head_pos_m, [state.face_radius_m], theta)[0]
        h = fw.margin * 2 * r
        w = h * fw.width_px / fw.height_px
        cv2.rectangle(
            out,
            (int(c[0] - w / 2), int(c[1] - h / 2)),
            (int(c[0] + w / 2), int(c[1] + h / 2)),
            (255, 230, 0),
            1,
        )
    return out


def robot_view(world: World, path: str | Path) -> Path:
    """Three panels: the room from behind the robot, the robot looking at the caregiver (face
    window boxed), and the robot after turning to the caregiver's target."""
    import matplotlib.pyplot as plt

    d_th = world.kinematics.width_px / 6  # the paper's default threshold (Eq. 3)
    overview = world.render("overview")
    world.set_head_angle(world.face_angle_rad)
    at_face = _annotate(world, world.render(), d_th, face_box=True)
    window = capture_face_window(world)
    world.set_head_angle(world.kinematics.centring_angles(world.state.target_pos_m))
    at_target = _annotate(world, world.render(), d_th, face_box=False)
    fig, axes = plt.subplots(1, 4, figsize=(15, 3.8), gridspec_kw={"width_ratios": [4, 4, 4, 1.6]})
    titles = [
        "room (experimenter's camera)",
        "robot looks at the caregiver",
        "robot looks at the caregiver's target",
        "face window",
    ]
    for ax, img, title in zip(axes, [overview, at_face, at_target, window], titles, strict=True):
        ax.imshow(img, cmap="gray", vmin=0, vmax=255)
        ax.set_title(title, fontsize=9)
        ax.set_xticks([])
        ax.set_yticks([])
    fig.tight_layout()
    return _save(fig, path)


def face_sheet(
    world: World,
    path: str | Path,
    pans_deg=(-40, -20, 0, 20, 40),
    tilts_deg=(18, -12, -24, -36),
    distance_m: float = 0.6,
) -> Path:
    """Face windows with the caregiver looking at targets on a grid of directions."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(
        len(tilts_deg), len(pans_deg), figsize=(1.5 * len(pans_deg), 1.45 * len(tilts_deg))
    )
    base = world.state
    for r, tilt in enumerate(tilts_deg):
        for c, pan in enumerate(pans_deg):
            target = distance_m * _direction(np.deg2rad(pan), np.deg2rad(tilt))
            world.set_scene(with_target(base, world.config, target))
            world.set_head_angle(world.face_angle_rad)
            ax = axes[r, c]
            ax.imshow(capture_face_window(world), cmap="gray", vmin=0, vmax=255)
            ax.set_xticks([])
            ax.set_yticks([])
            ax.set_title(f"pan {pan:+d}°, tilt {tilt:+d}°", fontsize=7)
    world.set_scene(base)
    fig.suptitle(
        "face windows; the caregiver looks at a target in the direction shown "
        "(as seen by the robot)",
        fontsize=8,
    )
    fig.tight_layout()
    return _save(fig, path)


def _save(fig, path: str | Path) -> Path:
    import matplotlib.pyplot as plt

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
