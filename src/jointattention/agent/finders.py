"""The robot's face finders, and the choice among them.

BlazeFace (:mod:`~jointattention.agent.blazeface`, the default), the template (the paper's
robot's way) and OpenCV's Haar cascade (:mod:`~jointattention.agent.faces`); docs/real-head.md
and docs/results/faces/detectors.md compare them.
"""

from __future__ import annotations

import cv2
import numpy as np

from .._checks import short_repr
from ..errors import ArgumentError
from .blazeface import BlazeFace
from .face_calibration import Calibration
from .faces import Face, FaceFinder

__all__ = ["DEFAULT_FACE", "FACE_METHODS", "BlazeFaceFinder", "check_finder", "finder_for"]

# the robot's face finders, default first
FACE_METHODS = ("blazeface", "template", "haar")
DEFAULT_FACE = FACE_METHODS[0]  # the finder of follow, the closed loop and the finder cut


def check_finder(face, min_score=None) -> None:
    """One ArgumentError line unless ``face`` is a finder and ``min_score`` one of its scores."""
    if not isinstance(face, str) or face not in FACE_METHODS:
        raise ArgumentError(f"face {short_repr(face)}: expected one of {', '.join(FACE_METHODS)}")
    if min_score is None:
        return
    probability = face == "blazeface"
    number = not isinstance(min_score, bool) and isinstance(min_score, (int, float))
    inside = number and (0 < min_score < 1 if probability else -1 <= min_score <= 1)  # NaN: no
    if not inside:
        what = "above 0 and below 1 (a probability" if probability else (
            "from -1 to 1 (a normalised correlation")
        raise ArgumentError(f"min_score {short_repr(min_score)}: expected a number {what}, for "
                            f"face {face!r})")


class BlazeFaceFinder:
    """Faces found by the shipped BlazeFace network, placed where the data sets cut windows.

    Each face's centre is the head's centre and its height ``margin`` times the head's, by the
    shipped :class:`~jointattention.agent.face_calibration.Calibration` (landmarks, then pixels),
    so a window cut around it is the window a data set cut around the head would hold.

    Args:
        min_score: least face probability. 0.4 finds 99.75% of 400 held-out rendered faces
            (0.5: 98.5%; the misses are dark skin in dim light); docs/results/faces/detectors.md.
        margin: the window's height as a multiple of the head's (the data sets' 1.15).
        refine: whether the calibration's pixel maps refine the landmarks' placement. They
            learned the simulated heads (2.0 px of median error there, against 3.2 px with
            the landmarks alone); for photographs of people, False.
    """

    method = "blazeface"

    def __init__(self, min_score: float = 0.4, margin: float = 1.15, *, refine: bool = True):
        self.net = BlazeFace(min_score)
        self.calibration = Calibration.load()
        self.margin, self.refine = margin, refine

    def find(self, image_rgb: np.ndarray) -> list[Face]:
        """The faces in an RGB uint8 image, best first."""
        image = np.ascontiguousarray(image_rgb)
        detections = self.net.detect(image)
        gray = (cv2.cvtColor(image, cv2.COLOR_RGB2GRAY) if detections and self.refine
                else None)
        faces = []
        for d in detections:
            centre, height = self.calibration.head(d, gray)
            # the box drawn is the paper's 30 x 25 window's shape
            faces.append(Face(centre, self.margin * height, d.score, 30 / 25, d.landmarks_px))
        return faces


def finder_for(method: str, template: np.ndarray | None = None,
               min_score: float | None = None, *, refine: bool = True
               ) -> FaceFinder | BlazeFaceFinder:
    """The robot's face finder of ``method`` (:data:`FACE_METHODS`).

    ``min_score``: None for the method's own (BlazeFace's probability 0.4, the template's
    correlation 0.7). ``refine``: BlazeFace's pixel refinements (:class:`BlazeFaceFinder`).
    Templates are tried from 8% of each image's height (8 px at least) to all of it, at
    heights 2% apart: the learning module answers a window cut a few percent too large or too
    small differently (docs/real-head.md).
    """
    if method == "blazeface":
        return BlazeFaceFinder(0.4 if min_score is None else min_score, refine=refine)
    return FaceFinder(method, template, min_score=0.7 if min_score is None else min_score,
                      heights_px=None, scale_step=1.02)
