"""The world's configuration: what only the experimenter sets.

The camera, head, caregiver, objects, light and face window; how caregivers, the room and the
robot's image vary is in :mod:`.variation`.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from types import MappingProxyType

from .._fields import Section, param, to_mapping
from .._toml import dumps
from ..errors import ConfigError
from .variation import IdentityConfig, RoomConfig, SensorConfig

__all__ = [
    "FAST_CAMERA",
    "N_OBJECTS",
    "CameraConfig",
    "CaregiverConfig",
    "EyeWindowConfig",
    "FaceWindowConfig",
    "HeadConfig",
    "IdentityConfig",
    "LightingConfig",
    "ObjectsConfig",
    "RoomConfig",
    "SensorConfig",
    "WorldConfig",
]

N_OBJECTS = 5  # objects in a scene when no condition says otherwise (the paper's Fig. 5)
# The camera settings that keep a 320 x 240 view's look and render it about 2.5x as fast on a
# CPU: one sample per pixel, 16 x 8 facets per sphere (Gymnasium's render_quality="fast").
FAST_CAMERA = MappingProxyType({"antialias_samples": 0, "sphere_slices": 16,
                                "sphere_stacks": 8})


@dataclass(frozen=True)
class CameraConfig(Section):
    """The robot's pinhole camera (docs/world.md)."""

    width_px: int = param(320, "image width W in pixels (the paper's d_th is W/6)", lo=16, hi=4096)
    height_px: int = param(240, "image height in pixels", lo=16, hi=4096)
    fov_deg: float = param(
        40.0, "horizontal field of view of the pinhole camera (40: the 10-object ceiling is "
        "above 0.8; docs/world.md)", lo=5, hi=150)
    offset_m: tuple[float, float, float] = param(
        (-0.03, 0.06, 0.05),
        "optical centre in the head frame (right, forward, up) from the pan/tilt axes' "
        "intersection: the left camera of a stereo head, as in the paper",
        lo=-0.5,
        hi=0.5,
    )
    antialias_samples: int = param(
        4, "samples per pixel of the rendered images (MuJoCo's offsamples): 0 renders about "
        "twice as fast on a CPU, with jagged edges; every image of the shipped data sets is "
        "rendered with 4 (the rendered preset renders with 0)", lo=0, hi=16)
    sphere_slices: int = param(
        28, "facets around each sphere, ellipsoid and capsule as rendered (MuJoCo's numslices): "
        "fewer render faster on a CPU, with a coarser outline; every image of the shipped data "
        "sets and runs is rendered with 28", lo=4, hi=128)
    sphere_stacks: int = param(
        16, "facets from pole to pole of each sphere, ellipsoid and capsule as rendered "
        "(MuJoCo's numstacks); the shipped images use 16", lo=2, hi=64)


@dataclass(frozen=True)
class HeadConfig(Section):
    """The pan and tilt joints' ranges."""

    pan_limits_deg: tuple[float, float] = param(
        (-60.0, 60.0), "pan joint range (positive turns right)", lo=-170, hi=170
    )
    tilt_limits_deg: tuple[float, float] = param(
        (-45.0, 35.0), "tilt joint range (positive looks up)", lo=-85, hi=85
    )


@dataclass(frozen=True)
class CaregiverConfig(Section):
    """Where the caregiver sits and how its head turns toward its target."""

    distance_m: float = param(1.0, "distance of the caregiver's head from the robot", lo=0.3, hi=5)
    height_m: float = param(0.05, "height of the caregiver's head above the robot's", lo=-1, hi=1)
    position_noise_m: float = param(0.03, "s.d. of the caregiver's head position", lo=0, hi=0.3)
    head_scale_range: tuple[float, float] = param(
        (0.9, 1.1), "range of the caregiver's head size (identity)", lo=0.5, hi=2.0
    )
    head_turn_fraction: float = param(
        0.8, "fraction of the gaze rotation made by the head; the eyes make the rest", lo=0, hi=1
    )
    pose_noise_deg: float = param(2.0, "s.d. of the head's yaw and pitch error", lo=0, hi=20)
    distance_spread_m: float = param(
        0.0, "per identity: her own mean distance is distance_m plus a uniform offset within "
        "+-this (0: every caregiver at distance_m)", lo=0, hi=2)
    height_spread_m: float = param(
        0.0, "per identity: her own head height (her stature) is height_m plus a uniform offset "
        "within +-this", lo=0, hi=0.5)
    head_turn_spread: float = param(
        0.0, "per identity: her head's own share of a gaze turn is head_turn_fraction plus a "
        "uniform offset within +-this (people differ in how much they move the head and how "
        "much only the eyes)", lo=0, hi=0.5)
    pose_noise_spread_deg: float = param(
        0.0, "per identity: her own s.d. of the head's yaw and pitch error is pose_noise_deg "
        "plus a uniform offset within +-this", lo=0, hi=10)


