"""Held-out measures of every cell: the frozen model on its training sets, new poses, new people.

A number on the data sets a model learned from says how well it remembers. Each cell's model
is also measured, frozen (:func:`~.evaluate.freeze`), at ``experiment.held_out.n_checkpoints``
learning times, on three kinds of data set (:data:`KINDS`): the training sets, new poses of
the training caregivers, and caregivers it never saw. The held-out sets come from the world's
held-out stream, which no training recording uses (``jointattention datasets make
--held-out``); for the shipped training sets the package ships them (:func:`shipped_held_out`),
for others each worker records them once (rendering) unless the configuration names files.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .._readers import shipped_path
from ..agent.protocol import freeze
from ..config import ConditionConfig, Config, WorldConfig, to_toml
from ..datasets import CaregiverDatasets, load
from ..errors import ConfigError
from .cells import datasets_of, run_cell
from .controls import blank_spread_deg, mirror_flip_share
from .dataset_cache import recorded_file
from .evaluate import _errors, data_sets_novelty, frozen_success, who_posed
from .probes import probe_sets

__all__ = ["KINDS", "MEASURES", "checkpoint_steps", "final_held_out", "held_out_datasets",
           "held_out_novelty", "held_out_sets", "measure_held_out", "run_cell_measured",
           "shipped_held_out"]

KINDS = ("training", "new poses", "unseen caregivers")
# what a cell keeps per kind (rows) and checkpoint (columns), with the checkpoints' times
MEASURES = ("held_out_success", "held_out_median_error_deg", "held_out_p90_error_deg",
            "held_out_share_over_10deg", "held_out_blank_spread_deg",
            "held_out_mirror_flip_share")
SHIPPED = {"new poses": "held_out_poses.npz", "unseen caregivers": "held_out_caregivers.npz"}


def checkpoint_steps(config: Config) -> np.ndarray:
    """The learning times at which a cell's model is measured (the last: the end)."""
    exp = config.experiment
    n = exp.held_out.n_checkpoints
    return np.unique(np.ceil(np.arange(1, n + 1) * exp.n_steps / n).astype(np.int64))


def shipped_held_out(kind: str) -> CaregiverDatasets:
    """The held-out sets of the shipped training sets, by kind (commands: docs/generalisation.md).

    ``new poses``: ``jointattention datasets make --n 250 --held-out --caregivers-of
    src/jointattention/data/caregiver_125.npz --seed 0``; ``unseen caregivers``:
    ``jointattention datasets make --n 400 --caregivers 16 --held-out --seed 0``.
    """
    return load(shipped_path(SHIPPED[kind]))


def held_out_datasets(world: WorldConfig, caregivers: int, poses: int, seed: int,
                      progress: Callable[[int], None] | None = None) -> CaregiverDatasets:
    """``caregivers`` unseen caregivers, ``poses`` data sets each, from the held-out stream.

    Recorded in ``world`` once per machine (:func:`~.recorded.recorded_file`).
    """
    return load(recorded_file(world, caregivers * poses, seed, caregivers=caregivers,
                              stream="held-out", progress=progress))


def _record(config: Config, kind: str, training: CaregiverDatasets) -> CaregiverDatasets:
    """Held-out sets of ``kind`` recorded from the held-out stream of the run's world."""
    from ..world.recording import caregivers_of  # the world: only when recording

    h = config.experiment.held_out
    try:
        if kind == "new poses":
            identities = caregivers_of(training, config.world)[: h.n_poses]
            return load(recorded_file(config.world, h.n_poses, h.seed, stream="held-out",
                                      identities=identities))
        return held_out_datasets(config.world, h.n_caregivers, h.poses_per_caregiver, h.seed)
    except ConfigError:
        raise
    except Exception as err:  # no OpenGL, a recording that names no caregivers, ...
        field = "poses" if kind == "new poses" else "caregivers"
        raise ConfigError(f"experiment.held_out.{field}: {kind} could not be recorded ({err}); "
                          f"expected a data-set file there, or experiment.held_out.n_trials "
                          "= 0") from None


_LOADED: dict[str, dict[str, CaregiverDatasets]] = {}  # by configuration: once per process


def _simulated(training: CaregiverDatasets, config: Config) -> bool:
    """Whether the training sets were recorded in this simulator (they say who posed them)."""
    return who_posed(training, config.world) is not None


def _held_out(config: Config) -> dict[str, CaregiverDatasets]:
    held_out, datasets = config.experiment.held_out, config.datasets
    training = datasets_of(config)
    sets = {"training": training}
    simulated = None  # asked only when needed: it builds no world, but imports it
    for kind, path in (("new poses", held_out.poses), ("unseen caregivers",
                                                       held_out.caregivers)):
        if path:
            sets[kind] = load(path)
        elif not datasets and not config.recording.caregivers:  # the shipped training sets
            sets[kind] = shipped_held_out(kind)
        else:
            simulated = _simulated(training, config) if simulated is None else simulated
            if not simulated:  # a robot's own recording: held-out sets only as files
                continue
            sets[kind] = _record(config, kind, training)
        if sets[kind].window_size_px != training.window_size_px:
            raise ConfigError(f"experiment.held_out: the {kind} sets' face windows are "
                              f"{sets[kind].window_size_px}; expected the training sets' "
                              f"{training.window_size_px}")
    return sets


