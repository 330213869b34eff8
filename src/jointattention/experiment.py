"""Runs of many trials (one cell = one condition x one seed), and many cells in parallel.

Every cell draws from its own streams of the run's seed: the same cell gives the same
records whatever the number of worker processes. Cells with the same seed index share the
sequence of data sets and distractor scenes (common random numbers across conditions).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np

from . import io
from .agent.bootstrap import BootstrapAgent
from .backends import CellJob, check_backend, run_jobs
from .config import ConditionConfig, Config, agent_config, with_n_objects
from .datasets import CaregiverDatasets, default_datasets, load
from .errors import ConfigError
from .oracle import OracleAgent
from .rng import stream
from .trial import run_trial
from .world.fast import FastScene
from .world.kinematics import HeadKinematics

__all__ = ["Renderer", "datasets_of", "make_agent", "measure_ceiling", "random_scene",
           "run_cell", "run_experiment"]


def datasets_of(config: Config) -> CaregiverDatasets:
    return load(config.datasets) if config.datasets else default_datasets()


def _trial_geometry(ds: CaregiverDatasets, k: int, kin: HeadKinematics, distance_m: float):
    """Where data set ``k``'s target and face are (the target at its recorded position, or,
    for data sets recorded without it, 0.65 m along the recorded command)."""
    theta_face = ds.theta_face_rad[k]
    face = kin.camera_position(theta_face) + distance_m * kin.gaze_direction(theta_face)
    if ds.target_m is not None:
        return ds.target_m[k], face
    theta = theta_face + ds.command_rad[k]
    return kin.camera_position(theta) + 0.65 * kin.gaze_direction(theta), face


def random_scene(config: Config, ds: CaregiverDatasets, kin: HeadKinematics, n_objects: int,
                  rng: np.random.Generator) -> tuple[int, FastScene, np.ndarray]:
    """A trial's data set index, its scene (the recorded target plus random distractors) and
    where the caregiver's face is."""
    k = int(rng.integers(len(ds)))
    target_m, face_m = _trial_geometry(ds, k, kin, config.world.caregiver.distance_m)
    return k, FastScene.sample(config.world, kin, target_m, face_m, n_objects, rng), face_m


def make_agent(config: Config, condition: ConditionConfig, seed_index: int,
               ds: CaregiverDatasets) -> BootstrapAgent:
    """The untrained agent of a cell (its own stream of the run's seed)."""
    kin = HeadKinematics.from_config(config.world)
    return BootstrapAgent(
        agent_config(config, condition), image_size_px=(kin.width_px, kin.height_px),
        joint_limits_rad=(kin.pan_limits_rad, kin.tilt_limits_rad),
        face_size_px=ds.window_size_px, rng=stream(config.seed, "agent", seed_index))


class Renderer:
    """The rendered mode: shows each trial's scene in MuJoCo for the OpenCV detector. Its own
    stream draws colours and light, so rendered and fast cells share their trials."""

    def __init__(self, config: Config, n_objects: int, seed_index: int):
        from .agent.vision import ImageDetector
        from .world.simulator import World

        self.world = World(with_n_objects(config, n_objects).world, seed=config.seed)
        self.detector = ImageDetector(config.detector, self.world.kinematics.focal_px)
        self.rng = stream(config.seed, "render", seed_index)

    def __call__(self, scene: FastScene, face_m):
        from .world.rendered import RenderedScene

        return RenderedScene(self.world, scene, face_m, self.detector, self.rng)

    def close(self) -> None:
        """Free the world's renderer."""
        self.world.close()


def run_cell(config: Config, condition: ConditionConfig, seed_index: int,
             progress: Callable[[int], None] | None = None,
             on_trial: Callable[[BootstrapAgent], None] | None = None) -> dict[str, np.ndarray]:
    """Learn for ``experiment.n_steps`` steps; one record per trial (see io.TRIAL_COLUMNS).

    ``progress`` gets the learning time after each trial, ``on_trial`` the agent."""
    ds = datasets_of(config)
    kin = HeadKinematics.from_config(config.world)
    agent = make_agent(config, condition, seed_index, ds)
    trials = stream(config.seed, "trials", seed_index)
    shuffle = stream(config.seed, "shuffle", seed_index)
    rows = []
    n_steps = config.experiment.n_steps
    render = (Renderer(config, condition.n_objects, seed_index)
              if config.experiment.perception == "rendered" else None)
    try:
        while agent.learning_time_steps < n_steps and len(rows) < n_steps:
            k, scene, face_m = random_scene(config, ds, kin, condition.n_objects, trials)
            if render is not None:
                scene = render(scene, face_m)
            face = ds.face[shuffle.integers(len(ds))] if condition.shuffle_faces else ds.face[k]
            t0 = agent.learning_time_steps
            r = run_trial(scene, agent, face, ds.theta_face_rad[k], agent.config.max_steps, kin)
            rows.append((t0, r.n_steps, r.n_lm_steps, r.attended, r.target, r.end, r.success,
                         r.fired))
            if progress is not None:
                progress(agent.learning_time_steps)
            if on_trial is not None:
                on_trial(agent)
    finally:
        if render is not None:
            render.close()
    cols = list(zip(*rows, strict=True))
    dtypes = (np.int64, np.int32, np.int32, np.int16, np.int16, np.int8, bool, bool)
    return {name: np.array(c, dtype=t)
            for name, c, t in zip(io.TRIAL_COLUMNS, cols, dtypes, strict=True)}


def measure_ceiling(config: Config, n_objects: int, n_trials: int | None = None) -> float:
    """Success of the oracle gaze-line follower over ``n_trials`` trials in the same world."""
    ds = datasets_of(config)
    kin = HeadKinematics.from_config(config.world)
    rng = stream(config.seed, "ceiling", n_objects)
    n_trials = config.experiment.n_ceiling_trials if n_trials is None else n_trials
    d_th = config.agent.d_th_px(kin.width_px)
    step = np.deg2rad(config.agent.lm_step_deg)
    wins = 0
    for _ in range(n_trials):
        k, scene, _ = random_scene(config, ds, kin, n_objects, rng)
        oracle = OracleAgent(ds.theta_face_rad[k] + ds.command_rad[k], step, d_th)
        r = run_trial(scene, oracle, ds.face[k], ds.theta_face_rad[k],
                      config.agent.max_steps, kin)
        wins += r.success
    return wins / n_trials


def run_experiment(config: Config, out: Path, workers: int = 1,
                   progress: Callable[[str], None] | None = None, *, backend: str = "local",
                   address: str | None = None):
    """Run every condition x seed into ``out``; cells already there are kept, not re-run.

    Returns {(condition, seed): records}. Each cell is saved as it finishes, so an
    interrupted run loses only the cells in progress. ``backend`` and ``address``: see
    :func:`jointattention.backends.run_jobs`.
    """
    check_backend(backend, address)
    out = Path(out)
    io.prepare_run_dir(out, config)
    exp = config.experiment
    names = [c.name for c in exp.conditions]
    if len(set(names)) != len(names):
        raise ConfigError("experiment.conditions: expected distinct names")
    cells = [(c, i) for c in exp.conditions for i in range(exp.n_seeds)]
    run_jobs([CellJob(config, c, i, io.cell_path(out, c.name, i)) for c, i in cells],
             workers=workers, backend=backend, address=address, progress=progress)
    return {(c.name, i): io.load_cell(io.cell_path(out, c.name, i)) for c, i in cells}
