"""Runs of many trials: one cell is one condition x one seed; and the oracle's ceiling.

Every cell draws from its own streams of the run's seed: the same cell gives the same
records whatever the number of worker processes. Cells with the same seed index share the
sequence of data sets and distractor scenes (common random numbers across conditions).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from functools import partial
from pathlib import Path

import numpy as np

from .._checks import check_int, short_repr
from ..agent.attention import attended_object
from ..agent.protocol import Agent, Body
from ..config import ConditionConfig, Config, check_config, model_options
from ..datasets import CaregiverDatasets, default_datasets, load, shipped_file
from ..errors import ArgumentError
from ..rng import stream
from ..world.fast import FastScene
from ..world.kinematics import HeadKinematics
from .compiled.cell import compiled_cell, pack_world, unsupported
from .compiled.inputs import placed
from .dataset_cache import training_file
from .oracle import oracle_trials
from .probes import lm_errors_deg, probe_sets
from .trial import SceneTrial, StepObserver, TrialResult, records, run_trial

__all__ = ["body_of", "check_condition", "datasets_file", "datasets_of", "engine_of",
           "evaluator", "fast_world", "make_agent", "measure_ceiling", "oracle_wins",
           "random_scene", "run_cell", "trial_geometries", "trial_geometry"]

_CHUNK_STEPS = 10_000  # the compiled engine reports progress this often (learning steps)


def datasets_file(config: Config) -> Path:
    """The file of the run's training sets: ``config.datasets``, the recording, or the shipped.

    A ``[recording]`` is made on first use and kept (:mod:`.dataset_cache`).
    """
    if config.datasets:
        return Path(config.datasets)
    recorded = training_file(config)
    return recorded if recorded is not None else shipped_file()


def datasets_of(config: Config) -> CaregiverDatasets:
    """The run's caregiver data sets: ``config.datasets``, its recording, or the shipped ones."""
    if not config.datasets and not config.recording.caregivers:
        return default_datasets()
    return load(datasets_file(config))


def trial_geometry(ds: CaregiverDatasets, k: int, kin: HeadKinematics, distance_m: float):
    """Where data set ``k``'s target and face are.

    The target at its recorded position, or, for data sets recorded without it, 0.65 m along the
    recorded command.
    """
    theta_face = ds.theta_face_rad[k]
    face = kin.camera_position(theta_face) + distance_m * kin.gaze_direction(theta_face)
    if ds.target_m is not None:
        return ds.target_m[k], face
    theta = theta_face + ds.command_rad[k]
    return kin.camera_position(theta) + 0.65 * kin.gaze_direction(theta), face


def trial_geometries(ds: CaregiverDatasets, kin: HeadKinematics,
                     distance_m: float) -> tuple[np.ndarray, np.ndarray]:
    """:func:`trial_geometry` of every data set: targets (K, 3) and faces (K, 3)."""
    geometry = [trial_geometry(ds, k, kin, distance_m) for k in range(len(ds))]
    return (np.array([g[0] for g in geometry], dtype=float),
            np.array([g[1] for g in geometry], dtype=float))


def random_scene(config: Config, ds: CaregiverDatasets, kin: HeadKinematics, n_objects: int,
                 rng: np.random.Generator) -> tuple[int, FastScene, np.ndarray]:
    """A trial's data set index, its scene and where the caregiver's face is.

    The scene is the recorded target plus random distractors.
    """
    k = int(rng.integers(len(ds)))
    target_m, face_m = trial_geometry(ds, k, kin, config.world.caregiver.distance_m)
    return k, FastScene.sample(config.world, kin, target_m, face_m, n_objects, rng), face_m


def engine_of(config: Config, condition: ConditionConfig) -> str:
    """The engine that runs ``condition``'s cells: "compiled" or "python".

    ``experiment.engine = "auto"`` runs compiled every condition whose model the compiled
    engine runs (:func:`~.compiled.unsupported`), and the rest step by step.
    """
    exp = config.experiment
    if exp.engine != "auto":
        return exp.engine
    if exp.perception != "fast" or unsupported(model_options(config, condition)) is not None:
        return "python"
    return "compiled"


def body_of(kin: HeadKinematics, ds: CaregiverDatasets) -> Body:
    """What the robot knows of its body: its camera's image, its joints, its windows."""
    return Body(image_size_px=(kin.width_px, kin.height_px),
                joint_limits_rad=(kin.pan_limits_rad, kin.tilt_limits_rad),
                face_size_px=ds.window_size_px, eye_size_px=ds.eye_window_size_px)


