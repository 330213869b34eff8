"""Where each eye lies in an eye window: the robot finds the sockets and cuts around them.

An eye window is cut around where the robot's eye finder puts the eyes, and a finder errs by
a tenth of an eye distance or more (docs/results/people/eye_placement.md). A window that moves
by that much moves the irises across the window more than a gaze turn of 20 degrees does, so a
learner that reads the window's pixels reads where the window was cut. Here the robot finds each
eye's socket (the visible eyeball: the white, with the iris somewhere in it) in its half of the
window, and cuts a patch around the socket: where the iris lies in the patch then says where the
eye turns, wherever the window was cut.

The socket is found by a bank of drawn eyes (a bright disc of radius R on a mid-grey ground,
with a dark iris disc of radius 0.6 R at an offset from its centre, on a grid of offsets and
three radii), each matched anywhere in the half-window by normalised cross-correlation
(OpenCV's ``TM_CCOEFF_NORMED``: a brighter or darker eye, skin or iris matches as well). The
best matches of the bank place the socket, to a fraction of a pixel (a parabola through each
peak on each axis). Matching eyes whose iris lies anywhere keeps the iris from pulling the
place toward it. Only the robot's own window is read.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

__all__ = ["FINDERS", "IRIS_RATIO", "MATCH_SCALE", "SOCKET_RADII", "eye_patches", "socket_bank",
           "socket_centre", "sockets"]

# Socket radii of the bank in eye distances (centre to centre): an eyeball's visible disc is
# about a fifth of an eye distance, and eye size and spacing vary by about 15% each among people.
SOCKET_RADII = (0.146, 0.1875, 0.229)
IRIS_RATIO = 0.6  # the iris's radius over the socket's
FINDERS = ("bank", "net")  # what finds the sockets: the drawn eyes, or the shipped network
_N_OFFSETS = 7  # iris offsets per axis of the bank, across +-0.5 R (the outer rows not vertically)
_SUPERSAMPLE = 4  # each drawn eye is drawn this much finer, then averaged down
# How much worse a drawn eye may match and still count (e-fold): in the people world, a window
# misplaced by 0.1 eye distances then moves the iris in its patch by a median 0.82 px, against
# 0.98 px for the best match alone (90th percentile 2.8 px against 3.7 px).
MATCH_SCALE = 0.02


def _drawn_eye(radius_px: float, dx_px: float, dy_px: float) -> np.ndarray:
    """One eye of the bank: the socket bright (1), the iris dark (0), the ground 0.5."""
    import cv2

    n = int(np.ceil(2.4 * radius_px)) | 1
    c = (n - 1) / 2
    y, x = (np.mgrid[0:n * _SUPERSAMPLE, 0:n * _SUPERSAMPLE] + 0.5) / _SUPERSAMPLE - 0.5
    socket = (x - c) ** 2 + (y - c) ** 2 <= radius_px ** 2
    iris = (x - c - dx_px) ** 2 + (y - c - dy_px) ** 2 <= (IRIS_RATIO * radius_px) ** 2
    drawn = np.where(socket, np.where(iris, 0.0, 1.0), 0.5).astype(np.float32)
    return cv2.resize(drawn, (n, n), interpolation=cv2.INTER_AREA)


@lru_cache(maxsize=8)
def socket_bank(px_per_eye_distance: float) -> tuple[np.ndarray, ...]:
    """The drawn eyes for a window of ``px_per_eye_distance`` pixels per eye distance."""
    bank = []
    for r in SOCKET_RADII:
        radius_px = r * px_per_eye_distance
        offsets = np.linspace(-0.5, 0.5, _N_OFFSETS) * radius_px
        bank += [_drawn_eye(radius_px, dx, dy) for dy in offsets[1:-1] for dx in offsets]
    return tuple(bank)


def _peak(response: np.ndarray) -> tuple[float, float, float]:
    """The largest response and where it lies, to a fraction of a pixel (x, y)."""
    y, x = np.unravel_index(int(np.argmax(response)), response.shape)

    def vertex(a: float, b: float, c: float) -> float:
        curvature = a - 2 * b + c
        return 0.0 if curvature >= 0 else 0.5 * (a - c) / curvature

    dx = vertex(*response[y, x - 1:x + 2]) if 0 < x < response.shape[1] - 1 else 0.0
    dy = vertex(*response[y - 1:y + 2, x]) if 0 < y < response.shape[0] - 1 else 0.0
    return float(response[y, x]), x + dx, y + dy


def socket_centre(half: np.ndarray, bank: tuple[np.ndarray, ...]) -> tuple[float, float]:
    """Where the socket's centre lies in ``half`` (x, y px): the drawn eyes' places, weighted.

    Each drawn eye's best place, weighted by exp(its match / :data:`MATCH_SCALE`) over the
    best's: a drawn eye that wins by a hair does not move the place by a pixel.
    """
    import cv2

    fits = []
    for drawn in bank:
        if drawn.shape[0] > half.shape[0] or drawn.shape[1] > half.shape[1]:
            continue
        value, x, y = _peak(cv2.matchTemplate(half, drawn, cv2.TM_CCOEFF_NORMED))
        fits.append((value, x + (drawn.shape[1] - 1) / 2, y + (drawn.shape[0] - 1) / 2))
    fits = np.array(fits).reshape(-1, 3)
    if not np.isfinite(fits[:, 0]).any() or fits[:, 0].max() <= 0:  # a flat half: no eye
        return (half.shape[1] - 1) / 2, (half.shape[0] - 1) / 2
    weight = np.exp((fits[:, 0] - fits[:, 0].max()) / MATCH_SCALE)
    x, y = weight @ fits[:, 1:] / weight.sum()
    return float(x), float(y)


def _bank_halves(grey: np.ndarray, span: float) -> tuple[list[np.ndarray], list]:
    """Each half of ``grey`` and the bank's socket in it (in that half's pixels)."""
    half = grey.shape[1] // 2
    bank = socket_bank(grey.shape[1] / span)
    halves = [np.ascontiguousarray(h) for h in (grey[:, :half], grey[:, half:])]
    return halves, [socket_centre(h, bank) for h in halves]


def sockets(window: np.ndarray, span: float, finder: str = "bank") -> np.ndarray:
    """Both sockets (2 eyes, x y) in ``window``'s pixels, the left eye first.

    ``finder``: ``"bank"``, the drawn eyes matched in each half (:func:`socket_centre`), or
    ``"net"``, the shipped eye-socket network (:mod:`.socket_net`), which reads the whole
    window (fitted for the windows of ``docs/results/people/sockets.toml``).
    """
    grey = np.asarray(window, np.float32)
    if finder == "net":
        from .socket_net import shipped

        return shipped().predict(grey[None])[0]
    if finder != "bank":
        raise ValueError(f"finder {finder!r}: expected one of {', '.join(FINDERS)}")
    found = np.array(_bank_halves(grey, span)[1])
    found[1, 0] += grey.shape[1] // 2
    return found


def eye_patches(window: np.ndarray, span: float, patch_px: int, finder: str = "bank"
                ) -> np.ndarray:
    """Each eye's ``patch_px`` square patch, cut around its socket; the two side by side.

    ``window``: an eye window (height, width) of grey levels holding both eyes, ``span`` eye
    distances wide, the left eye in its left half; ``finder``: what finds the sockets
    (:func:`sockets`). Returns (patch_px, 2 * patch_px) uint8.
    """
    import cv2

    grey = np.asarray(window, np.float32)
    if finder == "bank":  # each half's socket, cut from that half
        parts, centres = _bank_halves(grey, span)
    else:
        parts, centres = (grey, grey), [tuple(map(float, c)) for c in sockets(grey, span, finder)]
    patches = [cv2.getRectSubPix(part, (patch_px, patch_px), centre)
               for part, centre in zip(parts, centres, strict=True)]
    return np.clip(np.rint(np.hstack(patches)), 0, 255).astype(np.uint8)
