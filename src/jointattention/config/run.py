"""A run's configuration: the world, the robot, the model, the conditions and the presets."""

from __future__ import annotations

import copy
import tomllib
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np

from .._checks import check_int, check_name, short_repr
from .._fields import FrozenTable, Section, from_mapping, merge_tagged, param, to_mapping
from .._readers import check_nesting, read_toml
from .._toml import dumps
from ..agent.options import AgentConfig, DetectorConfig
from ..errors import ArgumentError, ConfigError, FileError
from ..models.registry import MODELS, ModelOptions
from ..world.options import N_OBJECTS, WorldConfig
from ._legacy import upgrade

__all__ = [
    "ConditionConfig",
    "Config",
    "ExperimentConfig",
    "HeldOutConfig",
    "RecordingConfig",
    "check_config",
    "condition_named",
    "load_config",
    "model_options",
    "preset_names",
    "to_toml",
    "with_n_objects",
]


def _default_model() -> ModelOptions:
    return MODELS["bootstrap"]()


@dataclass(frozen=True)
class ConditionConfig(Section):
    """One experimental condition: an object count, and changes to the run's model."""

    name: str = param("n5-sigmoid", "name of the condition (figure labels, file names): 1-80 "
                      "letters, digits and _ . , = + -")
    n_objects: int = param(N_OBJECTS, "objects in each trial, the caregiver's target among "
                           "them (the run's one count of objects: the world has none)", lo=1,
                           hi=20)
    model: FrozenTable = param(
        factory=FrozenTable, help="changes to the run's [model] for this condition, e.g. "
        "{ gate = { kind = \"constant\", rate = 0.7 } }, or another model: { kind = ... }")
    shuffle_faces: bool = param(
        False, "control: pair each trial with the face window of another data set")

    def __post_init__(self) -> None:
        check_name(self.name, "name")
        if not isinstance(self.model, FrozenTable):  # a plain dict is welcome
            if not isinstance(self.model, Mapping):
                raise ConfigError(f"model = {self.model!r}: expected a table of settings")
            object.__setattr__(self, "model", FrozenTable(self.model))
        super().__post_init__()


@dataclass(frozen=True)
class HeldOutConfig(Section):
    """Held-out data sets each cell's model is measured on, frozen, beside its training sets.

    Three kinds: the training sets themselves, new poses of the training caregivers, and
    caregivers it never saw, both recorded from the world's held-out stream (one no training
    recording uses). For the shipped training sets the package ships both held-out files.
    """

    n_trials: int = param(500, "trials of the frozen model on each kind of data set at each "
                          "checkpoint (0: no held-out measure)", lo=0, hi=10**6)
    n_checkpoints: int = param(5, "learning times at which they are measured, evenly spaced, "
                               "the last at the end of learning", lo=1, hi=1000)
    poses: str = param("", "data-set file of new poses of the training caregivers (empty: the "
                       "shipped one for the shipped data sets, else recorded by each worker "
                       "from the held-out stream, which needs off-screen OpenGL)")
    caregivers: str = param("", "data-set file of caregivers the model never saw (empty: as "
                            "for poses)")
    n_poses: int = param(250, "new poses recorded when poses is empty (the training "
                         "caregivers in turn)", lo=1, hi=100_000)
    n_caregivers: int = param(16, "unseen caregivers recorded when caregivers is empty", lo=1,
                              hi=1000)
    poses_per_caregiver: int = param(25, "data sets of each unseen caregiver recorded", lo=1,
                                     hi=10_000)
    seed: int = param(0, "seed of the held-out recordings", lo=0, hi=2**63 - 1)


