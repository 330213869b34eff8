"""Recording caregiver data sets from the simulated world (the paper's protocol)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .. import __version__
from ..agent.faces import face_window
from ..config import Config, WorldConfig, to_toml
from ..datasets import CaregiverDatasets
from .simulator import World

__all__ = ["capture_face_window", "face_box", "make_datasets"]


def face_box(world: World) -> tuple[np.ndarray, float]:
    """Where the face window is cut in the robot's current view.

    The image position of the caregiver's head centre, and the crop's height (``face_window.margin``
    times the head's apparent height).
    """
    kin, state = world.kinematics, world.state
    theta = world.head_angle_rad
    centre = kin.project(state.head_pos_m, theta)[0][0]
    radius = kin.apparent_radius_px(state.head_pos_m, [state.face_radius_m], theta)[0]
    return centre, world.config.face_window.margin * 2 * radius


def capture_face_window(world: World, image: np.ndarray | None = None) -> np.ndarray:
    """The face window of the robot's current view (``image``, else a new render)."""
    fw = world.config.face_window
    image = world.render() if image is None else image
    return face_window(image, *face_box(world), (fw.width_px, fw.height_px))


def make_datasets(
    config: WorldConfig, n: int, seed: int, progress: Callable[[int], None] | None = None
) -> CaregiverDatasets:
    """``n`` data sets, each from a new scene.

    In each, the robot looks at the caregiver's face, records the face window and its head angle,
    and the command that would centre the target.
    """
    if n < 1:
        raise ValueError(f"n = {n}: expected at least one data set")
    fw = config.face_window
    faces = np.empty((n, fw.height_px, fw.width_px), np.uint8)
    theta_face = np.empty((n, 2))
    command = np.empty((n, 2))
    target = np.empty((n, 3))
    with World(config, seed=seed) as world:
        for i in range(n):
            state = world.reset()
            theta_face[i] = world.face_angle_rad
            world.set_head_angle(theta_face[i])
            faces[i] = capture_face_window(world)
            command[i] = world.kinematics.centring_angles(state.target_pos_m) - theta_face[i]
            target[i] = state.target_pos_m
            if progress is not None:
                progress(i + 1)
    meta = {
        "generator": f"jointattention {__version__}",
        "seed": seed,
        "world_config_toml": to_toml(Config(world=config)),
    }
    return CaregiverDatasets(faces, theta_face, command, target, meta)

