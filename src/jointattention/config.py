"""Validated configuration: one source for every parameter, with presets in TOML.

Every field carries its help text and its allowed range; building a section checks them and
raises :class:`~jointattention.errors.ConfigError` naming the field. Angles are in degrees in
the configuration (readable) and in radians in the code that uses them (``*_rad`` names).
"""

from __future__ import annotations

import dataclasses
import tomllib
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from ._fields import check_section, from_mapping, param, to_mapping
from .errors import ConfigError

__all__ = [
    "READINGS",
    "AgentConfig",
    "CameraConfig",
    "CaregiverConfig",
    "ConditionConfig",
    "Config",
    "DetectorConfig",
    "ExperimentConfig",
    "FaceWindowConfig",
    "HeadConfig",
    "LightingConfig",
    "ObjectsConfig",
    "WorldConfig",
    "agent_config",
    "load_config",
    "preset_names",
    "to_toml",
    "with_n_objects",
]


class _Section:
    def __post_init__(self) -> None:
        check_section(self)


@dataclass(frozen=True)
class CameraConfig(_Section):
    width_px: int = param(320, "image width W in pixels (the paper's d_th is W/6)", lo=16, hi=4096)
    height_px: int = param(240, "image height in pixels", lo=16, hi=4096)
    fov_deg: float = param(
        40.0, "horizontal field of view of the pinhole camera (40: the 10-object ceiling is "
        "above 0.8; README, The world)", lo=5, hi=150)
    offset_m: tuple[float, float, float] = param(
        (-0.03, 0.06, 0.05),
        "optical centre in the head frame (right, forward, up) from the pan/tilt axes' "
        "intersection: the left camera of a stereo head, as in the paper",
        lo=-0.5,
        hi=0.5,
    )


@dataclass(frozen=True)
class HeadConfig(_Section):
    pan_limits_deg: tuple[float, float] = param(
        (-60.0, 60.0), "pan joint range (positive turns right)", lo=-170, hi=170
    )
    tilt_limits_deg: tuple[float, float] = param(
        (-45.0, 35.0), "tilt joint range (positive looks up)", lo=-85, hi=85
    )


@dataclass(frozen=True)
class CaregiverConfig(_Section):
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


@dataclass(frozen=True)
class ObjectsConfig(_Section):
    n_objects: int = param(5, "number of salient objects in a scene", lo=1, hi=20)
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
class LightingConfig(_Section):
    intensity_range: tuple[float, float] = param(
        (0.55, 0.85), "range of the key light's diffuse intensity", lo=0, hi=1
    )
    position_jitter_m: float = param(0.5, "s.d. of the key light's position", lo=0, hi=3)


@dataclass(frozen=True)
class FaceWindowConfig(_Section):
    width_px: int = param(30, "width of the caregiver's face window (paper: 30)", lo=4, hi=256)
    height_px: int = param(25, "height of the caregiver's face window (paper: 25)", lo=4, hi=256)
    margin: float = param(
        1.15, "crop height as a multiple of the face's apparent height", lo=0.5, hi=4
    )


@dataclass(frozen=True)
class WorldConfig(_Section):
    camera: CameraConfig = CameraConfig()
    head: HeadConfig = HeadConfig()
    caregiver: CaregiverConfig = CaregiverConfig()
    objects: ObjectsConfig = ObjectsConfig()
    lighting: LightingConfig = LightingConfig()
    face_window: FaceWindowConfig = FaceWindowConfig()

    def __post_init__(self) -> None:
        check_section(self)
        for name, (lo, hi) in [
            ("head.pan_limits_deg", self.head.pan_limits_deg),
            ("head.tilt_limits_deg", self.head.tilt_limits_deg),
            ("objects.radius_range_m", self.objects.radius_range_m),
            ("objects.distance_range_m", self.objects.distance_range_m),
            ("objects.pan_range_deg", self.objects.pan_range_deg),
            ("objects.tilt_range_deg", self.objects.tilt_range_deg),
            ("caregiver.head_scale_range", self.caregiver.head_scale_range),
            ("lighting.intensity_range", self.lighting.intensity_range),
        ]:
            if lo > hi:
                raise ConfigError(f"{name} = [{lo}, {hi}]: expected the low end first")
        if self.objects.distance_range_m[1] >= self.caregiver.distance_m:
            raise ConfigError(
                f"objects.distance_range_m = {list(self.objects.distance_range_m)}: expected "
                f"objects nearer than the caregiver (caregiver.distance_m = "
                f"{self.caregiver.distance_m}), so that it can look at them"
            )


