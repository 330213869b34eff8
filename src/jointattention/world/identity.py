"""Who the caregiver is: her identity, and drawing one at random.

An identity fixes her face (head size and shape, skin, hair, eyes, nose, mouth, brows), her
shirt and where she sits; it is drawn once per caregiver. The ranges are the configuration's
``[world.caregiver]`` and ``[world.identity]``; :mod:`.face` turns an identity into the
MuJoCo head's sizes and colours.
"""

from __future__ import annotations

import colorsys
import dataclasses
from dataclasses import dataclass

import numpy as np

from .mjcf import HEAD_RADII_M, PUPIL_RGB
from .options import WorldConfig

__all__ = ["HAIR_COLOURS", "IRIS_RAMP", "SKIN_TONES", "Caregiver", "caregiver_from_dict",
           "head_turn_fraction", "iris_colour", "pose_noise_deg", "sample_caregiver"]

_BASE_SKIN = [[0.96, 0.80, 0.69], [0.87, 0.67, 0.53], [0.71, 0.51, 0.38], [0.55, 0.38, 0.26],
              [0.38, 0.26, 0.18]]
_BASE_HAIR = [[0.08, 0.06, 0.05], [0.28, 0.18, 0.10], [0.55, 0.42, 0.25], [0.62, 0.60, 0.58],
              [0.45, 0.20, 0.10]]
# The base palettes are the colours of before; the wide ones keep their saturation below 0.7
# (the objects' is 0.85 or more, and the detector's threshold 0.8), so the base auburn is duller.
SKIN_TONES = {
    "base": np.array(_BASE_SKIN),
    "wide": np.array(_BASE_SKIN + [[0.99, 0.87, 0.79], [0.76, 0.60, 0.42], [0.27, 0.18, 0.13]]),
}
HAIR_COLOURS = {
    "base": np.array(_BASE_HAIR),
    "wide": np.array([
        [0.05, 0.04, 0.04],  # black
        [0.28, 0.18, 0.10],  # dark brown
        [0.40, 0.27, 0.15],  # mid brown
        [0.55, 0.42, 0.25],  # light brown
        [0.66, 0.53, 0.33],  # dark blonde
        [0.82, 0.70, 0.45],  # blonde
        [0.90, 0.86, 0.72],  # platinum
        [0.46, 0.25, 0.16],  # auburn
        [0.62, 0.36, 0.24],  # red
        [0.72, 0.47, 0.30],  # ginger
        [0.62, 0.60, 0.58],  # grey
        [0.90, 0.90, 0.88],  # white
    ]),
}
# The iris colour along [0, 1]: the default near-black dark brown, brown, hazel, blue-grey.
IRIS_RAMP = (np.array([0.0, 0.35, 0.65, 1.0]),
             np.array([PUPIL_RGB, (0.24, 0.14, 0.07), (0.32, 0.30, 0.16), (0.40, 0.50, 0.58)]))


@dataclass(frozen=True)
class Caregiver:
    """Who the caregiver is: her head, face, colours and place (her identity).

    Factors are 1 and offsets 0 for the default face (:mod:`.mjcf`); offsets in metres are at
    head scale 1 (they grow with ``head_scale``).
    """

    head_scale: float
    skin_rgb: tuple[float, float, float]
    hair_rgb: tuple[float, float, float]
    shirt_rgb: tuple[float, float, float]
    head_width: float = 1.0
    head_depth: float = 1.0
    head_height: float = 1.0
    hair_volume: float = 1.0
    hairline_m: float = 0.0
    eye_spacing: float = 1.0
    eye_height_m: float = 0.0
    eye_size: float = 1.0
    iris_rgb: tuple[float, float, float] = PUPIL_RGB
    nose_size: float = 1.0
    mouth_width: float = 1.0
    brow_thickness: float = 1.0
    distance_offset_m: float = 0.0  # from caregiver.distance_m
    height_offset_m: float = 0.0  # from caregiver.height_m
    head_turn_offset: float = 0.0  # from caregiver.head_turn_fraction
    pose_noise_offset_deg: float = 0.0  # from caregiver.pose_noise_deg

    @property
    def face_radius_m(self) -> float:
        """Half the head's height (the face window is cropped from it)."""
        return HEAD_RADII_M[2] * self.head_scale * self.head_height


def head_turn_fraction(world: WorldConfig, caregiver: Caregiver) -> float:
    """Her head's share of a gaze turn (the eyes make the rest)."""
    return world.caregiver.head_turn_fraction + caregiver.head_turn_offset


