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
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._arrays import angles
from ..agent.faces import Face, window_of
from ..agent.finders import DEFAULT_FACE, FACE_METHODS, check_finder, finder_for
from ..errors import ArgumentError, ConfigError
from .saved import LearnedModel, Robot, load_model

__all__ = ["FACE_METHODS", "GazeFollower", "Look"]


@dataclass(frozen=True)
class Look:
    """What the follower made of one frame.

    Attributes:
        face: the caregiver's face found in the frame.
        window: the face window cut around it, (H, W) uint8, as the model's inputs.
        command_rad: the learning module's (dpan, dtilt), one step long.
    """

    face: Face
    window: np.ndarray
    command_rad: np.ndarray


class GazeFollower:
    """A learned model applied to RGB frames.

    Args:
        model: the learned model (:func:`~jointattention.deploy.saved.load_model`).
        face: ``"blazeface"`` (the shipped neural face detector, calibrated to cut the
            windows the data sets cut: docs/results/faces/detectors.md), ``"template"`` (the
            mean face window the model learned from) or ``"haar"`` (OpenCV's frontal-face cascade).
        min_score: least score of a face (None: the finder's own; BlazeFace's probability
            from 0 to 1, the template's normalised correlation from -1 to 1); a run-time
            choice, not part of what was learned.
        refine: BlazeFace's pixel refinements of where the window is cut, learned on the
            simulated heads; False for photographs of people (the landmarks alone).
    """

    def __init__(self, model: LearnedModel, face: str = DEFAULT_FACE,
                 min_score: float | None = None, *, refine: bool = True):
        check_finder(face, min_score)
        if model.robot.eye_size_px is not None:
            raise ConfigError("the model reads an eye window, which the follower cannot "
                              "place in a camera image precisely enough yet (docs/results/people/"
                              "eye_placement.md); expected a "
                              "model of a world without [world.eye_window]")
        self.model, self.face = model, face
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

    def look(self, frame_rgb: np.ndarray, theta_rad) -> Look | None:
        """The face, its window and the command for a frame seen at head angle ``theta_rad``."""
        theta = self.check_angle(theta_rad)
        face = self.find(frame_rgb)
        if face is None:
            return None
        window = window_of(frame_rgb, face, self.model.robot.face_size_px)
        return Look(face, window, self.model.lm_command(window, theta))

    def command(self, frame_rgb: np.ndarray, theta_rad) -> np.ndarray | None:
        """(dpan, dtilt) in radians, one step toward where the caregiver looks; None: no face."""
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
