"""What an episode's step shows the agent: observations and ``info`` of fixed shape.

Every array has the same shape at every step of every episode, whatever the number of objects
in view, so that vector environments can stack them.
"""

from __future__ import annotations

import functools

import numpy as np
from gymnasium import spaces

from .._jit import jit
from ..agent.detections import Detections
from ..experiment.trial import SceneTrial

__all__ = ["DETECTION_COLUMNS", "DETECTION_INFO", "DETECTION_MASKS", "MAX_DETECTIONS",
           "OBS_MODES", "STEP_INFO", "STEP_MASKS", "detection_rows", "detections_of", "info_dict",
           "info_of", "observation_space", "scaled"]

OBS_MODES = ("image", "face", "detections")
MAX_DETECTIONS = 20  # a scene has at most 20 objects (n_objects)
# The columns of the "detections" observation: a row per object in view, zero rows after them.
DETECTION_COLUMNS = ("present", "centre_x_px", "centre_y_px", "colour_area_px", "edge", "motion")


def observation_space(mode: str, image_hw: tuple[int, int], face_hw: tuple[int, int],
                      joint_limits_rad: np.ndarray, scaled_obs: bool = False) -> spaces.Dict:
    """The observation space of ``mode`` (see :class:`~.joint_attention.JointAttentionEnv`)."""
    lo, hi = joint_limits_rad[:, 0], joint_limits_rad[:, 1]
    if scaled_obs:
        lo, hi = -np.ones(2), np.ones(2)
    head = spaces.Box(lo.astype(np.float32), hi.astype(np.float32), (2,), np.float32)
    if mode == "image":
        return spaces.Dict({"image": spaces.Box(0, 255, (*image_hw, 3), np.uint8),
                            "head_angle": head})
    face = (spaces.Box(-0.5, 0.5, face_hw, np.float32) if scaled_obs
            else spaces.Box(0, 255, face_hw, np.uint8))
    looks = {"face": face, "head_angle": head}
    if mode == "detections":
        low, high = _SCALED_ROW_BOUNDS if scaled_obs else _row_bounds(tuple(image_hw))
        looks["detections"] = spaces.Box(np.tile(low, (MAX_DETECTIONS, 1)),
                                         np.tile(high, (MAX_DETECTIONS, 1)), dtype=np.float32)
    return spaces.Dict(looks)


def scaled(obs: dict, joint_limits_rad: np.ndarray, image_hw: tuple[int, int]) -> dict:
    """An observation (or a batch of them) with ``scaled_obs``: every entry near [-1, 1].

    The face's grey levels g become g / 255 - 0.5; the head angle is scaled by the joint
    ranges to [-1, 1]; in the detections, centres are offsets from the image centre in half
    image sizes ([-1, 1]) and areas are in images ([0, 4]). The image is left as it is (uint8:
    the RL libraries scale images themselves).
    """
    mid = joint_limits_rad.mean(axis=1)
    half = (joint_limits_rad[:, 1] - joint_limits_rad[:, 0]) / 2
    out = {**obs, "head_angle": ((obs["head_angle"] - mid) / half).astype(np.float32)}
    if "face" in obs:
        out["face"] = (obs["face"] / np.float32(255) - np.float32(0.5)).astype(np.float32)
    if "detections" in obs:
        out["detections"] = _scaled_rows(obs["detections"], image_hw)
    return out


def _scaled_rows(rows: np.ndarray, image_hw: tuple[int, int]) -> np.ndarray:
    """Detection rows with centres in half image sizes from the centre and areas in images."""
    h, w = image_hw
    out = np.array(rows, np.float32)
    _scale_rows_into(out.reshape(-1, out.shape[-1]), w, h, *_SCALED_ROW_BOUNDS)
    return out


@jit
def _scale_rows_into(rows, width_px, height_px, low, high) -> None:
    """Scale detection rows in place (:func:`scaled`), in float32, within [low, high].

    The vector kernels scale their rows with it too.
    """
    x0, y0 = np.float32((width_px - 1) / 2), np.float32((height_px - 1) / 2)
    xh, yh = np.float32(width_px / 2), np.float32(height_px / 2)
    area = np.float32(width_px * height_px)
    for r in range(rows.shape[0]):
        present = rows[r, 0]
        rows[r, 1] = (rows[r, 1] - x0) / xh * present  # zero rows stay (signed) zero
        rows[r, 2] = (rows[r, 2] - y0) / yh * present
        rows[r, 3] = rows[r, 3] / area
        for j in range(rows.shape[1]):  # float32 rounding stays inside the space
            rows[r, j] = min(max(rows[r, j], low[j]), high[j])


