"""Where the head is, from a BlazeFace detection: its landmarks, then the pixels around it.

The network's box is the face's (brows to chin); the data sets cut their windows around the
head's centre, ``margin`` times the head's height tall. :class:`Calibration` places the head in
two steps, each a least-squares map fitted once on rendered views whose truth is known
(``python docs/results/faces/calibrate.py``; shipped as ``data/blazeface_calibration.npz``):

1. the landmarks' offsets in the box, in box heights -> the head's centre and height;
2. ``n`` refinements, each a ridge map of the grey levels of a square around the current head
   (``CROP`` head heights wide, seen at ``SIDE_PX`` x ``SIDE_PX``, standardised) -> a shift of
   the centre and a factor on the height, applied in turn (a cascade, as in face alignment).

So a window cut around a detection is the window a data set would hold: docs/real-head.md
gives the errors that remain.
"""

from __future__ import annotations

import json
from dataclasses import dataclass

import cv2
import numpy as np

from .._checks import short_repr
from .._readers import loads_json, read_npz, shipped_path
from ..errors import FileError
from .blazeface import Detection

__all__ = ["CALIBRATION_FILE", "CROP", "SIDE_PX", "Calibration"]

CALIBRATION_FILE = "blazeface_calibration.npz"
CROP = 1.6  # the refinements see a square this many head heights wide
SIDE_PX = 24  # ... at this many pixels a side
RIDGE = 100.0  # the refinements' ridge penalty (chosen on held-out views: 1-1000 within 0.2 px)


def _landmark_features(detections: list[Detection]) -> np.ndarray:
    """(n, 13): 1 and each landmark's offset from its box's centre, in box heights."""
    rows = []
    for d in detections:
        x, y, w, h = d.box_px
        rows.append(np.r_[1.0, ((d.landmarks_px - [x + w / 2, y + h / 2]) / h).ravel()])
    return np.array(rows).reshape(len(rows), 13)


def _pixel_features(gray: np.ndarray, centre_px, height_px: float) -> np.ndarray:
    """(1 + SIDE_PX**2,): 1 and the standardised grey levels of the square around a head."""
    side = max(2, int(round(CROP * height_px)))
    patch = cv2.getRectSubPix(gray, (side, side), (float(centre_px[0]), float(centre_px[1])))
    p = cv2.resize(patch, (SIDE_PX, SIDE_PX), interpolation=cv2.INTER_AREA).astype(float).ravel()
    return np.r_[1.0, (p - p.mean()) / (p.std() + 1e-6)]


def _first_guess(weights: np.ndarray, detection: Detection) -> tuple[np.ndarray, float]:
    x, y, w, h = detection.box_px
    dx, dy, height = (_landmark_features([detection]) @ weights)[0] * h
    return np.array([x + w / 2 + dx, y + h / 2 + dy]), float(height)


def _refine(stage: np.ndarray, gray: np.ndarray, centre, height: float):
    dx, dy, log_factor = _pixel_features(gray, centre, height) @ stage
    return centre + np.array([dx, dy]) * height, height * float(np.exp(log_factor))


@dataclass(frozen=True)
class Calibration:
    """The two-step map from a detection to the head's centre and height.

    Attributes:
        weights: (13, 3) landmark features -> (dx, dy, height) in box heights.
        stages: (n, 1 + SIDE_PX**2, 3) pixel features -> (dx, dy, log factor) in head heights.
        meta: how it was fitted (command, world, seed, views).
    """

    weights: np.ndarray
    stages: np.ndarray
    meta: dict

    def head(self, detection: Detection, gray: np.ndarray | None = None
             ) -> tuple[np.ndarray, float]:
        """The head's centre (px) and height (px); ``gray``: the image, for the refinements."""
        centre, height = _first_guess(self.weights, detection)
        if gray is not None:
            for stage in self.stages:
                centre, height = _refine(stage, gray, centre, height)
        return centre, height

    @classmethod
    def fit(cls, grays: list[np.ndarray], detections: list[Detection], centres_px, heights_px,
            meta: dict, n_stages: int = 3) -> Calibration:
        """Least-squares maps from detections in ``grays`` to the true heads."""
        n = len(detections)
        if n < 1 + SIDE_PX ** 2 or len(grays) != n:
            raise ValueError(f"{n} detections in {len(grays)} images: expected one image per "
                             f"detection and at least {1 + SIDE_PX ** 2}")
        centres, heights = np.asarray(centres_px, float), np.asarray(heights_px, float)
        boxes = np.array([d.box_px for d in detections])
        h = boxes[:, 3:4]
        target = np.c_[(centres - boxes[:, :2] - boxes[:, 2:] / 2) / h, heights[:, None] / h]
        weights = np.linalg.lstsq(_landmark_features(detections), target, rcond=None)[0]
        guesses = [_first_guess(weights, d) for d in detections]
        stages = []
        for _ in range(n_stages):
            x = np.array([_pixel_features(g, c, hh) for g, (c, hh) in zip(grays, guesses,
                                                                            strict=True)])
            hs = np.array([hh for _, hh in guesses])
            y = np.c_[(centres - [c for c, _ in guesses]) / hs[:, None], np.log(heights / hs)]
            penalty = RIDGE * np.eye(x.shape[1])
            penalty[0, 0] = 0.0  # the constant is not shrunk
            stage = np.linalg.solve(x.T @ x + penalty, x.T @ y)
            stages.append(stage)
            guesses = [_refine(stage, g, c, hh) for g, (c, hh) in zip(grays, guesses,
                                                                       strict=True)]
        return cls(weights, np.array(stages), dict(meta))

    def save(self, path) -> None:
        """Write the maps and how they were fitted to an .npz file."""
        np.savez(path, weights=self.weights, stages=self.stages, meta=json.dumps(self.meta))

    @classmethod
    def load(cls, path=None) -> Calibration:
        """The calibration at ``path``; None: the one shipped with the package."""
        what = "a BlazeFace calibration .npz (weights, stages, meta)"
        if path is None:
            path = shipped_path(CALIBRATION_FILE)
        f = read_npz(path, what)
        try:
            meta = loads_json(str(f["meta"]))
            weights, stages = f["weights"].astype(float), f["stages"].astype(float)
        except (KeyError, ValueError, TypeError) as err:
            raise FileError(f"{path}: {short_repr(str(err))}; expected {what}") from None
        if not isinstance(meta, dict):
            raise FileError(f"{path}: meta is not a JSON object; expected {what}")
        return cls(weights, stages, meta)