def held_out_sets(config: Config) -> dict[str, CaregiverDatasets]:
    """The run's kinds of data set (:data:`KINDS`), by kind; loaded once per process.

    Training sets that a robot recorded (they name no simulated caregiver) get no recorded
    held-out sets: only those the configuration names as files.
    """
    key = to_toml(config)
    if key not in _LOADED:
        _LOADED[key] = _held_out(config)
    return _LOADED[key]


def held_out_novelty(config: Config) -> dict[str, np.ndarray]:
    """How new each caregiver of the run's held-out sets is to its training caregivers.

    {kind: each identity's novelty (:func:`~.evaluate.data_sets_novelty`)} for the kinds
    other than the training sets; an empty array for a kind whose sets, or whose training
    sets, do not say who posed them.
    """
    sets = held_out_sets(config)
    known = who_posed(sets["training"], config.world)
    return {kind: data_sets_novelty(ds, config.world, known, config.world)
            for kind, ds in sets.items() if kind != "training"}


def measure_held_out(agent, config: Config, n_objects: int) -> np.ndarray:
    """The :data:`MEASURES` of the frozen ``agent`` on each kind: (len(MEASURES), len(KINDS)).

    ``experiment.held_out.n_trials`` trials per kind, drawn from the run's seed (the same
    trials for every cell and checkpoint). The errors and the controls are measured on at most
    ``experiment.probe_datasets`` of a kind's data sets (:func:`~.probes.probe_sets`; for the
    training sets, those the probes measure). A model with no ``learning`` switch cannot be
    frozen: it is not measured (all NaN), since its trials would change what it learned.
    """
    h = config.experiment.held_out
    out = np.full((len(MEASURES), len(KINDS)), np.nan)
    if not hasattr(agent, "learning"):
        return out
    frozen = freeze(agent)
    sets = held_out_sets(config)
    for j, kind in enumerate(KINDS):
        if kind in sets:  # else not measured: NaN
            ds = sets[kind]
            out[0, j] = frozen_success(frozen, ds, config, n_objects, h.n_trials, config.seed)
            ds = probe_sets(ds, config.experiment.probe_datasets, config.seed)  # the errors'
            if not hasattr(frozen, "lm_commands"):
                out[1:4, j] = _errors(frozen, ds)
                continue
            commands = frozen.lm_commands(ds.views, ds.theta_face_rad)  # taken once, for both
            out[1:4, j] = _errors(frozen, ds, commands)
            out[4, j] = blank_spread_deg(frozen, ds)  # the controls (experiment/controls.py)
            out[5, j] = mirror_flip_share(frozen, ds, commands=commands)
    return out


def run_cell_measured(config: Config, condition: ConditionConfig, seed_index: int,
                      progress: Callable[[int], None] | None = None,
                      on_end: Callable | None = None) -> dict[str, np.ndarray]:
    """:func:`~.cells.run_cell` and the frozen model's held-out measures at its checkpoints.

    With ``experiment.held_out.n_trials`` > 0 the records also hold ``held_out_steps`` (the
    learning times of :func:`checkpoint_steps`; measured at the first trial end past each) and
    one array (kinds, checkpoints) per :data:`MEASURES`. ``on_end(agent)`` is called with the
    learned agent at the end of learning.
    """
    n_steps = config.experiment.n_steps
    at = checkpoint_steps(config) if config.experiment.held_out.n_trials else np.zeros(0, int)
    measures = np.full((len(MEASURES), len(KINDS), len(at)), np.nan)
    times = [int(t) for t in at]

    def checkpoint(t: int, agent) -> None:
        if t in times:
            measures[:, :, times.index(t)] = measure_held_out(agent, config, condition.n_objects)
        if t == n_steps and on_end is not None:
            on_end(agent)

    records = run_cell(config, condition, seed_index, progress, checkpoints=[*times, n_steps],
                       on_checkpoint=checkpoint)
    if not times:
        return records
    return {**records, "held_out_steps": at.astype(np.int64),
            **dict(zip(MEASURES, measures, strict=True))}


def final_held_out(records: dict[str, np.ndarray]) -> dict[str, dict[str, float]] | None:
    """{kind: {measure: value}} at a cell's last checkpoint (None if it was not measured).

    Measures are named without their ``held_out_`` prefix; one not measured is None.
    """
    if "held_out_steps" not in records:
        return None

    def value(x) -> float | None:
        return float(x) if np.isfinite(x) else None

    return {kind: {m.removeprefix("held_out_"): value(records[m][j, -1]) for m in MEASURES}
            for j, kind in enumerate(KINDS)}