def make_agent(config: Config, condition: ConditionConfig, seed_index: int,
               ds: CaregiverDatasets) -> Agent:
    """The untrained agent of a cell: the condition's model, its own stream of the seed."""
    kin = HeadKinematics.from_config(config.world)
    return model_options(config, condition).build(
        config.agent, body_of(kin, ds), stream(config.seed, "agent", seed_index))


def evaluator(config: Config) -> Callable:
    """The internal evaluator of the run's robot (Eq. 3 with its d_th)."""
    return partial(attended_object, d_th_px=config.agent.d_th_px(config.world.camera.width_px))


def check_condition(condition) -> ConditionConfig:
    """``condition`` if it is a :class:`ConditionConfig`, else one ArgumentError naming it."""
    if not isinstance(condition, ConditionConfig):
        raise ArgumentError(f"condition {short_repr(condition)}: expected a ConditionConfig "
                            "(one of config.experiment.conditions)")
    return condition


def run_cell(config: Config, condition: ConditionConfig, seed_index: int,
             progress: Callable[[int], None] | None = None, checkpoints: Sequence[int] = (),
             on_checkpoint: Callable[[int, Agent], None] | None = None,
             observer: StepObserver | None = None) -> dict[str, np.ndarray]:
    """Learn for ``experiment.n_steps`` steps; one record per trial (``trial.RECORD``).

    The cell also holds ``lm_error_deg``, one value per learning-time bin: the learning
    module's median angle error over the data sets' faces (at most
    ``experiment.probe_datasets`` of them: :func:`~.probes.probe_sets`) at the first trial
    end past the bin (:func:`~.probes.median_error_deg`; NaN for a model without one), and
    its horizontal and vertical parts, ``lm_pan_error_deg`` and ``lm_tilt_error_deg``
    (:func:`~.probes.axis_errors_deg`), and ``lm_bias``, how alike its directions are over
    the faces (:func:`~.probes.bias_of`); all four from one pass,
    :func:`~.probes.lm_errors_deg`.
    ``progress`` gets the learning time now and then; ``on_checkpoint(t, agent)`` is called
    at the first trial end at or past each learning time ``t`` of ``checkpoints``; ``observer``
    sees each step (see :func:`~jointattention.experiment.trial.run_trial`; the python engine
    only). ``experiment.engine`` chooses the compiled engine or the step-by-step loop
    (:func:`engine_of`); both give the same records.
    """
    check_config(config)
    check_condition(condition)
    check_int("seed_index", seed_index, 0, 2**31 - 1)
    ds = datasets_of(config)
    agent = make_agent(config, condition, seed_index, ds)
    rngs = stream(config.seed, "trials", seed_index), stream(config.seed, "shuffle", seed_index)
    pending = sorted(set(checkpoints)) if on_checkpoint is not None else []
    exp = config.experiment
    bin_ends = [int(t) for t in exp.bin_ends_steps()]
    errors = np.full(len(bin_ends), np.nan)
    axes = np.full((3, len(bin_ends)), np.nan)  # horizontal and vertical parts, bias
    measured = 0  # bins whose error is measured
    probed = probe_sets(ds, exp.probe_datasets, config.seed)

    def reached(t: int) -> None:
        nonlocal measured
        while pending and t >= pending[0]:
            on_checkpoint(pending.pop(0), agent)
        while measured < len(bin_ends) and t >= bin_ends[measured]:
            errors[measured], *axes[:, measured] = lm_errors_deg(agent, probed)
            measured += 1

    if engine_of(config, condition) == "compiled":
        if observer is not None:
            raise ValueError("an observer sees single steps: expected experiment.engine = "
                             "'python'")
        records = _run_compiled(config, condition, ds, agent, rngs, progress,
                                [*pending, *bin_ends], reached)
    else:
        records = _run_steps(config, condition, seed_index, ds, agent, rngs, progress, reached,
                             observer)
    return {**records, "lm_error_deg": errors, "lm_pan_error_deg": axes[0],
            "lm_tilt_error_deg": axes[1], "lm_bias": axes[2]}


def _run_compiled(config, condition, ds, agent, rngs, progress, stops,
                  reached) -> dict[str, np.ndarray]:
    """run_cell in the compiled engine, stopping at ``stops`` and every _CHUNK_STEPS."""
    kin = HeadKinematics.from_config(config.world)
    world = pack_world(config.world, ds,
                       *trial_geometries(ds, kin, config.world.caregiver.distance_m),
                       condition.n_objects, condition.shuffle_faces)
    n_steps = config.experiment.n_steps
    cell = compiled_cell(agent, world, *rngs, max_trials=n_steps)
    for stop in sorted({*range(_CHUNK_STEPS, n_steps, _CHUNK_STEPS), *stops, n_steps}):
        if stop > n_steps:
            break
        cell.run_until(stop)
        if progress is not None:
            progress(agent.learning_time_steps)
        reached(agent.learning_time_steps)
    return cell.records()