@dataclass(frozen=True)
class AgentConfig(_Section):
    """The robot's embedded mechanisms (paper, section III) and their parameters."""

    interest_weights: tuple[float, float, float] = param(
        (1.0, 0.0, 0.0), "(a1, a2, a3) of Eq. 1: colour area, edge complexity, motion", lo=0)
    vf_gain_rad_per_px: float = param(
        0.0025, "gain g of the visual feedback controller (Eq. 2)", lo=0, hi=0.1)
    d_th_fraction: float = param(
        1 / 6, "evaluator threshold d_th as a fraction of the image width W (Eq. 3: W/6)",
        lo=0.01, hi=1)
    lm_step_deg: float = param(4.0, "length of one step of the learning module", lo=0.1, hi=30)
    n_hidden: int = param(7, "hidden units of the learning module (paper: 7)", lo=1, hi=1000)
    learning_rate: float = param(
        0.0003, "back-propagation step size (about 750 standardised inputs: keep it small)",
        lo=0, hi=10)
    momentum: float = param(0.5, "momentum of the back-propagation updates", lo=0, hi=0.999)
    init_scale: float = param(
        1.0, "scale of the initial weights (times 1/sqrt(fan-in))", lo=0, hi=100)
    gate: str = param("sigmoid", "gating function", choices=("sigmoid", "constant"))
    gate_rate: float = param(0.9, "rate of choosing the learning module for a constant gate",
                             lo=0, hi=1)
    gate_midpoint_steps: float = param(
        1.2e5, "learning time at which the sigmoid gate chooses each module equally", lo=0)
    gate_width_steps: float = param(
        2.0e4, "learning time over which the sigmoid gate rises by a factor e", lo=1)
    gate_per: str = param(
        "step", "reading: the gate decides at every step, or once per trial",
        choices=("step", "trial"))
    vf_fallback: str = param(
        "random", "reading: what moves the head when the gate picks the visual controller and no "
        "object is in view: the learning module, or a random step", choices=("lm", "random"))
    learning_target: str = param(
        "object_direction", "reading: what each step of a successful trial is taught: the unit "
        "direction to the final gaze, to the attended object (the final gaze plus the visual "
        "controller's command that would centre it), or the step that was executed",
        choices=("final_direction", "object_direction", "executed_step"))
    max_steps: int = param(40, "step limit of a trial", lo=1, hi=10000)

    def d_th_px(self, image_width_px: int) -> float:
        """The internal evaluator's radius (Eq. 3): d_th = W * d_th_fraction."""
        return image_width_px * self.d_th_fraction


@dataclass(frozen=True)
class DetectorConfig(_Section):
    """The robot's image-based salient feature detector (OpenCV), used in rendered mode and by
    ``jointattention detect``. The world paints objects with HSV saturation and value of at
    least 0.85 and everything else below 0.8 saturation, hence the colour thresholds."""

    min_saturation: float = param(
        0.8, "least HSV saturation of a bright-colour pixel (0-1)", lo=0, hi=1)
    min_value: float = param(0.3, "least HSV value (brightness) of a bright-colour pixel (0-1)",
                             lo=0, hi=1)
    hue_split_deg: float = param(
        20.0, "hue step between neighbouring pixels that separates two touching objects",
        lo=1, hi=180)
    min_area_px: int = param(20, "least area of a bright-colour region kept as an object",
                             lo=1)
    canny_thresholds: tuple[float, float] = param(
        (60.0, 150.0), "Canny's hysteresis thresholds for edge complexity (f_edge)", lo=0,
        hi=1000)
    motion_threshold: int = param(
        15, "least grey-level change between frames counted as motion (f_mot)", lo=0, hi=255)
    face_min_score: float = param(
        0.5, "least normalised correlation of a template match accepted as a face", lo=-1,
        hi=1)


@dataclass(frozen=True)
class ConditionConfig(_Section):
    """One experimental condition; unset agent fields keep the agent section's values."""

    name: str = param("n5-sigmoid", "name of the condition (figure labels, file names)")
    n_objects: int = param(5, "objects in each trial, the caregiver's target among them",
                           lo=1, hi=20)
    gate: str | None = param(None, "gating function", choices=("sigmoid", "constant"))
    gate_rate: float | None = param(None, "rate of a constant gate", lo=0, hi=1)
    gate_per: str | None = param(None, "reading: gate per step or per trial",
                                 choices=("step", "trial"))
    vf_fallback: str | None = param(None, "reading: VF with nothing in view",
                                    choices=("lm", "random"))
    learning_target: str | None = param(
        None, "reading: learning target",
        choices=("final_direction", "object_direction", "executed_step"))
    shuffle_faces: bool = param(
        False, "control: pair each trial with the face window of another data set")


