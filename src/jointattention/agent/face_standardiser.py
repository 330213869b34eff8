"""The faces' running statistics (per-pixel mean and s.d.), and a face standardised by them.

Every learner that reads the face window standardises it so (the paper's network, the
population code, the reinforcement learner); the kernels (:func:`welford_update`,
:func:`standardise`) are the compiled engine's too.
"""

from __future__ import annotations

import math

import numpy as np

from .._arrays import rows
from .._jit import jit
from ..errors import ArgumentError

__all__ = ["NO_FACE_SEEN", "FaceStandardiser", "standardise", "welford_update"]

# transform's error before any face (the compiled loops raise it too)
NO_FACE_SEEN = "faces: the standardiser has seen no face; expected partial_fit before transform"


@jit
def welford_update(x, mean, m2, n_seen: int) -> None:
    """Add face ``x`` to the running mean and sum of squares; ``n_seen`` counts it already."""
    for i in range(len(x)):
        delta = x[i] - mean[i]
        mean[i] += delta / n_seen
        m2[i] += delta * (x[i] - mean[i])


@jit
def standardise(x, mean, m2, n_seen: int, min_std: float, out) -> None:
    """``out`` = (x - mean) / max(s.d., min_std), the s.d. of the faces seen so far."""
    for i in range(len(x)):
        out[i] = (x[i] - mean[i]) / max(math.sqrt(m2[i] / max(n_seen, 1)), min_std)


class FaceStandardiser:
    """Per-pixel running mean and standard deviation of the faces seen (Welford).

    The count of faces seen (``n_seen_``) is kept in a one-element array, :attr:`seen`: the
    compiled engine counts in it and a learning module's kernels read it, the same array.
    """

    def __init__(self, min_std: float = 8.0):
        self.min_std = min_std
        self.seen = np.zeros(1, np.int64)
        self.mean_, self.m2_ = np.zeros(0), np.zeros(0)  # sized by the first face

    @property
    def n_seen_(self) -> int:
        """Faces seen so far."""
        return int(self.seen[0])

    @n_seen_.setter
    def n_seen_(self, n: int) -> None:
        self.seen[0] = n

    def partial_fit(self, faces: np.ndarray) -> FaceStandardiser:
        """Add the faces (n, pixels) to the running statistics."""
        faces = rows("faces", faces, len(self.mean_) if self.n_seen_ else None)
        for x in faces:
            if self.n_seen_ == 0:
                self.mean_, self.m2_ = np.zeros_like(x), np.zeros_like(x)
            self.n_seen_ += 1
            welford_update(np.ascontiguousarray(x), self.mean_, self.m2_, self.n_seen_)
        return self

    def transform(self, faces: np.ndarray) -> np.ndarray:
        """The faces standardised: minus the mean, over the s.d. (at least ``min_std``)."""
        if not self.n_seen_:
            raise ArgumentError(NO_FACE_SEEN)
        x = rows("faces", faces, len(self.mean_))
        out = np.empty_like(x)
        for row, o in zip(x, out, strict=True):
            standardise(row, self.mean_, self.m2_, self.n_seen_, float(self.min_std), o)
        return out if np.ndim(faces) == 2 else out[0]

    def statistics(self, n_pixels: int) -> tuple[np.ndarray, np.ndarray]:
        """``mean_`` and ``m2_``, which the compiled loops update in place.

        Zeros of ``n_pixels`` before the first face: made once, so that every caller holds
        the same arrays.
        """
        if self.n_seen_ == 0:
            if self.mean_.shape != (n_pixels,):
                self.mean_, self.m2_ = np.zeros(n_pixels), np.zeros(n_pixels)
            self.mean_[:], self.m2_[:] = 0.0, 0.0
        return self.mean_, self.m2_
