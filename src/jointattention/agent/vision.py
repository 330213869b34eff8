"""The salient feature detector on camera images (OpenCV): what the paper's robot computes.

Bright colour: pixels of high HSV saturation and value, split where the hue jumps (two
touching objects of different colours), grouped by connected components; each component's
pixel count is its f_col and its centroid its position. A component cut by the image border
is located by the circle through its visible outline (a ball's image is a disc), and dropped
if that centre lies outside the image, the fast detector's rule. Edge complexity (f_edge): the
fraction of Canny edge pixels inside the region (its outline excluded). Motion (f_mot): the
fraction of the region whose grey level changed since the previous image.
"""

from __future__ import annotations

import cv2
import numpy as np

from .detections import Detections
from .options import DetectorConfig

__all__ = ["ColourRegions", "ImageDetector", "colour_regions", "fit_ball", "fit_circle"]


class ColourRegions:
    """Bright-colour regions of one image.

    ``labels`` (H, W) int32 (0: none, k: region k-1), and per region ``centre_px`` (n, 2) and
    ``area_px`` (n,).
    """

    __slots__ = ("area_px", "centre_px", "labels")

    def __init__(self, labels: np.ndarray, centre_px: np.ndarray, area_px: np.ndarray):
        self.labels, self.centre_px, self.area_px = labels, centre_px, area_px

    def __len__(self) -> int:
        return len(self.area_px)


def _hue_cuts(hue: np.ndarray, mask: np.ndarray, split_deg: float) -> np.ndarray:
    """Pixels (right or lower of a pair of bright neighbours) where the hue jumps."""
    h = hue.astype(np.int16)  # OpenCV hue: 0-179, two degrees per unit
    cut = np.zeros_like(mask)
    for later, earlier in (((slice(1, None), slice(None)), (slice(None, -1), slice(None))),
                           ((slice(None), slice(1, None)), (slice(None), slice(None, -1)))):
        d = np.abs(h[later] - h[earlier])
        cut[later] |= (np.minimum(d, 180 - d) * 2 > split_deg) & mask[later] & mask[earlier]
    return cut


def fit_circle(points: np.ndarray) -> tuple[np.ndarray, float]:
    """Least-squares circle (centre, radius) through points (n, 2) (Kasa's algebraic fit)."""
    p = np.asarray(points, dtype=float)
    a = np.column_stack([2 * p, np.ones(len(p))])
    b = (p**2).sum(axis=1)
    (cx, cy, c), *_ = np.linalg.lstsq(a, b, rcond=None)
    return np.array([cx, cy]), float(np.sqrt(max(c + cx * cx + cy * cy, 0.0)))


def fit_ball(points: np.ndarray, centre_px, focal_px: float) -> tuple[np.ndarray, float]:
    """Where a ball's centre projects, and its radius, from points of its outline.

    ``points`` (n, 2) are image points of the outline; the radius is in pixels (f tan of the ball's
    angular radius).

    A calibrated camera sees a ball's outline as a cone of rays, all at the same angle b to
    the ray c through its centre: r_i . v = 1 for v = c / cos b, solved by least squares.
    """
    rays = np.column_stack([(np.asarray(points, float) - centre_px) / focal_px,
                            np.ones(len(points))])
    rays /= np.linalg.norm(rays, axis=1, keepdims=True)
    v, *_ = np.linalg.lstsq(rays, np.ones(len(rays)), rcond=None)
    cos_b = 1 / max(float(np.linalg.norm(v)), 1.0)
    radius = focal_px * np.sqrt(1 - cos_b**2) / cos_b
    return np.asarray(centre_px, float) + focal_px * v[:2] / v[2], float(radius)