@dataclass(frozen=True)
class ExperimentConfig(_Section):
    n_steps: int = param(300_000, "learning time of a run, in steps (paper: 3e5)", lo=1)
    n_seeds: int = param(10, "independent runs of each condition", lo=1, hi=10_000)
    bin_steps: int = param(10_000, "width of a learning-time bin of the success curves", lo=1)
    perception: str = param(
        "fast", "how the robot sees during learning: fast (objects projected, no rendering) or "
        "rendered (each step rendered with MuJoCo and detected with OpenCV; about 30x slower)",
        choices=("fast", "rendered"))
    n_ceiling_trials: int = param(
        4000, "trials of the oracle that measure each object count's ceiling", lo=1)
    conditions: tuple[ConditionConfig, ...] = param(
        (ConditionConfig(),), "the conditions to run")


@dataclass(frozen=True)
class Config(_Section):
    """The whole configuration of a run."""

    seed: int = param(0, "the seed every random stream of the run is born from", lo=0)
    world: WorldConfig = WorldConfig()
    agent: AgentConfig = AgentConfig()
    detector: DetectorConfig = DetectorConfig()
    experiment: ExperimentConfig = ExperimentConfig()
    datasets: str = param(
        "", "data-set file of the caregiver (empty: the 125 shipped with the package)")


def with_n_objects(config: Config, n_objects: int) -> Config:
    """``config`` with a world of ``n_objects`` objects."""
    objects = dataclasses.replace(config.world.objects, n_objects=n_objects)
    return dataclasses.replace(config, world=dataclasses.replace(config.world, objects=objects))


# The agent options where the paper is silent (DESIGN.md's readings).
READINGS = ("gate_per", "vf_fallback", "learning_target")


def agent_config(config: Config, condition: ConditionConfig) -> AgentConfig:
    """The agent section with the condition's overrides applied."""
    changes = {k: getattr(condition, k) for k in ("gate", "gate_rate", *READINGS)
               if getattr(condition, k) is not None}
    return dataclasses.replace(config.agent, **changes)


def preset_names() -> list[str]:
    """The names of the presets shipped with the package."""
    files = resources.files("jointattention.presets").iterdir()
    return sorted(p.name.removesuffix(".toml") for p in files if p.name.endswith(".toml"))


def load_config(source: str | Path | None = None) -> Config:
    """A configuration from a preset name, a TOML file path, or the defaults if ``None``."""
    if source is None:
        return Config()
    path = Path(source)
    if path.suffix != ".toml":
        if str(source) not in preset_names():
            raise ConfigError(
                f"{source}: no such preset; expected a .toml file or one of "
                f"{', '.join(preset_names())}"
            )
        text = resources.files("jointattention.presets").joinpath(f"{source}.toml").read_text()
    else:
        try:
            text = path.read_text(encoding="utf-8")
        except OSError as err:
            raise ConfigError(f"{path}: cannot read the configuration ({err.strerror})") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise ConfigError(f"{source}: not valid TOML ({err})") from None
    return from_mapping(Config, data)


def to_toml(config: Config) -> str:
    """The configuration as TOML text that :func:`load_config` reads back."""
    return _dump_toml(to_mapping(config))


def _dump_toml(mapping: dict, prefix: str = "") -> str:
    def fmt(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
        if isinstance(v, list):
            return "[" + ", ".join(fmt(x) for x in v) + "]"
        return repr(v)

    def is_tables(v):
        return isinstance(v, list) and v and isinstance(v[0], dict)

    lines = [f"{k} = {fmt(v)}" for k, v in mapping.items()
             if not isinstance(v, dict) and not is_tables(v)]
    for k, v in mapping.items():
        if isinstance(v, dict):
            lines += ["", f"[{prefix}{k}]", _dump_toml(v, prefix=f"{prefix}{k}.").strip()]
        elif is_tables(v):
            for item in v:
                lines += ["", f"[[{prefix}{k}]]", _dump_toml(item).strip()]
    return "\n".join(lines).strip() + "\n"