def _run_steps(config, condition, seed_index, ds, agent, rngs, progress, reached,
               observer) -> dict[str, np.ndarray]:
    """run_cell's step-by-step loop through the Agent and Scene seams (engine "python")."""
    kin = HeadKinematics.from_config(config.world)
    trials, shuffle = rngs
    evaluate = evaluator(config)
    results: list[TrialResult] = []
    n_steps = config.experiment.n_steps
    scenes = None
    if config.experiment.perception == "rendered":
        from ..world.rendered import RenderedScenes

        scenes = RenderedScenes(config.world, config.detector, condition.n_objects,
                                seed=config.seed, rng=stream(config.seed, "render", seed_index))
    try:
        while agent.learning_time_steps < n_steps and len(results) < n_steps:
            k, scene, face_m = random_scene(config, ds, kin, condition.n_objects, trials)
            if scenes is not None:
                scene = scenes.show(scene, face_m)
            face = ds.view(shuffle.integers(len(ds)) if condition.shuffle_faces else k)
            trial = SceneTrial(scene, ds.theta_face_rad[k], kinematics=kin,
                               max_steps=config.agent.max_steps, evaluate=evaluate)
            results.append(run_trial(trial, agent, face, observer))
            if progress is not None:
                progress(agent.learning_time_steps)
            reached(agent.learning_time_steps)
    finally:
        if scenes is not None:
            scenes.close()
    return records(results)


def measure_ceiling(config: Config, n_objects: int, n_trials: int | None = None,
                    reward: str = "external") -> float:
    """Success of the oracle gaze-line follower over ``n_trials`` trials in the same world.

    ``n_trials``: 1 to 10^7 (default: ``experiment.n_ceiling_trials``). ``reward``:
    ``"external"`` (default), the share of trials it ends on the target; ``"intrinsic"``, on
    any object (the evaluator fired), in the same trials.
    """
    check_config(config)
    check_int("n_objects", n_objects, 1, 20)
    if n_trials is not None:
        check_int("n_trials", n_trials, 1, 10**7)
    if reward not in ("external", "intrinsic"):
        raise ArgumentError(f"reward={short_repr(reward)}: expected 'external' or 'intrinsic'")
    n_trials = config.experiment.n_ceiling_trials if n_trials is None else n_trials
    return oracle_wins(datasets_of(config), config, n_objects, n_trials,
                       stream(config.seed, "ceiling", n_objects),
                       any_object=reward == "intrinsic") / n_trials


_PACKED: dict = {}  # fast_world's: {(id of the data sets, count, world): (them, the packing)}


def fast_world(config: Config, ds: CaregiverDatasets, n_objects: int):
    """``ds`` and the world as the compiled loops take them, for trials without shuffled faces.

    Packed once per process for each data sets object (a held-out set is measured at every
    checkpoint of every cell); the cache holds the data sets, so their id stays theirs, and
    the last 8 packings.
    """
    key = (id(ds), n_objects, config.world)
    if key not in _PACKED:
        if len(_PACKED) >= 8:
            del _PACKED[next(iter(_PACKED))]
        kin = HeadKinematics.from_config(config.world)
        _PACKED[key] = ds, pack_world(config.world, ds, *trial_geometries(
            ds, kin, config.world.caregiver.distance_m), n_objects, False)
    return _PACKED[key][1]


def oracle_wins(ds: CaregiverDatasets, config: Config, n_objects: int, n_trials: int,
                rng: np.random.Generator, any_object: bool = False) -> int:
    """How many of ``n_trials`` trials on ``ds`` the oracle gaze-line follower ends on the target.

    ``any_object``: on any object (the evaluator fired) instead.

    :class:`~.oracle.OracleAgent`'s trials (:func:`random_scene` from ``rng``), in one compiled
    loop (:func:`~.oracle.oracle_trials`).
    """
    world = fast_world(config, ds, n_objects)
    return placed(oracle_trials(world, ds.theta_face_rad + ds.command_rad, rng,
                                float(np.deg2rad(config.agent.lm_step_deg)),
                                float(config.agent.d_th_px(world.width_px)),
                                int(config.agent.max_steps), n_trials,
                                float(np.deg2rad(config.agent.line_capture_deg)),
                                float(config.agent.vf_gain_rad_per_px), bool(any_object)),
                  world)
