"""The ``jointattention detect`` command: the robot's detectors on a photograph.

What they find is drawn over the photograph.

Bright-colour regions (magenta outline, cross at the centre, the most interesting one by the
paper's Eq. 1 in yellow), faces (green boxes; OpenCV's Haar cascade by default, the shipped
data sets' template with ``face_method="template"``) and edge-rich regions (cyan: where the
density of Canny edges is at least ``EDGE_DENSITY``).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from .._files import atomic_path
from .._readers import read_image
from ..agent.attention import most_interesting
from ..agent.detections import equal_area_radius
from ..agent.faces import Face, FaceFinder, face_template
from ..agent.vision import ImageDetector
from ..config import Config

__all__ = ["EDGE_DENSITY", "Found", "detect_files", "find_all"]

EDGE_DENSITY = 0.2  # fraction of edge pixels in a window that makes it edge-rich
MAGENTA, YELLOW, GREEN, CYAN = (255, 0, 255), (255, 220, 0), (0, 230, 0), (0, 230, 230)


@dataclass(frozen=True)
class Found:
    """What the detectors found in one image."""

    centre_px: np.ndarray  # (n, 2) bright-colour regions
    area_px: np.ndarray  # (n,)
    most_interesting: int | None
    faces: list[Face]
    edge_regions: list[np.ndarray]  # contours (m, 1, 2) of the edge-rich regions


def find_all(image_rgb: np.ndarray, config: Config, finder: FaceFinder) -> Found:
    """Run the colour, face and edge detectors on one RGB image."""
    h, w = image_rgb.shape[:2]
    # a photograph is larger than the robot's view: ignore specks under 0.05% of it
    cfg = dataclasses.replace(config.detector,
                              min_area_px=max(config.detector.min_area_px, int(5e-4 * h * w)))
    det = ImageDetector(cfg).detect(image_rgb)
    gray = cv2.cvtColor(image_rgb, cv2.COLOR_RGB2GRAY)
    k = max(8, min(h, w) // 25)
    density = cv2.blur((cv2.Canny(gray, *cfg.canny_thresholds) > 0).astype(np.float32), (k, k))
    rich = (density >= EDGE_DENSITY).astype(np.uint8)
    contours, _ = cv2.findContours(rich, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
    edges = [c for c in contours if cv2.contourArea(c) >= k * k]
    return Found(det.centre_px, det.colour_area_px,
                 most_interesting(det, config.agent.interest_weights), finder.find(image_rgb),
                 edges)


def draw(image_rgb: np.ndarray, found: Found) -> np.ndarray:
    """The image with what was found drawn over it."""
    out = image_rgb.copy()
    h, w = out.shape[:2]
    thick = max(1, min(h, w) // 200)
    tint = out.copy()
    cv2.drawContours(tint, found.edge_regions, -1, CYAN, -1)
    out = cv2.addWeighted(tint, 0.25, out, 0.75, 0)
    cv2.drawContours(out, found.edge_regions, -1, CYAN, thick)
    for i, (c, a) in enumerate(zip(found.centre_px, found.area_px, strict=True)):
        colour = YELLOW if i == found.most_interesting else MAGENTA
        r = max(int(equal_area_radius(a)), 3)
        centre = tuple(int(round(v)) for v in c)
        cv2.circle(out, centre, r, colour, thick * (2 if colour == YELLOW else 1))
        cv2.drawMarker(out, centre, colour, cv2.MARKER_CROSS, 2 * r // 3 + 4, thick)
    for face in found.faces:
        x, y, bw, bh = face.box_px
        cv2.rectangle(out, (x, y), (x + bw, y + bh), GREEN, 2 * thick)
    scale = max(0.4, min(h, w) / 800)
    legend = [("bright colour", MAGENTA), ("most interesting (Eq. 1)", YELLOW),
              ("face", GREEN), ("edge-rich", CYAN)]
    for j, (text, colour) in enumerate(legend):
        org = (8, int((j + 1) * 22 * scale * 1.6))
        cv2.putText(out, text, org, cv2.FONT_HERSHEY_SIMPLEX, scale, (0, 0, 0), 3 * thick)
        cv2.putText(out, text, org, cv2.FONT_HERSHEY_SIMPLEX, scale, colour, thick)
    return out


def detect_files(paths: list[Path], out_dir: Path, config: Config,
                 face_method: str = "haar") -> list[tuple[Path, Found]]:
    """Write ``<name>_detected.png`` into ``out_dir`` for each image.

    Every image is read before anything is written, so a bad one leaves nothing behind.
    """
    images = [(Path(p), read_image(p)) for p in paths]
    if face_method == "template":
        from ..datasets import default_datasets

        finder = FaceFinder("template", face_template(default_datasets().face),
                            min_score=config.detector.face_min_score)
    else:
        smallest = min(min(img.shape[:2]) for _, img in images)
        finder = FaceFinder("haar", heights_px=(24, max(24, smallest)))
    written = []
    for path, image in images:
        found = find_all(image, config, finder)
        _, png = cv2.imencode(".png", cv2.cvtColor(draw(image, found), cv2.COLOR_RGB2BGR))
        target = Path(out_dir) / f"{path.stem}_detected.png"
        with atomic_path(target) as tmp:
            tmp.write_bytes(png.tobytes())
        written.append((target, found))
    return written