@dataclass(frozen=True)
class ExperimentConfig(Section):
    """How long to learn, how many seeds, how the robot sees, and the conditions."""

    n_steps: int = param(300_000, "learning time of a run, in steps (paper: 3e5; at most 1e9, "
                         "about an hour per cell compiled)", lo=1, hi=10**9)
    n_seeds: int = param(10, "independent runs of each condition", lo=1, hi=10_000)
    bin_steps: int = param(10_000, "width of a learning-time bin of the success curves", lo=1,
                           hi=10**9)
    perception: str = param(
        "fast", "how the robot sees during learning: fast (objects projected, no rendering) or "
        "rendered (each step rendered with MuJoCo and detected with OpenCV; about 30x slower)",
        choices=("fast", "rendered"))
    engine: str = param(
        "compiled", "how fast-perception cells run: compiled (whole cells in compiled code; "
        "every shipped model), python (step by step through the Agent "
        "and Scene seams: any model, rendered perception, step observers), or auto (each "
        "condition compiled if its model allows, else python); all give the same records",
        choices=("compiled", "python", "auto"))
    n_ceiling_trials: int = param(
        4000, "trials of the oracle that measure each object count's ceiling", lo=1,
        hi=10**7)
    probe_datasets: int = param(
        2000, "data sets the learning module's error is measured on at each bin's end, and "
        "each held-out kind's errors and controls: all, or this many drawn once from the "
        "run's seed if there are more (0: all)", lo=0,
        hi=10**7)
    head_moves_per_s: float = param(
        5.0, "moves a real pan/tilt head makes per second: the learning-speed table gives each "
        "learning time in minutes of such a head too", lo=0.01, hi=1000)
    held_out: HeldOutConfig = HeldOutConfig()
    conditions: tuple[ConditionConfig, ...] = param(
        (ConditionConfig(),), "the conditions to run (at least one)")

    def __post_init__(self) -> None:
        super().__post_init__()
        if not self.conditions:
            raise ConfigError("conditions = []: expected at least one condition")

    def bin_ends_steps(self) -> np.ndarray:
        """The learning time at which each learning-time bin ends (the last one at n_steps)."""
        n_bins = int(np.ceil(self.n_steps / self.bin_steps))
        return np.minimum(np.arange(1, n_bins + 1) * self.bin_steps, self.n_steps)


@dataclass(frozen=True)
class RecordingConfig(Section):
    """Training sets the run records itself in its world, instead of reading ``datasets``."""

    caregivers: int = param(0, "caregivers to record (0: read the datasets file instead)", lo=0,
                            hi=10_000)
    poses_per_caregiver: int = param(125, "data sets posed by each caregiver", lo=1,
                                     hi=100_000)
    seed: int = param(1, "world seed of the recording (0 is the shipped data sets' seed)",
                      lo=0, hi=2**63 - 1)


@dataclass(frozen=True)
class Config(Section):
    """The whole configuration of a run."""

    seed: int = param(0, "the seed every random stream of the run is born from", lo=0,
                      hi=2**63 - 1)
    world: WorldConfig = WorldConfig()
    agent: AgentConfig = AgentConfig()
    model: ModelOptions = param(
        factory=_default_model, registry=MODELS,
        help="the model that learns (kind: bootstrap, the paper's) and its options")
    detector: DetectorConfig = DetectorConfig()
    experiment: ExperimentConfig = ExperimentConfig()
    datasets: str = param(
        "", "data-set file of the caregiver (empty: the 125 shipped with the package)")
    recording: RecordingConfig = RecordingConfig()

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.datasets and self.recording.caregivers:
            raise ConfigError(f"datasets = {self.datasets!r} and recording.caregivers = "
                              f"{self.recording.caregivers}: expected one source of training "
                              "sets (a file, or caregivers recorded by the run)")
        names = [c.name for c in self.experiment.conditions]
        for i, c in enumerate(self.experiment.conditions):
            if c.name in names[:i]:
                raise ConfigError(f"experiment.conditions[{i}].name = {c.name!r}: expected "
                                  "distinct condition names")
            options = model_options(self, c, where=f"experiment.conditions[{i}].model")
            if self.experiment.engine == "compiled":
                _check_compiled(options, f"experiment.conditions[{i}] ({c.name!r})")
        if self.experiment.engine == "compiled" and self.experiment.perception != "fast":
            raise ConfigError(f"experiment.perception = {self.experiment.perception!r}: the "
                              "compiled engine sees in fast perception only; expected "
                              "experiment.engine = 'python' with rendered perception")


