"""The seam between the world and the trial loop: what a scene must offer.

A scene is one trial's objects, seen from any head angle. Two implement it: the fast
projection (:class:`~jointattention.world.fast.FastScene`) and MuJoCo renders given to the
OpenCV detector (:class:`~jointattention.world.rendered.RenderedScene`). The agent receives
only the :class:`~jointattention.agent.detections.Detections`; the object ids, their places and
the target are the experimenter's. A real recording that knows where the objects were can offer
the same: a trial is then scored the same way, whatever made its images.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np

from ..agent.detections import Detections

__all__ = ["Scene"]


@runtime_checkable
class Scene(Protocol):
    """The contract of a trial's scene.

    Attributes:
        target_index: the object the caregiver looks at.
        object_pos_m: (n, 3) the objects' centres in the robot's frame (x right, y forward,
            z up, from the pan/tilt axes): how far the object the robot ended at lies from the
            target (``Outcome.caregiver_error_rad``).
        visible_ids: after :meth:`observe`, the object id of each detection (-1 for a
            detection that is no object).
    """

    target_index: int
    object_pos_m: np.ndarray
    visible_ids: np.ndarray

    def observe(self, theta_rad: np.ndarray) -> Detections:
        """What the robot's detector reports at head angle ``theta_rad``."""
