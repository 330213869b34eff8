"""The image detector's passes over pixels, compiled (:mod:`.vision` is their public door).

One pass finds the bright-colour pixels and cuts them where the hue jumps; another counts, in
each region, the pixels of its inside that are edges and the pixels that moved. OpenCV does
the rest (the HSV and grey conversions, the connected components, Canny). Imports only the
plumbing.
"""

from __future__ import annotations

import numpy as np

from .._jit import jit

__all__ = ["bright_regions_into", "region_fractions"]


@jit
def _hue_jumps(hsv, y: int, x: int, y_before: int, x_before: int, split_deg: float) -> bool:
    d = abs(np.int64(hsv[y, x, 0]) - np.int64(hsv[y_before, x_before, 0]))
    return min(d, 180 - d) * 2 > split_deg  # OpenCV's hue: 0-179, two degrees per unit


@jit
def bright_regions_into(hsv, min_saturation: int, min_value: int, split_deg: float,
                        mask) -> tuple[int, int, int, int]:
    """``mask`` (H, W) uint8: 1 at the bright-colour pixels of ``hsv``, cut where hues jump.

    ``hsv`` is OpenCV's. Bright: saturation and value at least ``min_saturation`` and
    ``min_value`` (0-255). A bright pixel whose upper or left neighbour is bright too, with a
    hue more than ``split_deg`` away, is cut (0): it separates two touching objects. Returns
    the box of the 1s, ``(x0, y0, x1, y1)`` with ends excluded, or zeros if there is none.
    """
    flat, out = hsv.reshape(-1), mask.reshape(-1)
    least_s, least_v = np.uint8(min_saturation), np.uint8(min_value)
    for i in range(out.size):  # bytes without branches: it vectorises
        out[i] = np.uint8(flat[3 * i + 1] >= least_s) & np.uint8(flat[3 * i + 2] >= least_v)
    return _cut_hue_jumps(hsv, mask, split_deg)


@jit
def _cut_hue_jumps(hsv, bright, split_deg: float) -> tuple[int, int, int, int]:
    height, width = bright.shape
    x0, y0, x1, y1 = width, height, 0, 0
    above = np.zeros(width, np.bool_)  # the row above, as it was before its cuts
    above_any = False
    for y in range(height):
        any_here = np.uint8(0)
        for x in range(width):
            any_here |= bright[y, x]
        if not any_here:  # most rows
            if above_any:
                above[:] = False
            above_any = False
            continue
        left = False
        for x in range(width):
            here = bright[y, x] != 0
            if here and ((above[x] and _hue_jumps(hsv, y, x, y - 1, x, split_deg))
                         or (left and _hue_jumps(hsv, y, x, y, x - 1, split_deg))):
                bright[y, x] = 0
            elif here:
                x0, y0 = min(x0, x), min(y0, y)
                x1, y1 = max(x1, x + 1), max(y1, y + 1)
            above[x], left = here, here
        above_any = True
    if x1 == 0:
        return 0, 0, 0, 0
    return x0, y0, x1, y1


@jit
def _across(labels, box) -> np.ndarray:
    """Per pixel of ``box``: whether it and those within 2 along its row are in regions.

    Pixels outside the image do not count; every pixel outside ``box`` is in none.
    """
    x0, y0, x1, y1 = box
    width = labels.shape[1]
    across = np.zeros((y1 - y0, x1 - x0), np.bool_)
    for y in range(y0, y1):
        for x in range(x0, x1):
            if labels[y, x] == 0:
                continue
            full = True
            for u in range(max(x - 2, 0), min(x + 3, width)):
                full &= x0 <= u < x1 and labels[y, u] != 0
            across[y - y0, x - x0] = full
    return across


@jit
def region_fractions(labels, n: int, box, edges, gray, previous, threshold: int,
                     moved: bool) -> tuple[np.ndarray, np.ndarray]:
    """Per region 1..n of ``labels``: the fraction of its inside on ``edges``, and that moved.

    Every region lies in ``box`` (x0, y0, x1, y1, ends excluded). Its inside: its pixels whose
    5 x 5 square (in the image) is all in regions, OpenCV's erosion (the outline excluded: a
    plain ball has no texture). Moved: the grey level differs from ``previous`` by more than
    ``threshold``; all zeros unless ``moved``.
    """
    inside, on_edge = np.zeros(n + 1, np.int64), np.zeros(n + 1, np.int64)
    area, changed = np.zeros(n + 1, np.int64), np.zeros(n + 1, np.int64)
    x0, y0, x1, y1 = box
    height = labels.shape[0]
    across = _across(labels, box)  # the square's test in two passes: 10 reads, not 25
    for y in range(y0, y1):
        for x in range(x0, x1):
            k = labels[y, x]
            if k == 0:
                continue
            area[k] += 1
            if moved and abs(np.int64(gray[y, x]) - np.int64(previous[y, x])) > threshold:
                changed[k] += 1
            full = True
            for v in range(max(y - 2, 0), min(y + 3, height)):
                full &= y0 <= v < y1 and across[v - y0, x - x0]
            if full:
                inside[k] += 1
                on_edge[k] += edges[y, x] != 0
    edge, motion = np.zeros(n), np.zeros(n)
    for k in range(1, n + 1):
        edge[k - 1] = on_edge[k] / max(inside[k], 1)
        if moved:
            motion[k - 1] = changed[k] / max(area[k], 1)
    return edge, motion
