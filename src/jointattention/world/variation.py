"""How the world varies: the caregivers' faces, the room's colours, the robot camera's image.

Sections of :class:`~jointattention.world.options.WorldConfig` (``[world.identity]``,
``[world.room]``, ``[world.sensor]``). A range whose two ends are equal is *degenerate*: it
draws no random number and gives its one value. Every default is degenerate at today's value,
so the default world draws and shows exactly what it did before these sections existed; the
``many-caregivers`` preset widens them (docs/world.md).
"""

from __future__ import annotations

from dataclasses import dataclass

from .._fields import Section, param

__all__ = ["PALETTES", "IdentityConfig", "RoomConfig", "SensorConfig"]

PALETTES = ("base", "wide")  # world/identity.py holds the colours of each


def _factor(what: str, lo: float, hi: float):
    """A per-identity range of a size factor, (1, 1) by default."""
    return param((1.0, 1.0), f"per identity: {what}, a factor (1: the default face)", lo=lo, hi=hi)


@dataclass(frozen=True)
class IdentityConfig(Section):
    """How caregivers differ from one another: drawn once per identity."""

    head_width_range: tuple[float, float] = _factor(
        "the head's width (on top of caregiver.head_scale_range)", 0.6, 1.5)
    head_depth_range: tuple[float, float] = _factor(
        "the head's depth (front to back; the face's features follow its surface)", 0.6, 1.5)
    head_height_range: tuple[float, float] = _factor(
        "the head's height (the face window's crop follows it)", 0.6, 1.5)
    skin_palette: str = param(
        "base", "per identity: the skin tones drawn from: 'base' (five, light to dark) or 'wide' "
        "(eight: adds very fair, olive and very dark)", choices=PALETTES)
    skin_brightness_range: tuple[float, float] = param(
        (0.93, 1.05), "per identity: a factor on the skin tone's brightness (always drawn, as "
        "before [world.identity] existed)", lo=0.3, hi=2.0)
    hair_palette: str = param(
        "base", "per identity: the hair colours drawn from: 'base' (five: black, two browns, grey, "
        "auburn) or 'wide' (twelve: black, three browns, two blondes, platinum, auburn, red, "
        "ginger, grey, white; all below 0.7 saturation)", choices=PALETTES)
    hair_brightness_range: tuple[float, float] = _factor(
        "the hair colour's brightness (so that no two people share one exactly)", 0.3, 2.0)
    hair_volume_range: tuple[float, float] = _factor(
        "the hair's volume: its size, its front edge kept at the forehead", 0.6, 1.6)
    hairline_range_m: tuple[float, float] = param(
        (0.0, 0.0), "per identity: how far the hair sits above (+, more forehead) or below (-) "
        "its default place, at head scale 1", lo=-0.04, hi=0.04)
    eye_spacing_range: tuple[float, float] = _factor(
        "the distance between the eyes (the brows follow)", 0.6, 1.5)
    eye_height_range_m: tuple[float, float] = param(
        (0.0, 0.0), "per identity: the eyes' (and brows') height above (+) or below (-) their "
        "default place, at head scale 1", lo=-0.03, hi=0.03)
    eye_size_range: tuple[float, float] = _factor("the eyeballs' and irises' size", 0.5, 1.6)
    iris_range: tuple[float, float] = param(
        (0.0, 0.0), "per identity: the iris colour, from 0 (near-black dark brown, the default) "
        "through brown and hazel to 1 (blue-grey)", lo=0, hi=1)
    nose_size_range: tuple[float, float] = _factor("the nose's size", 0.4, 2.0)
    mouth_width_range: tuple[float, float] = _factor("the mouth's width", 0.4, 2.0)
    brow_thickness_range: tuple[float, float] = _factor("the brows' thickness", 0.2, 3.0)


@dataclass(frozen=True)
class RoomConfig(Section):
    """The background (walls and floor): drawn per scene."""

    brightness_range: tuple[float, float] = param(
        (1.0, 1.0), "per scene: the walls' and (drawn apart) the floor's brightness, a factor on "
        "their default greys", lo=0.1, hi=2.0)
    tint_saturation_range: tuple[float, float] = param(
        (0.0, 0.0), "per scene: HSV saturation of a random hue tinting the walls and (drawn "
        "apart) the floor; at most 0.4, so that only the objects are bright colours", lo=0,
        hi=0.4)


@dataclass(frozen=True)
class SensorConfig(Section):
    """The robot camera's image effects: drawn per scene, applied to the eye camera's colour image.

    Not to segmentation images nor to the experimenter's overview camera. Applied in the order
    light meets them: blur (the lens), gain (exposure), noise (the sensor).
    """

    blur_sd_range_px: tuple[float, float] = param(
        (0.0, 0.0), "per scene: s.d. of the Gaussian blur of the robot's image (0: sharp)", lo=0,
        hi=5)
    gain_range: tuple[float, float] = param(
        (1.0, 1.0), "per scene: exposure, a factor on every pixel of the robot's image", lo=0.2,
        hi=4)
    noise_sd_range_levels: tuple[float, float] = param(
        (0.0, 0.0), "per scene: s.d. of Gaussian sensor noise, in grey levels (0-255), new in "
        "each image", lo=0, hi=50)
