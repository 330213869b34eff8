"""Views of caregivers' faces with the truth about them: where each head is in the image.

To measure face finders: each view is a new scene (light, room, sensor) and, in turn, a new
caregiver, seen from a head angle off the face by up to ``jitter_deg``, so the face lands
anywhere in the middle of the image, at the world's range of distances and gaze directions.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import NamedTuple

import numpy as np

from .. import rng as rngs
from .options import WorldConfig
from .recording import head_box, split_evenly
from .simulator import World

__all__ = ["FaceView", "face_views"]


class FaceView(NamedTuple):
    """One rendered view and its truth.

    Attributes:
        image: RGB uint8 (H, W, 3), the robot's camera image (sensor effects included).
        centre_px: (2,) the projection of the head's centre: where the data sets' windows are
            cut (:func:`~jointattention.world.recording.head_box`).
        height_px: the head's apparent height (twice its apparent radius).
        caregiver: which of the views' caregivers (0 to ``caregivers`` - 1).
    """

    image: np.ndarray
    centre_px: np.ndarray
    height_px: float
    caregiver: int


def face_views(config: WorldConfig, n: int, caregivers: int, seed: int, *,
               stream: str = "faces", jitter_deg: tuple[float, float] = (12.0, 8.0)
               ) -> Iterator[FaceView]:
    """``n`` views of ``caregivers`` caregivers (split evenly, in turn) from ``stream``."""
    if not 1 <= caregivers <= n:
        raise ValueError(f"caregivers = {caregivers}: expected 1 to n = {n}")
    who = split_evenly(n, caregivers)
    aim = rngs.stream(seed, stream, 1)  # the head's offsets: apart from the world's draws
    jitter = np.deg2rad(np.asarray(jitter_deg, float))
    with World(config, seed=seed, stream=stream) as world:
        for i in range(n):
            world.reset(new_identity=i > 0 and who[i] != who[i - 1])
            world.set_head_angle(world.kinematics.clip(
                world.face_angle_rad + aim.uniform(-1, 1, 2) * jitter))
            yield FaceView(world.render(), *head_box(world), int(who[i]))