@dataclass(frozen=True)
class ObjectsConfig(Section):
    """The salient objects of a scene: how big, where, how far apart.

    How many is not the world's to say: each condition of a run says it (``n_objects``), and
    a world, an environment or a command without one takes it as an argument (default
    :data:`N_OBJECTS`).
    """

    radius_range_m: tuple[float, float] = param(
        (0.025, 0.045), "range of the objects' radii", lo=0.005, hi=0.3
    )
    distance_range_m: tuple[float, float] = param(
        (0.45, 0.85), "range of the objects' distances from the robot", lo=0.2, hi=5
    )
    pan_range_deg: tuple[float, float] = param(
        (-45.0, 45.0), "range of the objects' directions in pan", lo=-170, hi=170
    )
    tilt_range_deg: tuple[float, float] = param(
        (-35.0, 20.0), "range of the objects' directions in tilt", lo=-85, hi=85
    )
    min_gap_deg: float = param(
        3.0, "least angular gap between two objects' edges, as seen by the robot", lo=0, hi=45
    )
    face_clearance_deg: float = param(
        15.0,
        "least angle between an object and the caregiver's face, as seen by the robot",
        lo=0,
        hi=90,
    )


@dataclass(frozen=True)
class LightingConfig(Section):
    """How the key light varies from scene to scene."""

    intensity_range: tuple[float, float] = param(
        (0.55, 0.85), "range of the key light's diffuse intensity", lo=0, hi=1
    )
    position_jitter_m: float = param(0.5, "s.d. of the key light's position", lo=0, hi=3)
    direction_jitter_deg: float = param(
        0.0, "per scene: s.d. of the key light's direction in azimuth and in elevation about "
        "its default (down, toward the caregiver)", lo=0, hi=60)
    tint_range: tuple[float, float] = param(
        (0.0, 0.0), "per scene: the key light's colour, from -1 (warm, like a bulb) through 0 "
        "(white) to +1 (cool, like daylight)", lo=-1, hi=1)
    ambient_range: tuple[float, float] = param(
        (0.4, 0.4), "per scene: the ambient light's strength (grey, from every side)", lo=0, hi=1)


@dataclass(frozen=True)
class FaceWindowConfig(Section):
    """The caregiver's face window the robot keeps (paper: 30 x 25 pixels)."""

    width_px: int = param(30, "width of the caregiver's face window (paper: 30)", lo=4, hi=256)
    height_px: int = param(25, "height of the caregiver's face window (paper: 25)", lo=4, hi=256)
    margin: float = param(
        1.15, "crop height as a multiple of the face's apparent height", lo=0.5, hi=4
    )


