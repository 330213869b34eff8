"""The robot's face finders, and the choice among them.

BlazeFace (:mod:`~jointattention.agent.blazeface`, the default), BlazeFace placed by a
template, the template alone and OpenCV's Haar cascade (:mod:`~jointattention.agent.faces`);
README, *Face finders*, and docs/faces/detectors.md compare them.
"""

from __future__ import annotations

import cv2
import numpy as np

from .blazeface import BlazeFace, Calibration
from .faces import Face, FaceFinder

__all__ = ["FACE_METHODS", "AlignedFinder", "BlazeFaceFinder", "finder_for"]

# the robot's face finders, default first
FACE_METHODS = ("blazeface", "blazeface-template", "template", "haar")


class BlazeFaceFinder:
    """Faces found by the shipped BlazeFace network, placed where the data sets cut windows.

    Each face's centre is the head's centre and its height ``margin`` times the head's, by the
    shipped :class:`~jointattention.agent.blazeface.Calibration` of the network's landmarks,
    so a window cut around it is the window a data set cut around the head would hold.

    Args:
        min_score: least face probability. 0.4 finds 99.75% of 400 held-out rendered faces
            (0.5: 98.5%; the misses are dark skin in dim light); docs/faces/detectors.md.
        margin: the window's height as a multiple of the head's (the data sets' 1.15).
    """

    method = "blazeface"

    def __init__(self, min_score: float = 0.4, margin: float = 1.15):
        self.net = BlazeFace(min_score)
        self.calibration = Calibration.load()
        self.margin = margin

    def find(self, image_rgb: np.ndarray) -> list[Face]:
        """The faces in an RGB uint8 image, best first."""
        faces = []
        for d in self.net.detect(np.ascontiguousarray(image_rgb)):
            centre, height = self.calibration.head(d)
            # the box drawn is the paper's 30 x 25 window's shape
            faces.append(Face(centre, self.margin * height, d.score, 30 / 25, d.landmarks_px))
        return faces


class AlignedFinder:
    """BlazeFace finds the face; the template places its window.

    Around each face BlazeFace finds, the template (the mean window a model learned from) is
    matched at heights 2% apart within ``reach`` of the face's, and at places within a third of
    its height, so the window is cut nearer where the model's own windows were: a model learned
    from one caregiver's box-cut windows answers a window a few pixels or percent off
    differently (README, *The loop closed in the simulator*).
    """

    method = "blazeface-template"

    def __init__(self, template: np.ndarray, min_score: float = 0.4, reach: float = 1.15):
        self.coarse = BlazeFaceFinder(min_score)
        self.template = np.asarray(template, np.uint8)
        self.reach = reach

    def find(self, image_rgb: np.ndarray) -> list[Face]:
        """The faces in an RGB uint8 image, best first, each placed by the template."""
        faces = self.coarse.find(image_rgb)
        if not faces:
            return []
        gray = cv2.cvtColor(np.ascontiguousarray(image_rgb), cv2.COLOR_RGB2GRAY)
        out = []
        for face in faces:
            h = face.height_px
            th, tw = self.template.shape
            size = (int(round(h * self.reach * tw / th + 2 * h / 3)),
                    int(round(h * self.reach + 2 * h / 3)))
            centre = (float(face.centre_px[0]), float(face.centre_px[1]))
            patch = cv2.getRectSubPix(gray, size, centre)
            fine = FaceFinder("template", self.template, min_score=-1.0,
                              heights_px=(h / self.reach, h * self.reach), scale_step=1.02,
                              min_edge_score=-1.0)._match(patch, 1.0)
            if not fine:
                out.append(face)
                continue
            origin = np.array(centre) - (np.array(size) - 1) / 2
            out.append(Face(fine[0].centre_px + origin, fine[0].height_px, face.score,
                            fine[0].aspect, face.landmarks_px))
        return out


def finder_for(method: str, template: np.ndarray | None = None,
               min_score: float | None = None) -> FaceFinder | BlazeFaceFinder:
    """The robot's face finder of ``method`` (:data:`FACE_METHODS`).

    ``min_score``: None for the method's own (BlazeFace's probability 0.4, the template's
    correlation 0.7). Templates are tried from 8% of each image's height (8 px at least) to
    all of it, at heights 2% apart: the learning module answers a window cut a few percent too
    large or too small differently (README, *The loop closed in the simulator*).
    """
    if method == "blazeface":
        return BlazeFaceFinder() if min_score is None else BlazeFaceFinder(min_score)
    if method == "blazeface-template":
        if template is None:
            raise ValueError("face method 'blazeface-template': expected a template image")
        return AlignedFinder(template) if min_score is None else AlignedFinder(template,
                                                                               min_score)
    return FaceFinder(method, template, min_score=0.7 if min_score is None else min_score,
                      heights_px=None, scale_step=1.02)
