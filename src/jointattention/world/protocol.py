"""The seam between the world and the trial loop: what a scene must offer.

A scene is one trial's objects, seen from any head angle. Two implement it: the fast
projection (:class:`~jointattention.world.fast.FastScene`) and MuJoCo renders given to the
OpenCV detector (:class:`~jointattention.world.rendered.RenderedScene`). The agent receives
only the :class:`~jointattention.agent.detections.Detections`; the object ids and the target
are the experimenter's.
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
        visible_ids: after :meth:`observe`, the object id of each detection (-1 for a
            detection that is no object).
    """

    target_index: int
    visible_ids: np.ndarray

    def observe(self, theta_rad: np.ndarray) -> Detections:
        """What the robot's detector reports at head angle ``theta_rad``."""
