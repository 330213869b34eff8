"""The robot's configuration: the mechanisms every model shares, and its image detector."""

from __future__ import annotations

from dataclasses import dataclass

from .._fields import Section, param

__all__ = ["AgentConfig", "DetectorConfig"]


@dataclass(frozen=True)
class AgentConfig(Section):
    """The robot's embedded mechanisms (paper, section III) that every model shares.

    Visual attention (Eq. 1, 2), the internal evaluator (Eq. 3), the step length and the trial's
    step limit. What learns is the ``[model]`` section.
    """

    interest_weights: tuple[float, float, float] = param(
        (1.0, 0.0, 0.0), "(a1, a2, a3) of Eq. 1: colour area, edge complexity, motion", lo=0)
    vf_gain_rad_per_px: float = param(
        0.0025, "gain g of the visual feedback controller (Eq. 2)", lo=0, hi=0.1)
    d_th_fraction: float = param(
        1 / 6, "evaluator threshold d_th as a fraction of the image width W (Eq. 3: W/6)",
        lo=0.01, hi=1)
    lm_step_deg: float = param(4.0, "length of one step of the learning module", lo=0.1, hi=30)
    max_steps: int = param(40, "step limit of a trial", lo=1, hi=10000)
    line_capture_deg: float = param(
        0.0, "beyond the paper: a move along the learning module's line (or the oracle's) "
        "goes instead, in one move of visual feedback (Eq. 2), to the first object in view "
        "ahead along the line and at most this far from it (0: the paper's steps along the "
        "line until Eq. 3 fires)", lo=0, hi=90)

    def d_th_px(self, image_width_px: int) -> float:
        """The internal evaluator's radius (Eq. 3): d_th = W * d_th_fraction."""
        return image_width_px * self.d_th_fraction


@dataclass(frozen=True)
class DetectorConfig(Section):
    """The robot's image-based salient feature detector (OpenCV).

    Used in rendered mode and by ``jointattention detect``. The world paints objects with HSV
    saturation and value of at least 0.85 and everything else below 0.8 saturation, hence the colour
    thresholds.
    """

    min_saturation: float = param(
        0.8, "least HSV saturation of a bright-colour pixel (0-1)", lo=0, hi=1)
    min_value: float = param(0.3, "least HSV value (brightness) of a bright-colour pixel (0-1)",
                             lo=0, hi=1)
    hue_split_deg: float = param(
        20.0, "hue step between neighbouring pixels that separates two touching objects",
        lo=1, hi=180)
    min_area_px: int = param(20, "least area of a bright-colour region kept as an object",
                             lo=1)
    canny_thresholds: tuple[float, float] = param(
        (60.0, 150.0), "Canny's hysteresis thresholds for edge complexity (f_edge)", lo=0,
        hi=1000)
    motion_threshold: int = param(
        15, "least grey-level change between frames counted as motion (f_mot)", lo=0, hi=255)
    face_min_score: float = param(
        0.7, "least normalised correlation of a template match accepted as a face (the "
        "simulated caregiver scores 0.8-0.9, a blank wall up to 0.56)", lo=-1,
        hi=1)
