"""What the salient feature detector reports: the same structure from images or projection."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._arrays import floats
from ..errors import ArgumentError

__all__ = ["Detections", "equal_area_radius"]


@dataclass(frozen=True)
class Detections:
    """Salient objects found in one camera image.

    Attributes:
        centre_px: (n, 2) image positions (x right, y down; pixel centres on integers).
        colour_area_px: (n,) bright-colour area, the paper's f_col.
        edge: (n,) texture complexity, the paper's f_edge.
        motion: (n,) amount of motion, the paper's f_mot.
        image_size_px: (W, H) of the image they were found in.
    """

    centre_px: np.ndarray
    colour_area_px: np.ndarray
    edge: np.ndarray
    motion: np.ndarray
    image_size_px: tuple[int, int]

    def __post_init__(self) -> None:
        # the attention kernels read every column by the length of colour_area_px
        names = ("centre_px", "colour_area_px", "edge", "motion")
        c, a, e, m = self.centre_px, self.colour_area_px, self.edge, self.motion
        if type(c) is type(a) is type(e) is type(m) is np.ndarray and a.ndim == 1 and (
                c.shape == (len(a), 2) and e.shape == m.shape == a.shape) and (
                c.dtype.kind in "fiu" and a.dtype.kind in "fiu" and e.dtype.kind in "fiu"
                and m.dtype.kind in "fiu"):
            return  # the detectors' own output: checked at little cost
        for name in names:
            object.__setattr__(self, name, floats(name, getattr(self, name), None,
                                                  finite=False))
        n = len(self.colour_area_px) if self.colour_area_px.ndim == 1 else "n"
        for name, shape in zip(names[1:] + names[:1], [(n,), (n,), (n,), (n, 2)], strict=True):
            if getattr(self, name).shape != shape:
                raise ArgumentError(f"{name}: shape {getattr(self, name).shape}; expected "
                                    f"{shape}, one row per detection (n from colour_area_px)")

    def __len__(self) -> int:
        return len(self.colour_area_px)

    @property
    def image_centre_px(self) -> np.ndarray:
        """(c_x, c_y) of Eq. 2 and 3."""
        w, h = self.image_size_px
        return np.array([(w - 1) / 2, (h - 1) / 2])


def equal_area_radius(area_px) -> np.ndarray:
    """Radius of the circle of area ``area_px``: a disc's radius from its pixel count."""
    return np.sqrt(np.asarray(area_px, dtype=float) / np.pi)
