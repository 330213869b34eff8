"""What the robot computes from a face window before it learns: features that carry the pose.

Two parts, both the robot's own arithmetic on its own window:

- the window's grey levels, contrast-normalised (minus the window's own mean, over its own
  standard deviation), so that skin tone, exposure and the key light's strength do not shift
  every input at once;
- a histogram of gradient orientations (HOG, Dalal and Triggs 2005) over a grid of cells:
  per cell, the gradient magnitude summed into ``n_orientations`` signed orientation bins
  (each gradient split between its two nearest bins), the whole histogram scaled to unit
  length. Edges (the hairline, the eyes, the nose, the jaw against the wall) move with the
  head's pose, and their orientation does not depend on how bright the skin or the hair is.

The result is ``pixels / sqrt(pixels)`` followed by the histogram, so both parts have unit
length. :func:`face_features_into` is the compiled kernel; :func:`face_features` its wrapper
for windows (N, H, W).
"""

from __future__ import annotations

import math

import numpy as np

from ..._arrays import floats
from ..._jit import jit
from ...errors import ArgumentError

__all__ = ["face_features", "face_features_into", "n_features", "n_window_features"]


def n_features(face_size_px: tuple[int, int], cell_px: int, n_orientations: int,
               pixels: bool = True, hog: bool = True) -> int:
    """Length of the feature vector of a (width, height) window, with the parts asked for."""
    w, h = face_size_px
    return int(n_window_features(h, w, cell_px, n_orientations, bool(pixels), bool(hog)))


@jit
def n_window_features(height: int, width: int, cell_px: int, n_orientations: int,
                      pixels: bool, hog: bool) -> int:
    """:func:`n_features` of a ``height`` x ``width`` window, for kernels."""
    return height * width * pixels + (width // cell_px) * (height // cell_px) * n_orientations * hog


@jit
def face_features_into(face, height: int, width: int, cell_px: int, n_orientations: int,
                       pixels: bool, hog: bool, out) -> None:
    """The features of one face window ``face`` (height * width grey levels, row-major).

    Written into ``out`` (:func:`n_features` long): the grey levels if ``pixels``, then the
    histogram if ``hog``.
    """
    n = height * width
    if pixels:
        _pixels_into(face, out[:n])
    if hog:
        _hog_into(face, height, width, cell_px, n_orientations, out[n * pixels:])


@jit
def _pixels_into(face, out) -> None:
    """The grey levels minus their mean, over their s.d. (at least 1 grey level), / sqrt(n)."""
    n = len(face)
    mean = 0.0
    for i in range(n):
        mean += face[i]
    mean /= n
    var = 0.0
    for i in range(n):
        var += (face[i] - mean) ** 2
    scale = 1.0 / (max(math.sqrt(var / n), 1.0) * math.sqrt(n))  # a flat window stays ~0
    for i in range(n):
        out[i] = (face[i] - mean) * scale


@jit
def _hog_into(face, height: int, width: int, cell_px: int, n_orientations: int, hist) -> None:
    """The histogram of gradient orientations over the cells, of unit length."""
    rows, cols = height // cell_px, width // cell_px
    hist[:] = 0.0
    bin_width = 2 * math.pi / n_orientations
    for r in range(rows * cell_px):
        for c in range(cols * cell_px):
            # central differences, one-sided at the window's border
            c0, c1 = max(c - 1, 0), min(c + 1, width - 1)
            r0, r1 = max(r - 1, 0), min(r + 1, height - 1)
            gx = (face[r * width + c1] - face[r * width + c0]) / (c1 - c0)
            gy = (face[r1 * width + c] - face[r0 * width + c]) / (r1 - r0)
            mag = math.hypot(gx, gy)
            if mag == 0.0:
                continue
            pos = (math.atan2(gy, gx) + math.pi) / bin_width - 0.5
            lo = math.floor(pos)
            frac = pos - lo
            cell = ((r // cell_px) * cols + c // cell_px) * n_orientations
            hist[cell + int(lo) % n_orientations] += mag * (1.0 - frac)
            hist[cell + int(lo + 1) % n_orientations] += mag * frac
    norm = 0.0
    for i in range(len(hist)):
        norm += hist[i] * hist[i]
    norm = max(math.sqrt(norm), 1e-12)
    for i in range(len(hist)):
        hist[i] /= norm


def face_features(faces: np.ndarray, cell_px: int = 5, n_orientations: int = 12,
                  pixels: bool = True, hog: bool = True) -> np.ndarray:
    """The features of face windows (N, H, W) or (H, W): (N, :func:`n_features`) or (n,)."""
    rows = floats("faces", faces, None, what="grey levels: face windows")
    one = rows.ndim == 2
    rows = rows[None] if one else rows
    if rows.ndim != 3 or 0 in rows.shape:
        raise ArgumentError(f"faces: shape {np.shape(faces)}; expected (N, H, W) or (H, W) "
                            "grey levels: face windows")
    for name, value in (("cell_px", cell_px), ("n_orientations", n_orientations)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
            raise ArgumentError(f"{name}: {value!r}; expected a positive integer")
    n, h, w = rows.shape
    out = np.empty((n, n_features((w, h), cell_px, n_orientations, pixels, hog)))
    for face, o in zip(rows.reshape(n, -1), out, strict=True):
        face_features_into(face, h, w, cell_px, n_orientations, pixels, hog, o)
    return out[0] if one else out
