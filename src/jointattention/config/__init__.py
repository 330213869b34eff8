"""Validated configuration: one source for every parameter, with presets in TOML.

Every field carries its help text and its allowed range; building a section checks them and
raises :class:`~jointattention.errors.ConfigError` naming the field. Angles are in degrees in
the configuration (readable) and in radians in the code that uses them (``*_rad`` names).

A model's or a gate's options are a section of :func:`param` fields too (see
``docs/architecture.md``).

Sections: ``[world]`` (what only the experimenter sets, :mod:`.world`; how it varies,
:mod:`.variation`), ``[agent]`` (the robot's shared mechanisms) and ``[detector]``
(:mod:`.agent`), ``[model]`` (what learns: a kind registered in
:data:`~jointattention.agent.models.MODELS` and its options) and ``[experiment]`` with its
conditions (:mod:`.run`).
"""

from .._fields import param
from .agent import AgentConfig, DetectorConfig
from .run import (
    ConditionConfig,
    Config,
    ExperimentConfig,
    HeldOutConfig,
    RecordingConfig,
    check_config,
    condition_named,
    load_config,
    model_options,
    preset_names,
    to_toml,
    with_n_objects,
)
from .world import (
    CameraConfig,
    CaregiverConfig,
    FaceWindowConfig,
    HeadConfig,
    IdentityConfig,
    LightingConfig,
    ObjectsConfig,
    RoomConfig,
    SensorConfig,
    WorldConfig,
)

__all__ = [
    "AgentConfig",
    "CameraConfig",
    "CaregiverConfig",
    "ConditionConfig",
    "Config",
    "DetectorConfig",
    "ExperimentConfig",
    "FaceWindowConfig",
    "HeadConfig",
    "HeldOutConfig",
    "IdentityConfig",
    "LightingConfig",
    "ObjectsConfig",
    "RecordingConfig",
    "RoomConfig",
    "SensorConfig",
    "WorldConfig",
    "check_config",
    "condition_named",
    "load_config",
    "model_options",
    "param",
    "preset_names",
    "to_toml",
    "with_n_objects",
]
