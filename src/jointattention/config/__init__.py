"""Validated configuration: one source for every parameter, with presets in TOML.

Every field carries its help text and its allowed range; building a section checks them and
raises :class:`~jointattention.errors.ConfigError` naming the field. Angles are in degrees in
the configuration (readable) and in radians in the code that uses them (``*_rad`` names).

A model's or a gate's options are a section of :func:`param` fields too (see
``docs/architecture.md``).

The configuration is the composition root: each section's options live with what they
configure, and this package puts them together. Sections: ``[world]`` (what only the
experimenter sets, :mod:`jointattention.world.options`; how it varies,
:mod:`jointattention.world.variation`), ``[agent]`` (the robot's shared mechanisms) and
``[detector]`` (:mod:`jointattention.agent.options`), ``[model]`` (what learns: a kind
registered in :data:`~jointattention.models.registry.MODELS` and its options) and
``[experiment]`` with its conditions (:mod:`.run`). It imports the robot, the models and the
world's options, and no engine.

Layer 4: it may import the world's and the robot's options, the models' registry and the
plumbing.
"""

from .._fields import param
from ..agent.options import AgentConfig, DetectorConfig
from ..world.options import (
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
    preset_about,
    preset_names,
    to_toml,
    with_n_objects,
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
    "preset_about",
    "preset_names",
    "to_toml",
    "with_n_objects",
]
