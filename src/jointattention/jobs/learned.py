"""What the learning module learned (the paper's Fig. 6 and Fig. 7) and how well.

:func:`snapshots` learns one cell in the fast world and keeps copies of the agent at checkpoints;
:func:`grid_faces` renders the caregiver's face window for a grid of gaze directions;
:func:`record_trial` renders one trial step by step. The angle errors are
:mod:`jointattention.experiment.probes`'.
The figures are drawn by :mod:`jointattention.figures.learned`; :func:`write_gaze_figures`
(``jointattention gaze``) trains, measures, draws and writes them.
"""

from __future__ import annotations

import copy
import dataclasses
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._files import save_json
from ..config import Config, condition_named
from ..datasets import CaregiverDatasets
from ..errors import JointAttentionError
from ..experiment import probes
from ..experiment.cells import datasets_of, evaluator, make_agent, random_scene, run_cell
from ..experiment.trial import SceneTrial, Trial, TrialResult, run_trial
from ..figures.learned import PAN_DEG, TILT_DEG, error_figure, fig6, fig7
from ..models.bootstrap import BootstrapAgent
from ..rng import stream
from ..world.kinematics import HeadKinematics, direction
from ..world.recording import capture_face_window, make_datasets
from ..world.rendered import RenderedScene, RenderedScenes
from ..world.scene import with_target
from ..world.simulator import World

__all__ = ["Frame", "grid_faces", "held_out_poses", "record_trial", "snapshots", "train",
           "write_gaze_figures"]


def snapshots(config: Config, condition_name: str, seed_index: int, checkpoints,
              progress: Callable[[int], None] | None = None) -> dict[int, BootstrapAgent]:
    """Learn the cell, keeping copies of the agent at checkpoints.

    A copy at the first trial end past each checkpoint (in learning steps) and at the end (key
    ``n_steps``); key 0 is the untrained agent, with the face statistics of the data sets.
    """
    condition = condition_named(config, condition_name)
    wanted = sorted(t for t in set(checkpoints) | {config.experiment.n_steps} if t > 0)
    ds = datasets_of(config)
    untrained = make_agent(config, condition, seed_index, ds)
    untrained.faces.partial_fit(ds.views.reshape(len(ds), -1))  # it sees the faces, learns none
    kept: dict[int, BootstrapAgent] = {0: untrained}

    def keep(t: int, agent: BootstrapAgent) -> None:
        kept[t] = copy.deepcopy(agent)

    run_cell(config, condition, seed_index, progress=progress, checkpoints=wanted,
             on_checkpoint=keep)
    for t in wanted:  # the run ended before them (trial limit)
        kept.setdefault(t, kept[max(kept)])
    return dict(sorted(kept.items()))


def train(config: Config, condition_name: str, seed_index: int, checkpoints,
          progress: Callable[[int], None] | None = None) -> dict[int, BootstrapAgent]:
    """Deprecated (goes in version 0.5): :func:`snapshots`.

    ``jointattention.train`` is the one ``train``; it returns a learned model.
    """
    warnings.warn("jointattention.jobs.learned.train is deprecated and goes in version 0.5; "
                  "expected snapshots(...)", DeprecationWarning, stacklevel=2)
    return snapshots(config, condition_name, seed_index, checkpoints, progress)


def held_out_poses(config: Config, ds: CaregiverDatasets, n: int) -> CaregiverDatasets:
    """``n`` more data sets of the same caregiver.

    The recording continued past ``ds`` (the shipped sets record world seed ``ds.meta['seed']``), so
    no pose is among ``ds``.
    """
    seed = int(ds.meta.get("seed", config.seed))
    more = make_datasets(config.world, len(ds) + n, seed)
    if not np.array_equal(more.face[:len(ds)], ds.face):
        raise JointAttentionError("the data sets were not recorded from this world and seed; "
                                  "expected the shipped data sets or ones made by "
                                  "`jointattention datasets make` with this configuration")
    return more.subset(slice(len(ds), None))


def grid_faces(config: Config, seed: int, pan_deg, tilt_deg, distance_m: float = 0.65):
    """Face windows, head angles and commands for a grid of gaze directions.

    Face windows (len(tilt), len(pan), h, w), head angles at the face and commands to the target,
    for a caregiver at its mean place looking at targets ``distance_m`` from the robot in each
    direction (pan, tilt) of the grid.
    """
    c = config.world.caregiver
    faces, thetas, commands = [], [], []
    with World(config.world, seed=seed) as world:
        kin = world.kinematics
        base = dataclasses.replace(world.state,
                                   head_pos_m=np.array([0.0, c.distance_m, c.height_m]))
        for tilt in tilt_deg:
            for pan in pan_deg:
                target = distance_m * direction(np.deg2rad(pan), np.deg2rad(tilt))
                shown = with_target(base, config.world, target)
                # the objects out of the face window's way: behind the robot
                away = np.tile([0.0, -3.0, 0.0], (shown.n_objects, 1))
                world.set_scene(dataclasses.replace(shown, object_pos_m=away))
                theta = world.face_angle_rad
                world.set_head_angle(theta)
                faces.append(capture_face_window(world))
                thetas.append(theta)
                commands.append(kin.centring_angles(target) - theta)
    shape = (len(tilt_deg), len(pan_deg))
    return (np.array(faces).reshape(*shape, *faces[0].shape),
            np.array(thetas).reshape(*shape, 2), np.array(commands).reshape(*shape, 2))


