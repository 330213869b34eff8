"""Gaze following on camera images: a saved model in a robot's control loop.

    >>> from jointattention import GazeFollower
    >>> follower = GazeFollower.load("model.npz")          # doctest: +SKIP
    >>> while True:                                          # doctest: +SKIP
    ...     frame, theta = camera.read_rgb(), head.angle_rad()
    ...     command = follower.command(frame, theta)         # (dpan, dtilt) rad, or None
    ...     if command is not None:
    ...         head.move_by(command)

Each frame: the caregiver's face is found (by default BlazeFace, the shipped neural face
detector; or template matching with the mean face the model learned from, or OpenCV's Haar
cascade), its window is cut by
:func:`~jointattention.agent.faces.window_of` (the function imported recordings are
made with), and the learning module gives one step toward where the caregiver looks.

A model that reads the eyes too (a world with ``[world.eye_window]``) takes frames from the
finer sensor its eye window was seen through (``zoom`` times the camera's size, e.g. 1280 x 960
for a 320 x 240 camera at 4): the face is found and its window cut in the frame shrunk to
the camera's size, and the eye window is cut from the whole frame where BlazeFace, looking
twice, puts the eyes (:mod:`~jointattention.agent.eye_windows`), then kept as the model's
robot keeps it (its socket patches, :mod:`~jointattention.agent.eye_sockets`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from .._arrays import angles
from ..agent.blazeface import BlazeFace
from ..agent.eye_sockets import eye_patches
from ..agent.eye_windows import eye_landmarks, eye_window_of
from ..agent.faces import Face, window_of
from ..agent.finders import DEFAULT_FACE, FACE_METHODS, check_finder, finder_for
from ..datasets import views_of
from ..errors import ArgumentError, ConfigError
from .saved import LearnedModel, LMTrial, Robot, load_model

__all__ = ["EYE_MIN_SCORE", "FACE_METHODS", "GazeFollower", "Look"]

EYE_MIN_SCORE = 0.4  # BlazeFace's least face probability when it places the eyes, by default


@dataclass(frozen=True)
class Look:
    """What the follower made of one frame.

    Attributes:
        face: the caregiver's face found in the frame, in its pixels.
        window: the face window cut around it, (H, W) uint8, as the model's inputs.
        command_rad: the learning module's (dpan, dtilt), one step long.
        eyes: what the model read of the eyes (its eye window, or the socket patches kept
            of it), (h, w) uint8; None for a model of the face window alone.
    """

    face: Face
    window: np.ndarray
    command_rad: np.ndarray
    eyes: np.ndarray | None = None

    @property
    def view(self) -> np.ndarray:
        """What the model read, as its ``lm_command`` takes it: the window, then the eyes flat."""
        return views_of(self.window, self.eyes)


class GazeFollower:
    """A learned model applied to RGB frames.

    Args:
        model: the learned model (:func:`~jointattention.deploy.saved.load_model`).
        face: ``"blazeface"`` (the shipped neural face detector, calibrated to cut the
            windows the data sets cut: docs/results/faces/detectors.md), ``"template"`` (the
            mean face window the model learned from) or ``"haar"`` (OpenCV's frontal-face cascade).
        min_score: least score of a face (None: the finder's own; BlazeFace's probability
            from 0 to 1, the template's normalised correlation from -1 to 1); a run-time
            choice, not part of what was learned. For a model that reads the eyes it also
            holds for BlazeFace's looks that place them (None: :data:`EYE_MIN_SCORE`).
        refine: BlazeFace's pixel refinements of where the window is cut, learned on the
            simulated heads; False for photographs of people (the landmarks alone).
    """

    def __init__(self, model: LearnedModel, face: str = DEFAULT_FACE,
                 min_score: float | None = None, *, refine: bool = True):
        check_finder(face, min_score)
        self.eye_window = model.config.world.eye_window if model.robot.eye_size_px else None
        if self.eye_window is not None and face != "blazeface":
            raise ConfigError(f"face = {face!r}: the model reads the eyes, which only "
                              "BlazeFace's landmarks place; expected face = 'blazeface'")
        self.eye_net = (BlazeFace(EYE_MIN_SCORE if min_score is None else min_score)
                        if self.eye_window is not None else None)
        self.model, self.face = model, face
        self._trial: LMTrial | None = None
        self.finder = finder_for(face, model.face_template() if face == "template" else None,
                                 min_score, refine=refine)

    @classmethod
    def load(cls, path: str | Path, *, face: str = DEFAULT_FACE, robot: Robot | None = None,
             min_score: float | None = None, refine: bool = True) -> GazeFollower:
        """A follower of the model saved at ``path`` (refused if learned on another ``robot``)."""
        return cls(load_model(path, robot=robot), face, min_score, refine=refine)

    def find(self, frame_rgb: np.ndarray) -> Face | None:
        """The caregiver's face in an RGB uint8 frame (H, W, 3): the best match, or None."""
        frame = np.asarray(frame_rgb)
        if frame.dtype != np.uint8 or frame.ndim != 3 or frame.shape[2] != 3 or min(
                frame.shape[:2]) < 8:
            raise ArgumentError(f"frame of {frame.dtype} and shape {frame.shape}: expected an "
                                "RGB uint8 image (H, W, 3), at least 8 x 8")
        faces = self.finder.find(frame)
        return faces[0] if faces else None

    @property
    def frame_size_px(self) -> tuple[int, int] | None:
        """The (width, height) of the frames an eye model takes: its fovea's; None: any size."""
        if self.eye_window is None:
            return None
        width, height = self.model.robot.image_size_px
        return (round(self.eye_window.zoom * width), round(self.eye_window.zoom * height))

    def look(self, frame_rgb: np.ndarray, theta_rad) -> Look | None:
        """The face, its window and the command for a frame seen at head angle ``theta_rad``."""
        theta = self.check_angle(theta_rad)
        if self.eye_window is None:
            face = self.find(frame_rgb)
            if face is None:
                return None
            window = window_of(frame_rgb, face, self.model.robot.face_size_px)
            return Look(face, window, self.model.lm_command(window, theta))
        return self._look_with_eyes(frame_rgb, theta)

    def _look_with_eyes(self, frame_rgb: np.ndarray, theta: np.ndarray) -> Look | None:
        """:meth:`look` for a model that reads the eyes: the frame is its fovea's."""
        import cv2

        frame = np.asarray(frame_rgb)
        expected = self.frame_size_px
        if (frame.dtype != np.uint8 or frame.ndim != 3 or frame.shape[2] != 3
                or (frame.shape[1], frame.shape[0]) != expected):
            raise ArgumentError(
                f"frame of {frame.dtype} and shape {frame.shape}: the model reads the eyes "
                f"through a fovea {self.eye_window.zoom:g} times its camera's size; expected "
                f"RGB uint8 frames {expected[0]} wide and {expected[1]} high")
        camera = cv2.resize(frame, self.model.robot.image_size_px, interpolation=cv2.INTER_AREA)
        face = self.find(camera)
        marks = eye_landmarks(self.eye_net, frame) if face is not None else None
        if marks is None:
            return None
        window = window_of(camera, face, self.model.robot.face_size_px)
        ew = self.eye_window
        eyes = eye_window_of(cv2.cvtColor(frame, cv2.COLOR_RGB2GRAY), *marks,
                             (ew.width_px, ew.height_px), ew.span)
        if ew.socket_patch_px:
            eyes = eye_patches(eyes, ew.span, ew.socket_patch_px, ew.socket_finder)
        command = self.model.lm_command(views_of(window, eyes), theta)
        return Look(_in_frame(face, frame.shape[1] / camera.shape[1]), window, command, eyes)

    def begin(self, frame_rgb: np.ndarray, theta_rad) -> Look | None:
        """A trial's look at the face, the head at it: the face, its window and the first step.

        :meth:`step` then moves the head on as the model's learning module did when it led in
        learning (:meth:`~jointattention.deploy.saved.LearnedModel.lm_trial`): once at the
        face, then step by step, is how the population code and the memory follow a gaze.
        None: no face, and no trial.
        """
        look = self.look(frame_rgb, theta_rad)
        self._trial = None if look is None else self.model.lm_trial(look.view, theta_rad)
        return look

    def step(self, theta_rad, detections=None) -> np.ndarray:
        """(dpan, dtilt) in radians: the trial's next step, the head now at ``theta_rad``.

        ``detections``: the robot's detector's report now, for a model whose module looks
        (the memory's); the others need none.
        """
        if self._trial is None:
            raise ArgumentError("step: no trial to step in; expected begin(frame, theta) first, "
                                "with the head at the caregiver and her face found")
        return self._trial.step(self.check_angle(theta_rad), detections)

    def command(self, frame_rgb: np.ndarray, theta_rad) -> np.ndarray | None:
        """(dpan, dtilt) in radians, a first step toward where she looks; None: no face.

        The first step of a trial from this frame: :meth:`begin` and :meth:`step` run the rest.
        """
        look = self.look(frame_rgb, theta_rad)
        return None if look is None else look.command_rad

    def check_angle(self, theta_rad) -> np.ndarray:
        """The head angle as an array, or one ArgumentError line if it is not one of the robot's."""
        theta = angles("theta_rad", theta_rad)
        robot = self.model.robot
        for value, (lo, hi), name in ((theta[0], robot.pan_limits_deg, "pan"),
                                      (theta[1], robot.tilt_limits_deg, "tilt")):
            if not np.deg2rad(lo) - 1e-9 <= value <= np.deg2rad(hi) + 1e-9:
                raise ArgumentError(f"theta_rad: {name} {np.rad2deg(value):.1f} deg is outside "
                                    f"the model's robot's joint range [{lo}, {hi}] deg")
        return theta


def _in_frame(face: Face, zoom: float) -> Face:
    """``face``, found in the frame shrunk ``zoom`` times, in the frame's own pixels."""
    marks = None if face.landmarks_px is None else (face.landmarks_px + 0.5) * zoom - 0.5
    return replace(face, centre_px=(np.asarray(face.centre_px) + 0.5) * zoom - 0.5,
                   height_px=face.height_px * zoom, landmarks_px=marks)
