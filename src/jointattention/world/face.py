"""The caregiver's head as her identity shapes it: each part's size, place and colour.

:mod:`.mjcf` builds the default head once; :func:`head_parts` gives, for one identity, the
factors that multiply each part's base size and position and the offset added to the position,
so that the simulator reshapes one compiled model per scene. A default identity (factors 1,
offsets 0) gives factors of exactly ``head_scale`` and offsets of exactly 0: the head of before.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .identity import Caregiver
from .mjcf import CAREGIVER_PARTS, EYE_POS_M, EYE_RADIUS_M, HEAD_RADII_M, PUPIL_RADIUS_M

__all__ = ["BODIES", "Part", "head_colours", "head_parts"]

BODIES = ("cg_eye_l", "cg_eye_r")  # the eyes are bodies (they turn); the rest are geoms

_HAIR_DEPTH_M = CAREGIVER_PARTS["hair"][1][1]
_BROW_POS_M = CAREGIVER_PARTS["brow_r"][2]
# How far the iris's front lies before the eye's centre (mjcf: the pupil sphere's place).
_IRIS_FRONT_M = EYE_RADIUS_M + PUPIL_RADIUS_M * 0.55


class Part(NamedTuple):
    """How one geom or body of the head changes: position = base * pos + offset_m."""

    size: np.ndarray  # (3,) factors on the base size
    pos: np.ndarray  # (3,) factors on the base position
    offset_m: np.ndarray  # (3,) added to the position


def _depth(cg: Caregiver, pos_m, spacing: float, lift_m: float) -> float:
    """How deep in y the skin's surface lies at a feature moved by ``spacing`` and ``lift_m``.

    The ratios to the head's half axes are formed so that an unmoved feature (spacing 1, lift
    0) gives the same bits as the default head, whatever the head's shape.
    """
    u = pos_m[0] * spacing / HEAD_RADII_M[0]
    v = (pos_m[2] * cg.head_height + lift_m) / (HEAD_RADII_M[2] * cg.head_height)
    return HEAD_RADII_M[1] * cg.head_scale * cg.head_depth * np.sqrt(max(1 - u * u - v * v, 0.0))


def head_parts(cg: Caregiver) -> dict[str, Part]:
    """Geom or body name -> :class:`Part`, for every part of the head that an identity changes.

    The head ellipsoid scales by width, depth and height (and ``head_scale``), and every part
    fixed to it moves with it; the eyes and brows move apart and up by ``eye_spacing`` and
    ``eye_height_m`` and follow the skin's surface in depth (so they stay on the face); bigger
    eyes move back so that they stand as far out of the skin; the hair grows by ``hair_volume``
    with its front edge kept, and moves up by ``hairline_m``.
    """
    s = cg.head_scale
    shape = s * np.array([cg.head_width, cg.head_depth, cg.head_height])
    zero = np.zeros(3)
    lift = cg.eye_height_m * s
    spread = shape * [cg.eye_spacing, 1.0, 1.0]
    parts = {
        "cg_skin": Part(shape, shape, zero),
        "cg_hair": Part(shape * cg.hair_volume, shape,
                        np.array([0.0, (cg.hair_volume - 1) * _HAIR_DEPTH_M * shape[1],
                                  cg.hairline_m * s])),
        "cg_nose": Part(shape * cg.nose_size, shape, zero),
        "cg_mouth": Part(shape * [cg.mouth_width, 1.0, 1.0], shape, zero),
    }
    # Moved features follow the surface: the change of its depth from where it was.
    brow_dy = _depth(cg, _BROW_POS_M, 1.0, 0.0) - _depth(cg, _BROW_POS_M, cg.eye_spacing,
                                                         cg.eye_height_m)
    for side in "lr":
        parts[f"cg_brow_{side}"] = Part(shape * [1.0, 1.0, cg.brow_thickness], spread,
                                        np.array([0.0, brow_dy, lift]))
    eye = EYE_POS_M["r"]
    eye_dy = (_depth(cg, eye, 1.0, 0.0) - _depth(cg, eye, cg.eye_spacing, cg.eye_height_m)
              + s * (_IRIS_FRONT_M * cg.eye_size - _IRIS_FRONT_M))
    ball = np.full(3, s * cg.eye_size)
    for side in "lr":
        parts[f"cg_eye_{side}"] = Part(zero, spread, np.array([0.0, eye_dy, lift]))
        parts[f"cg_eyeball_{side}"] = Part(ball, ball, zero)
        parts[f"cg_pupil_{side}"] = Part(ball, ball, zero)
    return parts


def head_colours(cg: Caregiver) -> dict[str, tuple[float, ...]]:
    """Geom name -> RGB of the caregiver's skin, features, hair, eyes and shirt."""
    skin = np.array(cg.skin_rgb)
    return {
        "cg_skin": cg.skin_rgb,
        "cg_nose": tuple(skin * 0.9),
        "cg_mouth": tuple(skin * [0.6, 0.3, 0.3]),
        "cg_hair": cg.hair_rgb,
        "cg_brow_l": cg.hair_rgb,
        "cg_brow_r": cg.hair_rgb,
        "cg_pupil_l": cg.iris_rgb,
        "cg_pupil_r": cg.iris_rgb,
        "cg_torso": cg.shirt_rgb,
        "cg_neck": cg.skin_rgb,
    }