def pose_noise_deg(world: WorldConfig, caregiver: Caregiver) -> float:
    """Her s.d. of the head's yaw and pitch error, in degrees."""
    return world.caregiver.pose_noise_deg + caregiver.pose_noise_offset_deg


def iris_colour(t: float) -> tuple[float, float, float]:
    """The iris colour at ``t`` in [0, 1] along :data:`IRIS_RAMP`."""
    at, rgb = IRIS_RAMP
    return tuple(float(np.interp(t, at, rgb[:, c])) for c in range(3))


def _draw(rng: np.random.Generator, lo_hi) -> float:
    """A uniform draw in ``lo_hi``; a degenerate range draws nothing and gives its value."""
    lo, hi = lo_hi
    return float(lo) if lo == hi else float(rng.uniform(lo, hi))


def _rgb(a) -> tuple[float, float, float]:
    return tuple(float(x) for x in np.clip(a, 0, 1))


def sample_caregiver(world: WorldConfig, rng: np.random.Generator) -> Caregiver:
    """A caregiver identity drawn from ``world``'s ranges."""
    ident, cg = world.identity, world.caregiver
    lo, hi = cg.head_scale_range
    skins, hairs = SKIN_TONES[ident.skin_palette], HAIR_COLOURS[ident.hair_palette]
    skin = skins[rng.integers(len(skins))] * rng.uniform(*ident.skin_brightness_range)
    hair = hairs[rng.integers(len(hairs))]
    # Dull shirt: low saturation, so that only the objects are bright colours.
    shirt = colorsys.hsv_to_rgb(rng.uniform(), rng.uniform(0.1, 0.3), rng.uniform(0.3, 0.6))
    head_scale = float(rng.uniform(lo, hi))
    # The draws above are those made before [world.identity] existed, in their order. The new
    # ones come after them, each only if its range is not degenerate (_draw), so that a default
    # world (every new range degenerate) draws the same numbers as before and no stream shifts.
    width, depth, height = (_draw(rng, r) for r in (
        ident.head_width_range, ident.head_depth_range, ident.head_height_range))
    hair = hair * _draw(rng, ident.hair_brightness_range)
    face = {name: _draw(rng, getattr(ident, field)) for name, field in (
        ("hair_volume", "hair_volume_range"), ("hairline_m", "hairline_range_m"),
        ("eye_spacing", "eye_spacing_range"), ("eye_height_m", "eye_height_range_m"),
        ("eye_size", "eye_size_range"))}
    iris = iris_colour(_draw(rng, ident.iris_range))
    features = {name: _draw(rng, getattr(ident, f"{name}_range")) for name in (
        "nose_size", "mouth_width", "brow_thickness")}
    place = {name: 0.0 if spread == 0 else float(rng.uniform(-spread, spread)) for name, spread in (
        ("distance_offset_m", cg.distance_spread_m), ("height_offset_m", cg.height_spread_m),
        ("head_turn_offset", cg.head_turn_spread),
        ("pose_noise_offset_deg", cg.pose_noise_spread_deg))}
    return Caregiver(head_scale=head_scale, skin_rgb=_rgb(skin), hair_rgb=_rgb(hair),
                     shirt_rgb=_rgb(shirt), head_width=width, head_depth=depth,
                     head_height=height, iris_rgb=iris, **face, **features, **place)


def caregiver_from_dict(d) -> Caregiver:
    """The identity written as ``dataclasses.asdict`` (JSON lists for tuples).

    Fields a file lacks take their defaults (files written before they existed); anything else
    wrong raises ``ValueError`` naming it.
    """
    if not isinstance(d, dict):
        raise ValueError(f"expected a table of an identity's fields, got {type(d).__name__}")
    fields = {f.name: f for f in dataclasses.fields(Caregiver)}
    unknown = sorted(set(d) - set(fields))
    if unknown:
        raise ValueError(f"unknown field {unknown[0]!r}")
    out = {}
    for name, value in d.items():
        if name.endswith("_rgb"):
            if not (isinstance(value, (list, tuple)) and len(value) == 3
                    and all(isinstance(x, (int, float)) and 0 <= x <= 1 for x in value)):
                raise ValueError(f"{name} = {value!r}: expected three numbers in [0, 1]")
            value = tuple(float(x) for x in value)
        elif isinstance(value, bool) or not isinstance(value, (int, float)) \
                or not np.isfinite(value):
            raise ValueError(f"{name} = {value!r}: expected a number")
        out[name] = float(value) if not isinstance(value, tuple) else value
    missing = [n for n, f in fields.items() if f.default is dataclasses.MISSING and n not in out]
    if missing:
        raise ValueError(f"field {missing[0]!r} is missing")
    return Caregiver(**out)
