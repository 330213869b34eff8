"""How a scene looks apart from its geometry: the light, the room's colours, the robot's image.

Drawn per scene (:func:`sample_look`) from ``[world.lighting]``, ``[world.room]`` and
``[world.sensor]``; the default :class:`Look` is the world as it always looked.
"""

from __future__ import annotations

import colorsys
from dataclasses import dataclass

import numpy as np

from .mjcf import HEADLIGHT_AMBIENT, KEY_LIGHT_DIR
from .options import WorldConfig

__all__ = ["COOL_RGB", "WARM_RGB", "Look", "apply_sensor", "light_tint", "sample_look"]

WARM_RGB = np.array([1.0, 0.9, 0.78])  # the key light at tint -1 (a bulb)
COOL_RGB = np.array([0.82, 0.91, 1.0])  # at tint +1 (daylight)


@dataclass(frozen=True)
class Look:
    """One scene's light colour and direction, ambient light, room colours and image effects."""

    light_dir: tuple[float, float, float] | None = None  # the key light's; None: the default
    light_rgb: tuple[float, float, float] = (1.0, 1.0, 1.0)  # factors on its intensity
    ambient: float = HEADLIGHT_AMBIENT
    wall_rgb: tuple[float, float, float] = (1.0, 1.0, 1.0)  # factors on the walls' colours
    floor_rgb: tuple[float, float, float] = (1.0, 1.0, 1.0)  # on the floor's
    blur_sd_px: float = 0.0
    gain: float = 1.0
    noise_sd: float = 0.0  # grey levels
    noise_seed: int = 0  # the noise of the scene's images

    @property
    def plain_image(self) -> bool:
        """Whether the robot's image is the render as it is (no blur, gain or noise)."""
        return self.blur_sd_px == 0 and self.gain == 1 and self.noise_sd == 0


def light_tint(t: float) -> tuple[float, float, float]:
    """The key light's colour factors at tint ``t``: -1 warm, 0 white, +1 cool."""
    end = WARM_RGB if t < 0 else COOL_RGB
    return tuple(float(x) for x in 1 + abs(t) * (end - 1))


def _draw(rng: np.random.Generator, lo_hi) -> float:
    lo, hi = lo_hi
    return float(lo) if lo == hi else float(rng.uniform(lo, hi))


def _surface(world: WorldConfig, rng: np.random.Generator) -> tuple[float, float, float]:
    """Colour factors of a wall or the floor: a brightness and a tint of a random hue."""
    room = world.room
    brightness = _draw(rng, room.brightness_range)
    saturation = _draw(rng, room.tint_saturation_range)
    hue = float(rng.uniform()) if saturation > 0 else 0.0
    return tuple(brightness * x for x in colorsys.hsv_to_rgb(hue, saturation, 1.0))


def _direction(jitter_deg: float, rng: np.random.Generator) -> tuple[float, float, float]:
    """The key light's default direction turned by normal errors in azimuth and elevation."""
    x, y, z = np.asarray(KEY_LIGHT_DIR) / np.linalg.norm(KEY_LIGHT_DIR)
    az, el = np.arctan2(y, x), np.arcsin(z)
    az, el = az + rng.normal(0, np.deg2rad(jitter_deg)), el + rng.normal(0, np.deg2rad(jitter_deg))
    el = float(np.clip(el, -np.pi / 2 + 0.05, -0.05))  # the light shines down
    return (float(np.cos(el) * np.cos(az)), float(np.cos(el) * np.sin(az)), float(np.sin(el)))


def sample_look(world: WorldConfig, rng: np.random.Generator) -> Look:
    """A scene's look drawn from ``world``'s ranges.

    Each number is drawn only if its range is not degenerate, so that a default world draws
    none and its other streams do not shift.
    """
    light = world.lighting
    direction = (None if light.direction_jitter_deg == 0
                 else _direction(light.direction_jitter_deg, rng))
    tint = light_tint(_draw(rng, light.tint_range))
    ambient = _draw(rng, light.ambient_range)
    walls, floor = _surface(world, rng), _surface(world, rng)
    sensor = world.sensor
    blur, gain = _draw(rng, sensor.blur_sd_range_px), _draw(rng, sensor.gain_range)
    noise = _draw(rng, sensor.noise_sd_range_levels)
    seed = int(rng.integers(2**63)) if noise > 0 else 0
    return Look(direction, tint, ambient, walls, floor, blur, gain, noise, seed)


def apply_sensor(image: np.ndarray, look: Look, rng: np.random.Generator) -> np.ndarray:
    """``image`` (RGB uint8) as the robot's camera gives it: blurred, exposed, noisy.

    In the order light meets them: the lens's blur, the exposure's gain, the sensor's noise
    (drawn from ``rng``, new in each image).
    """
    if look.plain_image:
        return image
    import cv2

    out = image.astype(np.float32)
    if look.blur_sd_px > 0:
        out = cv2.GaussianBlur(out, (0, 0), look.blur_sd_px)
    out *= look.gain
    if look.noise_sd > 0:
        out += look.noise_sd * rng.standard_normal(out.shape, dtype=np.float32)
    return np.clip(np.rint(out), 0, 255).astype(np.uint8)
