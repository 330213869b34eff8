"""How new an unseen caregiver is: her distance to the nearest known one, in units of spacing.

An identity is a point in the world's parameter space: every quantity in which one caregiver
differs from another (:data:`COORDINATES`: head size and shape, the face's proportions, skin,
hair and iris colours, her distance and stature, her head's share of a gaze turn and her pose
noise), each as she has it (the world's mean plus her own offset), so that identities of two
worlds compare. Each coordinate is divided by its standard deviation over the known and the
unseen identities together (a coordinate constant in both is left out). An unseen identity's
*novelty* is her Euclidean distance to the nearest known identity, over the spacing of the
known ones (the median distance from a known identity to the nearest other): 1 is as far as
two neighbours among the known are apart.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .identity import Caregiver, head_turn_fraction, pose_noise_deg
from .options import WorldConfig

__all__ = ["COORDINATES", "coordinates", "novelty"]

COORDINATES = (
    "head_scale", "head_width", "head_depth", "head_height", "hair_volume", "hairline_m",
    "eye_spacing", "eye_height_m", "eye_size", "nose_size", "mouth_width", "brow_thickness",
    "skin_r", "skin_g", "skin_b", "hair_r", "hair_g", "hair_b", "iris_r", "iris_g", "iris_b",
    "distance_m", "height_m", "head_turn_fraction", "pose_noise_deg",
)


def coordinates(caregivers: Sequence[Caregiver], world: WorldConfig) -> np.ndarray:
    """The identities as points (n, len(:data:`COORDINATES`)), as each has them in ``world``."""
    cg = world.caregiver
    return np.array([[
        c.head_scale, c.head_width, c.head_depth, c.head_height, c.hair_volume, c.hairline_m,
        c.eye_spacing, c.eye_height_m, c.eye_size, c.nose_size, c.mouth_width,
        c.brow_thickness, *c.skin_rgb, *c.hair_rgb, *c.iris_rgb,
        cg.distance_m + c.distance_offset_m, cg.height_m + c.height_offset_m,
        head_turn_fraction(world, c), pose_noise_deg(world, c),
    ] for c in caregivers], float).reshape(len(caregivers), len(COORDINATES))


def _nearest(a: np.ndarray, b: np.ndarray, exclude_self: bool = False) -> np.ndarray:
    """Each row of ``a``'s distance to the nearest row of ``b`` (itself excluded if asked)."""
    d = np.sqrt(((a[:, None, :] - b[None, :, :]) ** 2).sum(-1))
    if exclude_self:
        np.fill_diagonal(d, np.inf)
    return d.min(1)


def novelty(unseen: Sequence[Caregiver], unseen_world: WorldConfig,
            known: Sequence[Caregiver], known_world: WorldConfig) -> np.ndarray:
    """Each unseen identity's distance to the nearest known one, over the known's spacing.

    (n_unseen,); NaN for each if fewer than two known identities (no spacing) or if the
    known ones all coincide.
    """
    u, k = coordinates(unseen, unseen_world), coordinates(known, known_world)
    if len(k) < 2:
        return np.full(len(u), np.nan)
    both = np.vstack([u, k])
    sd = both.std(0)
    keep = sd > 1e-12 * np.maximum(np.abs(both).max(0), 1.0)
    u, k = u[:, keep] / sd[keep], k[:, keep] / sd[keep]
    spacing = float(np.median(_nearest(k, k, exclude_self=True)))
    if not spacing > 0:
        return np.full(len(u), np.nan)
    return _nearest(u, k) / spacing