def _border_centre(labels: np.ndarray, k: int, box, shape,
                   focal_px: float | None) -> np.ndarray | None:
    """Centre of region ``k`` (touching the image border) from its outline off the border.

    The ball fitted through the outline if the focal length is known, else the circle. None if the
    outline is too short, or if the region reaches less than the fitted radius (or 5 px, as a thin
    cap's fit is unsound) in from the border: a ball whose centre is in the image reaches at least
    its radius in from it.
    """
    x, y, w, h = box
    crop = (labels[y:y + h, x:x + w] == k).astype(np.uint8)
    contours, _ = cv2.findContours(crop, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    pts = np.concatenate([c[:, 0, :] for c in contours]) + (x, y)
    height, width = shape
    off = ((pts[:, 0] > 0) & (pts[:, 0] < width - 1) & (pts[:, 1] > 0)
           & (pts[:, 1] < height - 1))
    if off.sum() < 8:
        return None
    if focal_px is None:
        centre, radius = fit_circle(pts[off])
    else:
        centre, radius = fit_ball(pts[off], ((width - 1) / 2, (height - 1) / 2), focal_px)
    return centre if min(w, h) >= max(radius - 1, 5) else None


def colour_regions(image_rgb: np.ndarray, config: DetectorConfig,
                   focal_px: float | None = None) -> ColourRegions:
    """The bright-colour regions of an RGB uint8 image (see the module's docstring).

    ``focal_px``, the camera's focal length, locates balls cut by the border.
    """
    hsv = cv2.cvtColor(np.ascontiguousarray(image_rgb), cv2.COLOR_RGB2HSV)
    mask = (hsv[..., 1] >= config.min_saturation * 255) & (hsv[..., 2] >= config.min_value * 255)
    mask &= ~_hue_cuts(hsv[..., 0], mask, config.hue_split_deg)
    n, labels, stats, centroids = cv2.connectedComponentsWithStats(
        mask.astype(np.uint8), connectivity=4, ltype=cv2.CV_32S)
    height, width = mask.shape
    keep, centres, areas = [], [], []
    for k in range(1, n):
        x, y, w, h, area = stats[k]
        if area < config.min_area_px:
            continue
        centre = centroids[k]
        if x == 0 or y == 0 or x + w == width or y + h == height:
            centre = _border_centre(labels, k, (x, y, w, h), mask.shape, focal_px)
            if centre is None or not (-0.5 <= centre[0] <= width - 0.5
                                      and -0.5 <= centre[1] <= height - 0.5):
                continue
        keep.append(k)
        centres.append(centre)
        areas.append(float(area))
    relabel = np.zeros(n, np.int32)
    relabel[keep] = np.arange(1, len(keep) + 1)
    return ColourRegions(relabel[labels], np.array(centres, float).reshape(-1, 2),
                         np.array(areas, float))


def _fractions(flags: np.ndarray, labels: np.ndarray, n: int) -> np.ndarray:
    """Per region 1..n, the fraction of its pixels where ``flags`` is set."""
    inside = labels > 0
    total = np.bincount(labels[inside], minlength=n + 1)[1:]
    hits = np.bincount(labels[inside & flags], minlength=n + 1)[1:]
    return hits / np.maximum(total, 1)


class ImageDetector:
    """The robot's salient feature detector on RGB images; reports :class:`Detections`.

    Args:
        config: thresholds (:class:`~jointattention.config.DetectorConfig`).
        focal_px: the camera's focal length in pixels, if known (the robot knows its own
            camera): a ball cut by the image border is then located by its outline's cone
            of rays, else by the circle through the outline.

    Motion compares each image with the previous one given to :meth:`detect`; call
    :meth:`reset` when the view jumps (a new trial), so that the first image has no motion.
    """

    def __init__(self, config: DetectorConfig | None = None, focal_px: float | None = None):
        self.config = config if config is not None else DetectorConfig()
        self.focal_px = focal_px
        self._previous_gray: np.ndarray | None = None

    def reset(self) -> None:
        """Forget the previous image."""
        self._previous_gray = None

    def detect(self, image_rgb: np.ndarray) -> Detections:
        """The salient objects of one image, with the paper's f_col, f_edge and f_mot."""
        image_rgb = np.asarray(image_rgb)
        if image_rgb.ndim != 3 or image_rgb.shape[2] != 3 or image_rgb.dtype != np.uint8:
            raise ValueError(f"image of shape {image_rgb.shape} and type {image_rgb.dtype}: "
                             "expected RGB uint8 (H, W, 3)")
        cfg = self.config
        regions = colour_regions(image_rgb, cfg, self.focal_px)
        gray = cv2.cvtColor(np.ascontiguousarray(image_rgb), cv2.COLOR_RGB2GRAY)
        n = len(regions)
        inner = cv2.erode((regions.labels > 0).astype(np.uint8), np.ones((5, 5), np.uint8))
        inner_labels = regions.labels * inner  # outline excluded: a plain ball has no texture
        edges = cv2.Canny(gray, *cfg.canny_thresholds) > 0
        edge = _fractions(edges, inner_labels, n)
        if self._previous_gray is None or self._previous_gray.shape != gray.shape:
            motion = np.zeros(n)
        else:
            change = cv2.absdiff(gray, self._previous_gray) > cfg.motion_threshold
            motion = _fractions(change, regions.labels, n)
        self._previous_gray = gray
        h, w = gray.shape
        return Detections(regions.centre_px, regions.area_px, edge, motion, (w, h))
