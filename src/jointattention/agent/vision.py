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

import math

import cv2
import numpy as np

from ._regions import bright_regions_into, region_fractions
from .detections import Detections
from .options import DetectorConfig

__all__ = ["ColourRegions", "ImageDetector", "colour_regions", "fit_ball", "fit_circle"]


class ColourRegions:
    """Bright-colour regions of one image.

    ``labels`` (H, W) int32 (0: none, k: region k-1), and per region ``centre_px`` (n, 2) and
    ``area_px`` (n,). ``box_px`` (x0, y0, x1, y1), ends excluded, holds every region's pixels.
    """

    __slots__ = ("area_px", "box_px", "centre_px", "labels")

    def __init__(self, labels: np.ndarray, centre_px: np.ndarray, area_px: np.ndarray,
                 box_px: tuple[int, int, int, int] | None = None):
        self.labels, self.centre_px, self.area_px = labels, centre_px, area_px
        self.box_px = (0, 0, labels.shape[1], labels.shape[0]) if box_px is None else box_px

    def __len__(self) -> int:
        return len(self.area_px)


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


def _border_centre(labels: np.ndarray, k: int, box, origin, shape,
                   focal_px: float | None) -> np.ndarray | None:
    """Centre of region ``k`` (touching the image border) from its outline off the border.

    ``labels`` is the part of the image at ``origin`` (x, y), ``box`` the region's in it.
    The ball fitted through the outline if the focal length is known, else the circle. None if
    the outline is too short, or if the region reaches less than the fitted radius (or 5 px, as
    a thin cap's fit is unsound) in from the border: a ball whose centre is in the image reaches
    at least its radius in from it.
    """
    x, y, w, h = box
    crop = (labels[y:y + h, x:x + w] == k).astype(np.uint8)
    contours, _ = cv2.findContours(crop, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    pts = np.concatenate([c[:, 0, :] for c in contours]) + (x + origin[0], y + origin[1])
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


def _whole_image_centre(centroid, area: int, x0: int, y0: int) -> np.ndarray:
    """OpenCV's centroid of a component of the part of an image at (x0, y0), in the whole.

    OpenCV's centroid is the sum of the pixels' coordinates (an integer) over the area: that
    sum is recovered exactly and moved, so the centre has the whole image's bits.
    """
    return np.array([(round(centroid[0] * area) + area * x0) / area,
                     (round(centroid[1] * area) + area * y0) / area])


def colour_regions(image_rgb: np.ndarray, config: DetectorConfig,
                   focal_px: float | None = None) -> ColourRegions:
    """The bright-colour regions of an RGB uint8 image (see the module's docstring).

    ``focal_px``, the camera's focal length, locates balls cut by the border.
    """
    hsv = cv2.cvtColor(np.ascontiguousarray(image_rgb), cv2.COLOR_RGB2HSV)
    height, width = hsv.shape[:2]
    mask = np.empty((height, width), np.uint8)
    x0, y0, x1, y1 = box = bright_regions_into(  # levels are whole: >= x is >= ceil(x)
        hsv, math.ceil(config.min_saturation * 255), math.ceil(config.min_value * 255),
        config.hue_split_deg, mask)
    labels = np.zeros((height, width), np.int32)
    if x1 == 0:
        return ColourRegions(labels, np.zeros((0, 2)), np.zeros(0), box)
    # only the box around the bright pixels: OpenCV numbers its components as the whole
    # image's (by their first pixel, row by row), at a fraction of the cost
    n, part, stats, centroids = cv2.connectedComponentsWithStats(
        mask[y0:y1, x0:x1], connectivity=4, ltype=cv2.CV_32S)
    keep, centres, areas = [], [], []
    for k, (x, y, w, h, area) in enumerate(stats.tolist()):
        if k == 0 or area < config.min_area_px:
            continue
        if x + x0 == 0 or y + y0 == 0 or x0 + x + w == width or y0 + y + h == height:
            centre = _border_centre(part, k, (x, y, w, h), (x0, y0), mask.shape, focal_px)
            if centre is None or not (-0.5 <= centre[0] <= width - 0.5
                                      and -0.5 <= centre[1] <= height - 0.5):
                continue
        else:
            centre = _whole_image_centre(centroids[k], area, x0, y0)
        keep.append(k)
        centres.append(centre)
        areas.append(float(area))
    relabel = np.zeros(n, np.int32)
    relabel[keep] = np.arange(1, len(keep) + 1)
    labels[y0:y1, x0:x1] = relabel[part]
    return ColourRegions(labels, np.array(centres, float).reshape(-1, 2),
                         np.array(areas, float), box)


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
        previous, self._previous_gray = self._previous_gray, gray
        moved = previous is not None and previous.shape == gray.shape
        h, w = gray.shape
        if len(regions) == 0:  # nothing to measure (the edges cost as much as all the rest)
            return Detections(regions.centre_px, regions.area_px, np.zeros(0), np.zeros(0),
                              (w, h))
        edges = cv2.Canny(gray, *cfg.canny_thresholds)
        edge, motion = region_fractions(regions.labels, len(regions), regions.box_px, edges, gray,
                                        previous if moved else gray, cfg.motion_threshold,
                                        moved)
        return Detections(regions.centre_px, regions.area_px, edge, motion, (w, h))
