"""A saved model driving the rendered head through images alone, as a real robot would run it.

Each trial starts with the head at the caregiver: the image is rendered, the caregiver's face
found in it (:class:`~jointattention.deploy.follower.GazeFollower`), its window cut, and from
then on the learning module moves the head, step by step, while the OpenCV detector looks at
each rendered image and the internal evaluator (Eq. 3) ends the trial. The same model, on the
same trials, in the fast world (data-set face windows, projected objects) is the comparison;
between the two, the rendered trials given the experimenter's window (cut around the head's
projection in the same image) and the data set's window tell where the loss is: the finder's
window, the image, or the object detector and evaluator.

A model that reads the eyes too (``[world.eye_window]``) is shown, for its first look, the view
rendered through its fovea (``zoom`` times the camera's size), as a robot with a finer sensor
would take it: the follower finds the face in it shrunk and the eyes in it whole
(:class:`~jointattention.deploy.follower.GazeFollower`). The experimenter's window then holds
the eye window cut at the eyeballs' centres too, and the data set's window its kept eyes.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..agent.finders import DEFAULT_FACE
from ..agent.protocol import LM, Outcome
from ..config import WorldConfig
from ..datasets import CaregiverDatasets, views_of, window_mismatch
from ..deploy.follower import GazeFollower
from ..deploy.saved import LearnedModel
from ..errors import DatasetError
from ..experiment.cells import datasets_of, evaluator, random_scene
from ..experiment.probes import angle_deg
from ..experiment.trial import SceneTrial, run_trial
from ..rng import stream
from ..world.identity import Caregiver
from ..world.kinematics import HeadKinematics
from ..world.recording import (
    capture_face_window,
    caregivers_of,
    eye_box,
    eye_window_at,
    eye_window_kept,
)
from ..world.rendered import RenderedScenes

__all__ = ["TABLE_HEAD", "ClosedLoopResult", "FollowingAgent", "caregivers_shown",
           "check_windows", "closed_loop", "experimenters_view"]


def check_windows(ds: CaregiverDatasets, model: LearnedModel, where: str) -> None:
    """Refuse data sets whose face or eye windows are not the model's size, before any trial.

    ``where``: how the data sets are named in the error.
    """
    wrong = window_mismatch(ds, model.robot.face_size_px, model.robot.eye_size_px)
    if wrong is not None:
        raise DatasetError(f"{where}: {wrong} (its world's face_window and eye_window)")


def experimenters_view(world, image: np.ndarray, eyes: bool) -> np.ndarray:
    """The window cut around the head's projection in ``image``; with ``eyes``, then the eyes'.

    The eye window is cut at the eyeballs' centres (:func:`~jointattention.world.recording.
    eye_box`, which only the experimenter knows) and kept as the model's robot keeps it.
    """
    face = capture_face_window(world, image)
    if not eyes:
        return face
    kept = eye_window_kept(world.config.eye_window, eye_window_at(world, *eye_box(world)))
    return views_of(face, kept)


def caregivers_shown(ds: CaregiverDatasets, world: WorldConfig) -> list[Caregiver] | None:
    """Who poses each data set's trials (by ``ds.caregiver``); None: the world seed's own.

    Data sets that name neither caregivers nor the seed they were recorded from (a robot's
    recording) show the world seed's caregiver, as version 0.3 did; malformed ones raise
    :class:`~jointattention.errors.DatasetError` (:func:`~jointattention.world.recording.
    caregivers_of`).
    """
    if "caregivers" not in ds.meta and "seed" not in ds.meta:
        return None
    return caregivers_of(ds, world)


class FollowingAgent:
    """A learned model as an agent that only follows: the learning module moves the head.

    Each trial is the module's own (:meth:`~jointattention.deploy.saved.LearnedModel.lm_trial`):
    it reads the face once at the start, then steps as it did when it led in learning. It
    learns no more (``end_trial`` does nothing): what is measured is what was saved.
    """

    def __init__(self, model: LearnedModel):
        self.model, self.learning_time_steps = model, 0

    def begin_trial(self, face_window: np.ndarray, theta_rad: np.ndarray) -> None:
        """Read this trial's view (its face window; and eyes, for a model that reads them)."""
        self._trial = self.model.lm_trial(face_window, theta_rad)

    def act(self, detections, theta_rad: np.ndarray) -> tuple[np.ndarray, str]:
        """One step of the learning module."""
        self.learning_time_steps += 1
        return self._trial.step(theta_rad, detections), LM

    def end_trial(self, outcome: Outcome) -> None:
        """Nothing is learned."""


@dataclass(frozen=True)
class ClosedLoopResult:
    """Success of one model over the same trials, through images and in the fast world."""

    n_objects: int
    n_trials: int
    rendered_success: float
    rendered_box_face_success: float  # rendered, the window cut around the head's projection
    rendered_dataset_face_success: float  # rendered, but the data set's face window
    fast_success: float
    faces_found: float  # fraction of trials whose first image gave a face
    image_error_deg: float  # median angle of the first command to the target's, image window
    dataset_error_deg: float  # the same with the data set's window

    def row(self) -> str:
        """This result as a row of the Markdown table under :data:`TABLE_HEAD`."""
        return (f"| {self.n_objects} | {self.n_trials} | {self.faces_found:.3f} | "
                f"{self.rendered_success:.3f} | {self.rendered_box_face_success:.3f} | "
                f"{self.rendered_dataset_face_success:.3f} | {self.fast_success:.3f} | "
                f"{self.image_error_deg:.1f}°, {self.dataset_error_deg:.1f}° |")


# the closed loop's Markdown table: its header lines; ClosedLoopResult.row gives the rows
TABLE_HEAD = ("| objects | trials | faces found | images only | rendered, the head's box window "
              "| rendered, the data set's window | fast world | first command's error: image "
              "window, data set's window |", "|---|---|---|---|---|---|---|---|")


def closed_loop(model: LearnedModel, n_objects: int, n_trials: int, *, seed: int = 0,
                progress: Callable[[int], None] | None = None,
                datasets: CaregiverDatasets | None = None, face: str = DEFAULT_FACE
                ) -> ClosedLoopResult:
    """Run ``model`` for ``n_trials`` trials of ``n_objects`` objects, rendered and fast.

    The trials are drawn (by ``seed``) from ``datasets``: by default the model's own, else
    others recorded in its world (e.g. unseen caregivers, ``datasets make --held-out``). Each
    trial shows the caregiver who posed its data set (:func:`~jointattention.world.recording.
    caregivers_of`; data sets that name none, a robot's recording, show the world seed's
    caregiver). A trial whose first image shows no face the finder accepts is a failure.
    ``face``: the face finder (:data:`~jointattention.agent.finders.FACE_METHODS`).
    """
    config = model.config
    ds = datasets if datasets is not None else datasets_of(config)
    check_windows(ds, model, "datasets")
    people = caregivers_shown(ds, config.world)
    kin = HeadKinematics.from_config(config.world)
    evaluate = evaluator(config)
    follower, agent = GazeFollower(model, face), FollowingAgent(model)
    rng = stream(seed, "closed-loop", n_objects)
    scenes = RenderedScenes(config.world, config.detector, n_objects, seed=config.seed,
                            rng=stream(seed, "closed-loop-render", n_objects))
    reads_eyes = follower.frame_size_px is not None  # then its frames are its fovea's
    wins = {"rendered": 0, "rendered_box_face": 0, "rendered_dataset_face": 0, "fast": 0}
    found, errors = 0, {"image": [], "dataset": []}
    try:
        for i in range(n_trials):
            k, fast, face_m = random_scene(config, ds, kin, n_objects, rng)
            theta = ds.theta_face_rad[k]
            if people is not None:
                scenes.world.caregiver = people[0 if ds.caregiver is None else ds.caregiver[k]]
            rendered = scenes.show(fast, face_m)
            trial = SceneTrial(rendered, theta, kinematics=kin, max_steps=config.agent.max_steps,
                               evaluate=evaluate)  # its first look renders the start image
            image = (scenes.world.render_zoomed(config.world.eye_window.zoom) if reads_eyes
                     else rendered.last_image)  # the head is at theta: the start view
            look = follower.look(image, theta)
            box = experimenters_view(scenes.world, rendered.last_image, reads_eyes)
            view = ds.view(k)
            errors["dataset"].append(angle_deg(model.lm_command(view, theta), ds.command_rad[k]))
            if look is not None:
                found += 1
                errors["image"].append(angle_deg(look.command_rad, ds.command_rad[k]))
                wins["rendered"] += run_trial(trial, agent, look.view).success
            for name, scene, window in (
                    ("rendered_box_face", scenes.show(fast, face_m), box),
                    ("rendered_dataset_face", scenes.show(fast, face_m), view),
                    ("fast", fast, view)):
                trial = SceneTrial(scene, theta, kinematics=kin,
                                   max_steps=config.agent.max_steps, evaluate=evaluate)
                wins[name] += run_trial(trial, agent, window).success
            if progress is not None:
                progress(i + 1)
    finally:
        scenes.close()
    return ClosedLoopResult(n_objects, n_trials, **{f"{k}_success": v / n_trials
                                                    for k, v in wins.items()},
                            faces_found=found / n_trials,
                            image_error_deg=float(np.median(errors["image"] or [np.nan])),
                            dataset_error_deg=float(np.median(errors["dataset"])))

