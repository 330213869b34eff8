"""The caregiver's face in an image, and the face window cut around it.

Faces are found by template matching, as the paper's robot did, or by OpenCV's Haar cascade;
:mod:`~jointattention.agent.finders` adds BlazeFace, the robot's default, and chooses among
them. The face window is the paper's 30 x 25 pixels.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

__all__ = ["MAX_SEARCH_SIDE_PX", "Face", "FaceFinder", "face_template", "face_window",
           "window_of"]


@dataclass(frozen=True)
class Face:
    """A face found in an image.

    Its centre, the height of its box (both in pixels), the match score (normalised correlation
    for the template; 1.0 for the Haar cascade, which gives none; BlazeFace's probability), the
    box's width / height and, from BlazeFace, the six landmarks (6, 2).
    """

    centre_px: np.ndarray
    height_px: float
    score: float
    aspect: float = 1.0
    landmarks_px: np.ndarray | None = None

    @property
    def box_px(self) -> tuple[int, int, int, int]:
        """(x, y, w, h) of the box."""
        h = self.height_px
        w = h * self.aspect
        x, y = self.centre_px
        return int(round(x - w / 2)), int(round(y - h / 2)), int(round(w)), int(round(h))


def face_template(face_windows: np.ndarray) -> np.ndarray:
    """A template from face windows the robot has seen (n, h, w): their mean, uint8."""
    faces = np.asarray(face_windows, dtype=float)
    if faces.ndim != 3 or len(faces) == 0:
        raise ValueError(f"face windows of shape {faces.shape}: expected (n, height, width)")
    return np.clip(np.rint(faces.mean(axis=0)), 0, 255).astype(np.uint8)


class FaceFinder:
    """Finds faces in RGB images.

    Args:
        method: ``"template"`` (normalised correlation with ``template`` over a range of
            scales; returns the best match above ``min_score``) or ``"haar"`` (OpenCV's
            frontal-face cascade; returns every face it finds).
        template: grayscale uint8 (h, w), e.g. :func:`face_template` of the data sets'
            windows; needed for ``"template"``.
        min_score: least score of a template match.
        heights_px: (least, greatest) face height to look for; None: from 8% of each
            image's height (8 px at least) to all of it.
        scale_step: ratio of one template height to the next tried (below 1.1: heights 10%
            apart first, then this step around the three best).
        min_edge_score: least correlation of the best match's edge strength (Sobel
            magnitude) with the template's. A face has eyes, nose and mouth; a dark ball on
            a wall can match a mean face's grey levels but has none. Measured with
            ``examples/recorded_head.py --look-away 50``: 125 views of the caregiver score
            0.68 or more, the 11 of 50 views away that pass the grey-level test 0.62 or less.
        cascade: the Haar cascade's file among those OpenCV ships (``cv2.data.haarcascades``).
    """

    def __init__(self, method: str = "template", template: np.ndarray | None = None, *,
                 min_score: float = 0.5,
                 heights_px: tuple[float, float] | None = (50.0, 200.0),
                 scale_step: float = 1.1, min_edge_score: float = 0.65,
                 cascade: str = "haarcascade_frontalface_default.xml"):
        if method not in ("template", "haar"):
            raise ValueError(f"face method {method!r}: expected 'template' or 'haar'")
        if method == "template" and template is None:
            raise ValueError("face method 'template': expected a template image")
        if not scale_step > 1:
            raise ValueError(f"scale_step {scale_step}: expected a ratio above 1")
        self.method, self.min_score, self.heights_px = method, min_score, heights_px
        self.scale_step, self.min_edge_score = scale_step, min_edge_score
        self.template = None if template is None else np.asarray(template, np.uint8)
        self._cascade = None
        if method == "haar":
            path = cv2.data.haarcascades + cascade
            self._cascade = cv2.CascadeClassifier(path)
            if self._cascade.empty():
                raise RuntimeError(f"{path}: OpenCV's Haar cascade did not load; expected "
                                   "opencv-python-headless<5, which ships it")

    def find(self, image_rgb: np.ndarray) -> list[Face]:
        """The faces in an RGB uint8 image, best first.

        An image whose longer side exceeds :data:`MAX_SEARCH_SIDE_PX` is searched at that
        size (the faces are given in the image's own pixels): the work is bounded whatever
        the image's size.
        """
        gray = cv2.cvtColor(np.ascontiguousarray(image_rgb), cv2.COLOR_RGB2GRAY)
        scale = min(1.0, MAX_SEARCH_SIDE_PX / max(gray.shape))
        if scale == 1.0:
            return self._find(gray, 1.0)
        size = (max(1, round(gray.shape[1] * scale)), max(1, round(gray.shape[0] * scale)))
        sx, sy = size[0] / gray.shape[1], size[1] / gray.shape[0]
        small = cv2.resize(gray, size, interpolation=cv2.INTER_AREA)
        return [Face((f.centre_px + 0.5) / (sx, sy) - 0.5, f.height_px / sy, f.score, f.aspect)
                for f in self._find(small, sy)]

    def _find(self, gray: np.ndarray, scale: float) -> list[Face]:
        """:meth:`find` in ``gray``, an image ``scale`` times the original's size."""
        if self.method == "haar":
            lo, hi = (int(v) for v in self._heights(gray, scale))
            boxes = self._cascade.detectMultiScale(gray, scaleFactor=1.1, minNeighbors=5,
                                                   minSize=(lo, lo), maxSize=(hi, hi))
            faces = [Face(np.array([x + w / 2, y + h / 2]), float(h), 1.0, w / h)
                     for x, y, w, h in boxes]
            return sorted(faces, key=lambda f: -f.height_px)
        return self._match(gray, scale)

    def _heights(self, gray: np.ndarray, scale: float) -> tuple[float, float]:
        """The least and greatest face height looked for in this image."""
        if self.heights_px is not None:
            return self.heights_px[0] * scale, self.heights_px[1] * scale
        return max(8.0, _LEAST_FACE_FRACTION * gray.shape[0]), float(gray.shape[0])

    def _match(self, gray: np.ndarray, scale: float) -> list[Face]:
        th, tw = self.template.shape
        lo, hi = self._heights(gray, scale)
        hi = min(hi, gray.shape[0])
        # coarse to fine: heights 10% apart, then ``scale_step`` apart around the three best
        # (a face's peak sampled 5% off its height can score below a small spurious match)
        matches = self._matches(gray, lo, hi, max(self.scale_step, _COARSE_STEP))
        if matches and self.scale_step < _COARSE_STEP:
            matches = [m for _, _, h in sorted(matches, key=lambda m: -m[0])[:3]
                       for m in self._matches(gray, max(lo, h / _COARSE_STEP),
                                              min(hi, h * _COARSE_STEP), self.scale_step)]
        score, centre, h = max(matches, key=lambda m: m[0], default=(-np.inf, None, 0.0))
        if centre is None or score < self.min_score:
            return []
        window = _gray_window(gray, centre, h, (tw, th))
        if _correlation(_edges(window), _edges(self.template)) < self.min_edge_score:
            return []
        return [Face(centre, h, float(score), tw / th)]

    def _matches(self, gray: np.ndarray, lo: float, hi: float, step: float) -> list[tuple]:
        """(score, centre, height) of the best match at each height ``lo``, ``lo * step``, ..."""
        th, tw = self.template.shape
        found = []
        height = lo
        while height <= hi * (1 + 1e-9):
            w, h = int(round(height * tw / th)), int(round(height))
            if w > gray.shape[1]:
                break
            t = cv2.resize(self.template, (w, h), interpolation=cv2.INTER_AREA)
            _, score, _, (x, y) = cv2.minMaxLoc(cv2.matchTemplate(gray, t, cv2.TM_CCOEFF_NORMED))
            found.append((score, np.array([x + (w - 1) / 2, y + (h - 1) / 2]), float(h)))
            height *= step
        return found


_COARSE_STEP = 1.1


def _edges(gray: np.ndarray) -> np.ndarray:
    """Edge strength: the magnitude of the Sobel gradient."""
    g = gray.astype(np.float32)
    return np.hypot(cv2.Sobel(g, cv2.CV_32F, 1, 0), cv2.Sobel(g, cv2.CV_32F, 0, 1))


def _correlation(a: np.ndarray, b: np.ndarray) -> float:
    """Pearson correlation of two arrays of one shape (0 if either is constant)."""
    a, b = a - a.mean(), b - b.mean()
    norm = float(np.sqrt((a * a).sum() * (b * b).sum()))
    return float((a * b).sum()) / norm if norm > 0 else 0.0


def face_window(
    image_rgb: np.ndarray, centre_px, height_px: float, size_px: tuple[int, int] = (30, 25)
) -> np.ndarray:
    """The grayscale face window (paper: 30 x 25) cropped around ``centre_px``.

    The crop is ``height_px`` tall with the window's aspect ratio, so the face fills the
    window whatever its distance; it is then resized to ``size_px = (width, height)`` by
    area averaging. Parts of the crop outside the image repeat the border pixels.
    """
    gray = cv2.cvtColor(np.ascontiguousarray(image_rgb), cv2.COLOR_RGB2GRAY)
    return _gray_window(gray, centre_px, height_px, size_px)


def _gray_window(gray: np.ndarray, centre_px, height_px: float,
                 size_px: tuple[int, int]) -> np.ndarray:
    """:func:`face_window` of an image already in grey levels."""
    width, height = size_px
    crop_h = max(int(round(height_px)), height)
    crop_w = max(int(round(crop_h * width / height)), width)
    patch = cv2.getRectSubPix(gray, (crop_w, crop_h), (float(centre_px[0]), float(centre_px[1])))
    return cv2.resize(patch, (width, height), interpolation=cv2.INTER_AREA)


# faces are looked for from this fraction of an image's height up to all of it
_LEAST_FACE_FRACTION = 0.08
MAX_SEARCH_SIDE_PX = 1280  # larger images are searched reduced to this longer side


def window_of(image_rgb: np.ndarray, face: Face, size_px: tuple[int, int]) -> np.ndarray:
    """The face window of a face found in an image: :func:`face_window` of its box.

    Imported recordings, ``follow`` and the closed loop all cut their windows with it.
    """
    return face_window(image_rgb, face.centre_px, face.height_px, size_px)
