"""The rendered way to see: MuJoCo renders given to the robot's OpenCV detector.

A trial's objects are shown in MuJoCo, and each view is rendered and given to
:mod:`jointattention.agent.vision`.

A :class:`~jointattention.world.protocol.Scene` like
:class:`~jointattention.world.fast.FastScene`, so the trial loop and the agent cannot tell
which one feeds them; the parity of the two is measured by
:mod:`jointattention.jobs.parity`.
"""

from __future__ import annotations

import numpy as np

from ..agent.detections import Detections, equal_area_radius
from ..agent.options import DetectorConfig
from ..agent.vision import ImageDetector
from .fast import FastScene
from .options import WorldConfig
from .scene import scene_with
from .simulator import World

__all__ = ["RenderedScene", "RenderedScenes", "object_ids"]


class RenderedScene:
    """One trial's objects (those of ``fast``) in ``world``, seen through rendered images.

    Args:
        world: the MuJoCo world; its caregiver is shown with the head at ``face_m``, looking
            at the target. It must hold as many objects as ``fast``.
        fast: the trial's geometry (positions, radii, target).
        face_m: the centre of the caregiver's head.
        detector: the robot's image detector (reset here: a new trial is a new view).
        rng: draws the objects' colours and the light.

    ``visible_ids`` (the objects of the last detections) is the experimenter's knowledge:
    each detection is given the object whose projected disc holds its centre (-1 if none).
    """

    def __init__(self, world: World, fast: FastScene, face_m, detector: ImageDetector,
                 rng: np.random.Generator):
        self.world, self.detector = world, detector
        self.target_index = fast.target_index
        self.object_pos_m = fast.object_pos_m  # the caregiver's judge (trial.SceneTrial.outcome)
        world.set_scene(scene_with(world.config, world.caregiver, face_m, fast.object_pos_m,
                                   fast.object_radius_m, fast.target_index, rng))
        detector.reset()
        self.visible_ids = np.arange(0)
        self.last_image: np.ndarray | None = None

    def observe(self, theta_rad) -> Detections:
        """Turn the head to ``theta_rad``, render the robot's view and detect in it."""
        self.world.set_head_angle(theta_rad)
        self.last_image = self.world.render()
        det = self.detector.detect(self.last_image)
        s = self.world.state
        uv, _, area = self.world.kinematics.project_spheres(s.object_pos_m, s.object_radius_m,
                                                            theta_rad)
        self.visible_ids = object_ids(det.centre_px, uv, equal_area_radius(area))
        return det


class RenderedScenes:
    """The rendered mode of a run: each trial's scene shown in one MuJoCo world.

    Args:
        world: the world's configuration.
        detector: the OpenCV detector's thresholds.
        n_objects: objects per trial.
        seed: the world's seed (the caregiver's identity).
        rng: draws colours and light, a stream of its own so that rendered and fast cells
            of a seed share their trials.
    """

    def __init__(self, world: WorldConfig, detector: DetectorConfig, n_objects: int, *,
                 seed: int, rng: np.random.Generator):
        self.world = World(world, seed=seed, n_objects=n_objects)
        self.detector = ImageDetector(detector, self.world.kinematics.focal_px)
        self.rng = rng

    def show(self, fast: FastScene, face_m) -> RenderedScene:
        """The trial of ``fast`` (caregiver's head at ``face_m``), rendered."""
        return RenderedScene(self.world, fast, face_m, self.detector, self.rng)

    def close(self) -> None:
        """Free the world's renderer."""
        self.world.close()


def object_ids(centres_px: np.ndarray, uv: np.ndarray, radius_px: np.ndarray) -> np.ndarray:
    """The object each detection belongs to, else -1.

    The nearest projected centre whose disc (one pixel wider) holds it.
    """
    ids = np.full(len(centres_px), -1)
    for j, c in enumerate(centres_px):
        d = np.hypot(*(uv - c).T)
        d[~(d <= radius_px + 1)] = np.inf
        if np.isfinite(d).any():
            ids[j] = int(np.argmin(d))
    return ids
