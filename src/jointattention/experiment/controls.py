"""Controls on held-out faces: what a model does with a face that carries no gaze, or a mirror.

A module that follows the caregiver's gaze must point one way for a blank face (no gaze to
read: a uniform grey window, the mean grey of the data sets) and must flip its horizontal
command for a mirrored face (the window mirrored left to right and the head angle's pan
negated: the mirrored caregiver looks to the other side). The shuffled-faces control (faces
paired with other trials' targets) is a condition of a run (``shuffle_faces``).
"""

from __future__ import annotations

import numpy as np

from ..datasets import CaregiverDatasets, views_of

__all__ = ["blank_spread_deg", "mirror_flip_share"]


def _directions(agent, faces: np.ndarray, thetas: np.ndarray) -> np.ndarray:
    out = agent.lm_commands(faces, thetas)
    return np.arctan2(out[:, 1], out[:, 0])


def blank_spread_deg(agent, ds: CaregiverDatasets) -> float:
    """Circular s.d. (deg) of the module's directions for a blank face at each set's head angle.

    A blank face (every pixel the data sets' mean grey) at the head angles of the data sets:
    near 0 if the module points one way for a face without gaze.
    """
    views = ds.views  # the face window, and the eye window if kept: both blank
    blank = np.full_like(views, int(round(float(views.mean()))))
    psi = _directions(agent, blank, ds.theta_face_rad)
    r = np.hypot(np.cos(psi).mean(), np.sin(psi).mean())
    r = min(max(r, 1e-12), 1.0)  # identical directions can round r above 1
    return float(np.rad2deg(np.sqrt(-2 * np.log(r))))


def mirror_flip_share(agent, ds: CaregiverDatasets, min_pan_deg: float = 10.0,
                      commands: np.ndarray | None = None) -> float:
    """The share of data sets whose horizontal command flips sign for the mirrored face.

    Among the data sets whose command to the target turns the head by more than
    ``min_pan_deg`` sideways (the side is clear); the mirrored face is the window flipped left
    to right at the head angle with its pan negated. ``commands``: the module's commands at
    every data set's face (N, 2), if already taken.
    """
    side = np.abs(np.rad2deg(ds.command_rad[:, 0])) > min_pan_deg
    faces, thetas = ds.views[side], ds.theta_face_rad[side]
    eyes = None if ds.eyes is None else ds.eyes[:, :, ::-1]
    mirrored = np.ascontiguousarray(views_of(ds.face[:, :, ::-1], eyes)[side])
    flip = thetas * [-1.0, 1.0]
    pan = (agent.lm_commands(faces, thetas) if commands is None else commands[side])[:, 0]
    pan_mirrored = agent.lm_commands(mirrored, flip)[:, 0]
    return float(np.mean(np.sign(pan) == -np.sign(pan_mirrored)))