def _check_compiled(options: ModelOptions, where: str) -> None:
    """Refuse, naming it, a model the compiled engine does not run."""
    refusal = options.compiled_refusal()  # each model and gate says what runs compiled
    if refusal is not None:
        raise ConfigError(f"{where}: {refusal}")


def model_options(config: Config, condition: ConditionConfig,
                  where: str = "model") -> ModelOptions:
    """The options of ``condition``'s model.

    The run's ``[model]`` with the condition's changes applied.
    """
    if not condition.model:
        return config.model
    return merge_tagged(MODELS, config.model, condition.model.to_dict(), where)


def condition_named(config: Config, name: str) -> ConditionConfig:
    """The experiment's condition called ``name``."""
    names = [c.name for c in config.experiment.conditions]
    if name not in names:
        raise ConfigError(f"condition {name!r}: expected one of {', '.join(names)}")
    return config.experiment.conditions[names.index(name)]


def with_n_objects(config: Config, n_objects: int) -> Config:
    """Deprecated (goes in version 0.5): ``config`` itself; the world holds no object count.

    A condition says its count (``ConditionConfig.n_objects``); a world, an environment or a
    command takes one as an argument (``World(..., n_objects=)``).
    """
    warnings.warn("with_n_objects is deprecated and goes in version 0.5: the world holds no "
                  "object count; expected n_objects passed to World, the environment or the "
                  "condition", DeprecationWarning, stacklevel=2)
    check_int("n_objects", n_objects, 1, 20)
    return config


def preset_names() -> list[str]:
    """The names of the presets shipped with the package."""
    files = resources.files("jointattention.presets").iterdir()
    return sorted(p.name.removesuffix(".toml") for p in files if p.name.endswith(".toml"))


def preset_about(name: str) -> str:
    """What the preset runs, in one line: the first line of its file's opening comment."""
    if name not in preset_names():
        raise ConfigError(f"unknown preset {name!r}; expected one of {', '.join(preset_names())}")
    text = resources.files("jointattention.presets").joinpath(f"{name}.toml").read_text("utf-8")
    return text.splitlines()[0].lstrip("#").strip()


def load_config(source: str | Path | Mapping | None = None) -> Config:
    """A configuration from a preset, a TOML file, a mapping as TOML gives, or the defaults.

    ``None`` gives the defaults. Anything wrong is one
    :class:`~jointattention.errors.ConfigError` naming the setting.
    """
    if source is None:
        return Config()
    if isinstance(source, Mapping):
        try:
            check_nesting(dict(source))  # before deepcopy, which recurses
        except ValueError as err:
            raise ConfigError(f"config mapping: {err}; expected a configuration") from None
        return from_mapping(Config, upgrade(copy.deepcopy(dict(source))))
    if not isinstance(source, (str, Path)):
        raise ConfigError(f"config source {source!r}: expected a preset name, a .toml file, a "
                          "mapping or None")
    path = Path(source)
    if path.suffix != ".toml":
        if str(source) not in preset_names():
            raise ConfigError(
                f"{source}: no such preset; expected a .toml file or one of "
                f"{', '.join(preset_names())}"
            )
        text = resources.files("jointattention.presets").joinpath(f"{source}.toml").read_text()
        return from_mapping(Config, upgrade(tomllib.loads(text)))
    try:
        data = read_toml(path, "a configuration (TOML)")
    except FileError as err:
        raise ConfigError(str(err)) from None
    return from_mapping(Config, upgrade(data))


def check_config(value, name: str = "config") -> Config:
    """``value`` if it is a :class:`Config`, else one ArgumentError naming ``name``."""
    if not isinstance(value, Config):
        raise ArgumentError(f"{name} {short_repr(value)}: expected a Config (load_config(...))")
    return value


def to_toml(config: Config) -> str:
    """The configuration as TOML text that :func:`load_config` reads back."""
    return dumps(to_mapping(config))
