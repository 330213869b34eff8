"""Recording caregiver data sets from the simulated world (the paper's protocol)."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np

from .. import __version__
from ..agent.faces import face_template, face_window, finder_for, window_of
from ..config import Config, DetectorConfig, WorldConfig, to_toml
from ..datasets import CaregiverDatasets
from .simulator import World

__all__ = ["CUTS", "capture_face_window", "face_box", "make_datasets", "split_evenly"]

CUTS = ("box", "finder")  # where make_datasets cuts the face windows


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


def _cut_by_finder(images: list[np.ndarray], faces: np.ndarray, size_px) -> np.ndarray:
    """Re-cut ``faces`` in place around the faces the robot finds; which ones were found."""
    template = face_template(faces)
    finder = finder_for("template", template, DetectorConfig().face_min_score)
    found = np.zeros(len(faces), bool)
    for i, image in enumerate(images):
        match = finder.find(image)
        if match:
            faces[i], found[i] = window_of(image, match[0], size_px), True
    if not found.any():
        raise ValueError("cut = 'finder': the face finder found no face in any recording; "
                         "expected the caregiver's face in them")
    return found


def split_evenly(n: int, k: int) -> np.ndarray:
    """The part (0 to k - 1) of each of ``n`` items cut into ``k`` contiguous parts.

    The sizes differ by at most one: the first ``n % k`` parts hold one more.
    """
    sizes = np.full(k, n // k)
    sizes[: n % k] += 1
    return np.repeat(np.arange(k), sizes)


def make_datasets(
    config: WorldConfig, n: int, seed: int, progress: Callable[[int], None] | None = None,
    caregivers: int = 1, cut: str = "box",
) -> CaregiverDatasets:
    """``n`` data sets, each from a new scene, posed by ``caregivers`` people.

    In each, the robot looks at the caregiver's face, records the face window and its head angle,
    and the command that would centre the target. The data sets are split as evenly as possible
    across the caregivers, in turn (:func:`split_evenly`): caregiver 0 is the world's own
    identity (drawn from ``seed``), each next one a new identity drawn by the world
    (``World.reset(new_identity=True)``). With several caregivers the data sets name them
    (the ``caregiver`` field) and ``meta["caregivers"]`` holds each one's head size and
    colours; with one they are exactly the data sets recorded before caregivers existed.

    ``cut``: where each face window is cut. ``"box"``: around the head's projection (what only
    the experimenter knows). ``"finder"``: around the face the robot's own face finder
    finds, with the mean of the recording's box windows as its template, as a robot's
    recordings are made (``datasets import``) and as ``follow`` and the closed loop cut their
    windows; data sets whose face it does not find are left out (``meta["without_face"]``).
    """
    if cut not in CUTS:
        raise ValueError(f"cut {cut!r}: expected one of {', '.join(CUTS)}")
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
    identities, images = [], []
    with World(config, seed=seed) as world:
        for i in range(n):
            new_identity = i > 0 and who[i] != who[i - 1]
            state = world.reset(new_identity=new_identity)
            if i == 0 or new_identity:
                identities.append(dataclasses.asdict(world.caregiver))
            theta_face[i] = world.face_angle_rad
            world.set_head_angle(theta_face[i])
            image = world.render()
            faces[i] = capture_face_window(world, image)
            if cut == "finder":
                images.append(image)
            command[i] = world.kinematics.centring_angles(state.target_pos_m) - theta_face[i]
            target[i] = state.target_pos_m
            if progress is not None:
                progress(i + 1)
    meta = {
        "generator": f"jointattention {__version__}",
        "seed": seed,
        "world_config_toml": to_toml(Config(world=config)),
    }
    if cut == "finder":
        keep = _cut_by_finder(images, faces, (fw.width_px, fw.height_px))
        faces, theta_face, command, target, who = (
            a[keep] for a in (faces, theta_face, command, target, who))
        meta.update(cut="finder", without_face=np.flatnonzero(~keep).tolist())
    if caregivers == 1:
        return CaregiverDatasets(faces, theta_face, command, target, meta)
    meta["caregivers"] = identities
    return CaregiverDatasets(faces, theta_face, command, target, meta, caregiver=who)