@dataclass(frozen=True)
class EyeWindowConfig(Section):
    """A window on the caregiver's eyes, seen through a fovea finer than the camera.

    Off by default (the paper's robot keeps the face window only). Where head turns differ
    among people, where the head points is not where the eyes look (docs/results/people/
    head_pose_bound.md): reading the eyes takes seeing the irises move, which at the camera's
    own resolution is under a pixel. The eye window is cut around both eyes from a sensor
    ``zoom`` times finer than the camera's (as a 1280 x 960 camera is to a 320 x 240 one at 4);
    the simulator renders only that part of it (:meth:`~.simulator.World.render_fovea`).
    """

    width_px: int = param(0, "width of the eye window (0: no eye window)", lo=0, hi=256)
    height_px: int = param(0, "height of the eye window (0: no eye window)", lo=0, hi=256)
    zoom: float = param(4.0, "the fovea's resolution as a multiple of the camera's", lo=1, hi=16)
    span: float = param(2.0, "the window's width in eye distances (centre to centre)", lo=1,
                        hi=6)
    placement_sd: float = param(
        0.0, "s.d. of the robot's error in placing the window, in eye distances, on each axis "
        "and (as a log factor) in its width: 0, at the eyeballs' centres, which only the "
        "experimenter knows; an eye finder errs (docs/results/people/eye_placement.md)", lo=0, hi=1)
    socket_patch_px: int = param(
        0, "the side of the patch the robot cuts around each eye's socket, found in the window "
        "(jointattention.agent.eye_sockets), kept in place of the window: the two patches side "
        "by side; 0: the window as cut", lo=0, hi=128)
    socket_finder: str = param(
        "bank", "what finds the sockets for the patches: 'bank', drawn eyes matched in each half "
        "of the window (jointattention.agent.eye_sockets); 'net', the shipped eye-socket network, "
        "fitted on 128 x 48 windows 2.67 eye distances wide (jointattention.agent.socket_net)",
        choices=("bank", "net"))

    def __post_init__(self) -> None:
        super().__post_init__()
        sizes = (self.width_px, self.height_px)
        if (0 in sizes and sizes != (0, 0)) or 0 < min(sizes) < 4:
            raise ConfigError(f"eye_window = {self.width_px} x {self.height_px} px: expected "
                              "both at least 4, or both 0 (no eye window)")

    @property
    def enabled(self) -> bool:
        """Whether the robot keeps an eye window."""
        return self.width_px > 0

    @property
    def kept_size_px(self) -> tuple[int, int]:
        """The (width, height) of what the robot keeps of the window: the socket patches, or it."""
        if self.socket_patch_px:
            return 2 * self.socket_patch_px, self.socket_patch_px
        return self.width_px, self.height_px


@dataclass(frozen=True)
class WorldConfig(Section):
    """What only the experimenter sets: the camera, head, caregiver, objects, light."""

    camera: CameraConfig = CameraConfig()
    head: HeadConfig = HeadConfig()
    caregiver: CaregiverConfig = CaregiverConfig()
    objects: ObjectsConfig = ObjectsConfig()
    lighting: LightingConfig = LightingConfig()
    face_window: FaceWindowConfig = FaceWindowConfig()
    eye_window: EyeWindowConfig = EyeWindowConfig()
    identity: IdentityConfig = IdentityConfig()
    room: RoomConfig = RoomConfig()
    sensor: SensorConfig = SensorConfig()

    def __post_init__(self) -> None:
        super().__post_init__()
        for section in dataclasses.fields(self):
            part = getattr(self, section.name)
            for f in dataclasses.fields(part):
                value = getattr(part, f.name)
                if ("_range" in f.name or "_limits" in f.name) and value[0] > value[1]:
                    raise ConfigError(f"{section.name}.{f.name} = [{value[0]}, {value[1]}]: "
                                      "expected the low end first")
        cg = self.caregiver
        for name, value, spread, lo, hi in (
                ("head_turn_fraction", cg.head_turn_fraction, cg.head_turn_spread, 0.0, 1.0),
                ("pose_noise_deg", cg.pose_noise_deg, cg.pose_noise_spread_deg, 0.0, 20.0)):
            if not lo <= value - spread <= value + spread <= hi:
                raise ConfigError(
                    f"caregiver.{name} = {value} with a spread of +-{spread}: expected "
                    f"{value} - {spread} to {value} + {spread} within [{lo:g}, {hi:g}]")
        if self.objects.distance_range_m[1] >= cg.distance_m - cg.distance_spread_m:
            spread = f" - caregiver.distance_spread_m = {cg.distance_spread_m}" \
                if cg.distance_spread_m else ""
            raise ConfigError(
                f"objects.distance_range_m = {list(self.objects.distance_range_m)}: expected "
                f"objects nearer than the caregiver (caregiver.distance_m = "
                f"{cg.distance_m}{spread}), so that it can look at them"
            )

    def with_people_of(self, other: WorldConfig) -> WorldConfig:
        """This world with ``other``'s people and setting, and its own robot.

        The caregivers (``caregiver``, ``identity``), ``lighting``, ``room`` and ``sensor``
        are ``other``'s; the camera, head, objects and windows stay this world's: the world a
        model learned in, peopled as another world is (e.g. a people-world model among the
        default world's caregivers).
        """
        return dataclasses.replace(self, **{name: getattr(other, name) for name in (
            "caregiver", "identity", "lighting", "room", "sensor")})

    def to_toml(self) -> str:
        """This world as a ``[world]`` section of TOML, which :func:`load_config` reads back."""
        return dumps({"world": to_mapping(self)})
