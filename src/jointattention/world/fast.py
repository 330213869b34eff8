"""The fast way to see: a trial's objects projected through the head's camera, no rendering.

Used by the experiments; the rendered mode renders the same objects and detects them in the
image. The detector's rule here: an object is seen when its centre lies in the image; its
bright-colour area is its image area times the part of it inside the image.
"""

from __future__ import annotations

import numpy as np

from ..agent.detections import Detections, equal_area_radius
from ..config import WorldConfig
from .kinematics import HeadKinematics
from .scene import place_objects, shuffle_target

__all__ = ["FastScene"]


def _inside_fraction(h: np.ndarray) -> np.ndarray:
    """Fraction of a disc inside a straight border at signed distance h (in radii)."""
    h = np.clip(h, -1.0, 1.0)
    return 1.0 - (np.arccos(h) - h * np.sqrt(1 - h**2)) / np.pi


class FastScene:
    """One trial's objects as the fast detector sees them (a :class:`~.protocol.Scene`).

    Args:
        kinematics: the head and camera.
        object_pos_m: (n, 3) object centres.
        object_radius_m: (n,) object radii.
        target_index: the caregiver's target among them.
        edge: (n,) each object's texture complexity (the paper's f_edge).

    :meth:`sample` draws one for an experiment's trial.
    """

    def __init__(self, kinematics: HeadKinematics, object_pos_m, object_radius_m,
                 target_index: int, edge):
        self.kinematics = kinematics
        self.object_pos_m = np.asarray(object_pos_m, dtype=float)
        self.object_radius_m = np.asarray(object_radius_m, dtype=float)
        self.target_index = int(target_index)
        self.edge = np.asarray(edge, dtype=float)
        self.visible_ids = np.arange(0)

    @classmethod
    def sample(cls, world: WorldConfig, kinematics: HeadKinematics, target_m, face_m,
               n_objects: int, rng: np.random.Generator) -> FastScene:
        """The caregiver's target at ``target_m`` plus random distractors.

        The distractors are kept clear of the face at ``face_m``; ``rng`` draws them, the target's
        size, the objects' order and every object's texture.
        """
        target_radius = rng.uniform(*world.objects.radius_range_m)
        pos, rad = place_objects(world, face_m, rng, n_objects, [target_m], [target_radius])
        pos, rad, target = shuffle_target(pos, rad, rng)  # the target's place is random
        return cls(kinematics, pos, rad, target, rng.uniform(0, 1, n_objects))

    def observe(self, theta_rad) -> Detections:
        """What the robot's detector reports at head angle ``theta_rad``.

        The object ids of the detections are left in ``visible_ids``.
        """
        kin = self.kinematics
        uv, depth, area = kin.project_spheres(self.object_pos_m, self.object_radius_m, theta_rad)
        w, h = kin.width_px, kin.height_px
        ids = np.flatnonzero(kin.in_image(uv, depth))
        c, a = uv[ids], area[ids]
        r = equal_area_radius(a)
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
