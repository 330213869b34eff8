"""The fast way to see: a trial's objects projected through the head's camera, no rendering.

Used by the experiments; the rendered mode renders the same objects and detects them in the
image. The detector's rule here: an object is seen when its centre lies in the image; its
bright-colour area is its image area times the part of it inside the image.
"""

from __future__ import annotations

import numpy as np

from ..agent.detections import Detections
from ..config import WorldConfig
from .kinematics import HeadKinematics
from .scene import place_objects

__all__ = ["FastScene"]


def _inside_fraction(h: np.ndarray) -> np.ndarray:
    """Fraction of a disc inside a straight border at signed distance h (in radii)."""
    h = np.clip(h, -1.0, 1.0)
    return 1.0 - (np.arccos(h) - h * np.sqrt(1 - h**2)) / np.pi


class FastScene:
    """One trial's objects: the caregiver's target plus random distractors.

    Args:
        world: geometry of the room and of the object region.
        kinematics: the head and camera.
        target_m: where the caregiver's target is.
        face_m: where the caregiver's face is (distractors keep clear of it).
        n_objects: objects in all, the target among them.
        rng: draws the distractors, the target's size, and every object's texture.
    """

    def __init__(self, world: WorldConfig, kinematics: HeadKinematics, target_m, face_m,
                 n_objects: int, rng: np.random.Generator):
        self.kinematics = kinematics
        target_radius = rng.uniform(*world.objects.radius_range_m)
        pos, rad = place_objects(world, face_m, rng, n_objects, [target_m], [target_radius])
        order = rng.permutation(n_objects)  # the target's place in the list is random
        self.object_pos_m, self.object_radius_m = pos[order], rad[order]
        self.target_index = int(np.flatnonzero(order == 0)[0])
        self.edge = rng.uniform(0, 1, n_objects)
        self.visible_ids = np.arange(0)

    def observe(self, theta_rad) -> Detections:
        """What the robot's detector reports at head angle ``theta_rad``; the object ids of
        the detections are left in ``visible_ids``."""
        kin = self.kinematics
        uv, depth, area = kin.project_spheres(self.object_pos_m, self.object_radius_m, theta_rad)
        w, h = kin.width_px, kin.height_px
        ids = np.flatnonzero(kin.in_image(uv, depth))
        c, a = uv[ids], area[ids]
        r = np.sqrt(a / np.pi)
        # distance of each centre to the nearest image border, in radii
        border = np.minimum(np.minimum(c[:, 0] + 0.5, w - 0.5 - c[:, 0]),
                            np.minimum(c[:, 1] + 0.5, h - 0.5 - c[:, 1])) / r
        cut = border < 1.0
        if cut.any():
            frac = np.ones(len(ids))
            cc, rr = c[cut], r[cut]
            frac[cut] = (_inside_fraction((cc[:, 0] + 0.5) / rr)
                         * _inside_fraction((w - 0.5 - cc[:, 0]) / rr)
                         * _inside_fraction((cc[:, 1] + 0.5) / rr)
                         * _inside_fraction((h - 0.5 - cc[:, 1]) / rr))
            a = a * frac
        self.visible_ids = ids
        return Detections(c, a, self.edge[ids], np.zeros(len(ids)), (w, h))
