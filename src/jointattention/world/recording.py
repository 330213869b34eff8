"""Recording caregiver data sets from the simulated world (the paper's protocol)."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np

from .. import __version__
from ..agent.faces import face_window
from ..config import Config, WorldConfig, to_toml
from ..datasets import CaregiverDatasets
from .simulator import World

__all__ = ["capture_face_window", "face_box", "make_datasets", "split_evenly"]


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


def split_evenly(n: int, k: int) -> np.ndarray:
    """The part (0 to k - 1) of each of ``n`` items cut into ``k`` contiguous parts.

    The sizes differ by at most one: the first ``n % k`` parts hold one more.
    """
    sizes = np.full(k, n // k)
    sizes[: n % k] += 1
    return np.repeat(np.arange(k), sizes)


def make_datasets(
    config: WorldConfig, n: int, seed: int, progress: Callable[[int], None] | None = None,
    caregivers: int = 1,
) -> CaregiverDatasets:
    """``n`` data sets, each from a new scene, posed by ``caregivers`` people.

    In each, the robot looks at the caregiver's face, records the face window and its head angle,
    and the command that would centre the target. The data sets are split as evenly as possible
    across the caregivers, in turn (:func:`split_evenly`): caregiver 0 is the world's own
    identity (drawn from ``seed``), each next one a new identity drawn by the world
    (``World.reset(new_identity=True)``). With several caregivers the data sets name them
    (the ``caregiver`` field) and ``meta["caregivers"]`` holds each one's head size and
    colours; with one they are exactly the data sets recorded before caregivers existed.
    """
    if n < 1:
        raise ValueError(f"n = {n}: expected at least one data set")
    if not 1 <= caregivers <= n:
        raise ValueError(f"caregivers = {caregivers}: expected 1 to n = {n} (each caregiver "
                         "poses at least one data set)")
    fw = config.face_window
    faces = np.empty((n, fw.height_px, fw.width_px), np.uint8)
    theta_face = np.empty((n, 2))
    command = np.empty((n, 2))
    target = np.empty((n, 3))
    who = split_evenly(n, caregivers)
    identities = []
    with World(config, seed=seed) as world:
        for i in range(n):
            new_identity = i > 0 and who[i] != who[i - 1]
            state = world.reset(new_identity=new_identity)
            if i == 0 or new_identity:
                identities.append(dataclasses.asdict(world.caregiver))
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
    if caregivers == 1:
        return CaregiverDatasets(faces, theta_face, command, target, meta)
    meta["caregivers"] = identities
    return CaregiverDatasets(faces, theta_face, command, target, meta, caregiver=who)