# present, centre x and y (half image sizes from the centre), area (images), edge, motion
_SCALED_ROW_BOUNDS = (np.array([0, -1, -1, 0, 0, 0], np.float32),
                      np.array([1, 1, 1, 4, 1, 1], np.float32))


@functools.cache
def _row_bounds(image_hw: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """Bounds of a detection row: centres in the image, areas up to 4 images, fractions."""
    h, w = image_hw
    bounds = (np.array([0, -0.5, -0.5, 0, 0, 0], np.float32),
              np.array([1, w - 0.5, h - 0.5, 4 * w * h, 1, 1], np.float32))
    for b in bounds:
        b.setflags(write=False)  # kept for every step of that image size
    return bounds


@jit
def _rows_into(centre, area, edge, motion, low, high, rows) -> None:
    """Write the first ``len(area)`` rows: 1, the centre, area, edge and motion, in float32.

    Each within [low, high]: rounded to float32 first, then clipped, as numpy's clip of the
    float32 rows would.
    """
    for i in range(len(area)):
        values = (1.0, float(centre[i, 0]), float(centre[i, 1]), float(area[i]), float(edge[i]),
                  float(motion[i]))
        for j in range(6):
            rows[i, j] = min(max(np.float32(values[j]), low[j]), high[j])


def detection_rows(det: Detections) -> np.ndarray:
    """The detections as (MAX_DETECTIONS, 6) float32 rows of DETECTION_COLUMNS, zero-padded."""
    rows = np.zeros((MAX_DETECTIONS, len(DETECTION_COLUMNS)), np.float32)
    low, high = _row_bounds(tuple(det.image_size_px[::-1]))
    _rows_into(det.centre_px, det.colour_area_px, det.edge, det.motion, low, high, rows)
    return rows


def detections_of(info: dict, image_size_px: tuple[int, int]) -> Detections:
    """The :class:`~jointattention.agent.detections.Detections` in a step's ``info``."""
    n, d = int(info["n_detections"]), info["detections"]
    return Detections(d["centre_px"][:n], d["colour_area_px"][:n], d["edge"][:n],
                      d["motion"][:n], image_size_px=image_size_px)


# A step's info: "detections" (a dict of these, padded to MAX_DETECTIONS), then these keys.
DETECTION_INFO = ("centre_px", "colour_area_px", "edge", "motion")
STEP_INFO = ("n_detections", "fired", "seen", "attended", "target", "limit_hit",
             "intrinsic_reward", "external_reward", "caregiver_error_rad")


# Gymnasium's "_key" mask of each info key in a vector environment: the detections' own, then
# the step's
DETECTION_MASKS = tuple(f"_{key}" for key in DETECTION_INFO)
STEP_MASKS = tuple(f"_{key}" for key in ("detections", *STEP_INFO))
_KEYS = {False: (DETECTION_INFO, ("detections", *STEP_INFO)),
         True: ((*DETECTION_INFO, *DETECTION_MASKS), ("detections", *STEP_INFO, *STEP_MASKS))}


def info_dict(detections, values, masks=()) -> dict:
    """A step's ``info`` from the values of :data:`DETECTION_INFO` and :data:`STEP_INFO`.

    ``masks``: a vector environment's, one for each of :data:`DETECTION_MASKS` then
    :data:`STEP_MASKS`, each after its dictionary's values (one zip per dictionary: a step of
    64 sub-environments is short).
    """
    detection_keys, step_keys = _KEYS[len(masks) > 0]
    if len(masks):
        n = len(DETECTION_MASKS)
        detections, values = (*detections, *masks[:n]), (*values, *masks[n:])
    return dict(zip(step_keys, (dict(zip(detection_keys, detections, strict=True)), *values),
                    strict=True))


def info_of(trial: SceneTrial) -> dict:
    """The step's ``info``: the detector's report (padded) and how the trial stands."""
    det, fired = trial.detections, trial.seen is not None
    n, rows = len(det), np.zeros((3, MAX_DETECTIONS))  # one allocation for three columns
    centre = np.zeros((MAX_DETECTIONS, 2))
    centre[:n] = det.centre_px
    rows[0, :n], rows[1, :n], rows[2, :n] = det.colour_area_px, det.edge, det.motion
    return info_dict((centre, rows[0], rows[1], rows[2]), (
        len(det), fired, -1 if trial.seen is None else int(trial.seen), int(trial.attended),
        int(trial.target), bool(trial.limit_hit), float(fired),
        float(fired and trial.attended == trial.target), _error_of(trial)))


def _error_of(trial: SceneTrial) -> float:
    """How far from her target the robot looked, as the caregiver sees it (-1: not fired)."""
    error = trial.outcome.caregiver_error_rad if trial.seen is not None else None
    return -1.0 if error is None else float(error)