@dataclass(frozen=True)
class Frame:
    """One step of a recorded trial.

    The robot's image, its head angle, the detections' centres, the target's projected centre
    (experimenter's), and the module that moved next.
    """

    image: np.ndarray
    theta_rad: np.ndarray
    detections_px: np.ndarray
    target_px: np.ndarray
    module: str


class _Recorder:
    """Keeps a frame at each look of a rendered trial (a step observer)."""

    def __init__(self, scene: RenderedScene, kin: HeadKinematics):
        self.scene, self.kin, self.frames = scene, kin, []

    def __call__(self, trial: Trial, module: str | None) -> None:
        target = self.scene.world.state.target_pos_m
        uv = self.kin.project(target, trial.theta_rad)[0][0]
        self.frames.append(Frame(self.scene.last_image, np.asarray(trial.theta_rad),
                                 trial.detections.centre_px, uv, module or ""))


def record_trial(config: Config, agent: BootstrapAgent, n_objects: int, seed: int = 0,
                 min_lm_steps: int = 3, max_tries: int = 300) -> tuple[list[Frame], TrialResult]:
    """Render trials with a copy of ``agent`` until one achieves joint attention.

    The trial must have at least ``min_lm_steps`` steps of the learning module; returns its frames
    and result.
    """
    ds = datasets_of(config)
    kin = HeadKinematics.from_config(config.world)
    rng = stream(seed, "figure-trials")
    scenes = RenderedScenes(config.world, config.detector, n_objects, seed=config.seed,
                            rng=stream(config.seed, "render", seed))
    try:
        for _ in range(max_tries):
            k, fast, face_m = random_scene(config, ds, kin, n_objects, rng)
            scene = scenes.show(fast, face_m)
            recorder = _Recorder(scene, kin)
            trial = SceneTrial(scene, ds.theta_face_rad[k], kinematics=kin,
                               max_steps=config.agent.max_steps, evaluate=evaluator(config))
            r = run_trial(trial, copy.deepcopy(agent), ds.view(k), recorder)
            if r.success and r.n_lm_steps >= min_lm_steps:
                return recorder.frames, r
    finally:
        scenes.close()
    raise JointAttentionError(f"no trial of {max_tries} achieved joint attention with "
                              f"{min_lm_steps} learning-module steps; expected a trained agent")


def write_gaze_figures(config: Config, condition: str, seed_index: int, out: Path,
                       n_held_out: int = 200, n_checkpoints: int = 6,
                       progress: Callable[[int], None] | None = None) -> dict:
    """Train one cell, then write fig6.png, lm_error.png, fig7.png, fig7.gif and gaze.json."""
    out = Path(out)
    n_steps = config.experiment.n_steps
    checkpoints = np.linspace(0, n_steps, n_checkpoints + 1).astype(int)
    agents = snapshots(config, condition, seed_index, checkpoints, progress)
    ds = datasets_of(config)
    held = held_out_poses(config, ds, n_held_out)
    curve = {t: (float(np.median(probes.angle_errors(a, ds))),
                 float(np.median(probes.angle_errors(a, held)))) for t, a in agents.items()}
    trained = agents[max(agents)]
    faces, thetas, commands = grid_faces(config, int(ds.meta.get("seed", 0)), PAN_DEG,
                                              TILT_DEG)
    numbers = fig6(trained, faces, thetas, commands, ds.command_rad, out / "fig6.png")
    error_figure(curve, out / "lm_error.png")
    cond = condition_named(config, condition)
    frames, result = record_trial(config, trained, cond.n_objects, seed=config.seed)
    d_th_px = config.agent.d_th_px(config.world.camera.width_px)
    fig7(frames, d_th_px, out / "fig7.png", out / "fig7.gif")
    numbers.update({
        "condition": condition, "seed_index": seed_index, "n_steps": n_steps,
        "median_error_deg": {str(t): {"data_sets": a, "held_out": b}
                             for t, (a, b) in curve.items()},
        "fig7_trial": {"steps": result.n_steps, "lm_steps": result.n_lm_steps},
    })
    save_json(numbers, out / "gaze.json")
    return numbers
