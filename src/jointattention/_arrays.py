"""Checks at the doors of the compiled kernels.

A compiled kernel reads its arrays by the sizes it is given and checks no bound: a face window
of the wrong size or a point with two coordinates makes it read past an array (a wrong
result, or a crash of the interpreter). Every public function that hands arrays to a kernel
passes them through :func:`floats` first, which returns them in the kernel's layout or raises
one :class:`~jointattention.errors.ArgumentError` line naming the argument (docs/bad-input.md).
"""

from __future__ import annotations

import numpy as np

from .errors import ArgumentError

__all__ = ["angles", "flat", "floats", "rows", "same_lengths", "views", "windows"]


def _shape_text(shape: tuple | None) -> str:
    if shape is None:
        return "an array of"
    return "(" + ", ".join("n" if d is None else str(d) for d in shape) + ("," if len(
        shape) == 1 else "") + ")"


def floats(name: str, value, shape: tuple | None, *, what: str = "numbers",
           finite: bool = True, kinds: str = "biuf") -> np.ndarray:
    """``value`` as a C-contiguous float64 array of ``shape`` (None: any length; any shape).

    Refused (ArgumentError naming ``name``) if it is not numeric (its dtype's kind not in
    ``kinds``: "uf" refuses booleans too), has another shape, or holds NaN or infinity (unless
    ``finite`` is False).
    """
    a = None
    if not isinstance(value, (str, bytes)):
        try:
            a = np.asarray(value)
        except (TypeError, ValueError, OverflowError):  # ragged lists, huge integers
            a = None
    ok = a is not None and a.dtype.kind in kinds and (shape is None or (
        a.ndim == len(shape) and all(d is None or d == n
                                     for d, n in zip(shape, a.shape, strict=True))))
    if not ok or (finite and not np.isfinite(a).all()):
        got = (f"shape {a.shape}, dtype {a.dtype}" if a is not None else
               f"a {type(value).__name__}")
        raise ArgumentError(f"{name}: {got}; expected {_shape_text(shape)} "
                            f"{'finite ' if finite else ''}{what}")
    # ascontiguousarray makes a 0-d array 1-d; a number stays a number
    return np.ascontiguousarray(a, dtype=float).reshape(a.shape)


def windows(name: str, value, face_size_px, n: int | None = 0) -> np.ndarray:
    """A face window (H, W) of grey levels; with ``n`` not 0, ``n`` of them (n, H, W).

    ``face_size_px`` is the robot's (W, H).
    """
    w, h = face_size_px
    return floats(name, value, (h, w) if n == 0 else (n, h, w),
                  what=f"grey levels: face windows of {h} x {w} pixels")


def views(name: str, value, body, n: int | None = 0) -> np.ndarray:
    """What ``body`` keeps of a look at the caregiver, flat: (view_size,), or (n, view_size).

    Without an eye window a view is its face window (H, W) (or (n, H, W)), as :func:`windows`
    takes it; with one, the face window's grey levels then the eye window's, flat
    (:class:`~jointattention.agent.protocol.Body`).
    """
    if body.eye_size_px is None:
        out = windows(name, value, body.face_size_px, n)
        return out.reshape(-1) if n == 0 else out.reshape(len(out), -1)
    (w, h), (ew, eh) = body.face_size_px, body.eye_size_px
    return floats(name, value, (body.view_size,) if n == 0 else (n, body.view_size),
                  what=f"grey levels: views of a {h} x {w} face window then a {eh} x {ew} "
                       "eye window, flat")


def flat(name: str, value, size: int) -> np.ndarray:
    """``value`` of any shape holding ``size`` numbers, as a 1-D array (a face window)."""
    a = floats(name, value, None).reshape(-1)
    if len(a) != size:
        raise ArgumentError(f"{name}: {len(a)} numbers; expected {size}")
    return a


def rows(name: str, value, n_cols: int, n: int | None = None) -> np.ndarray:
    """Rows of ``n_cols`` numbers (a 1-D ``value`` is one row): (n, n_cols)."""
    try:
        one = np.ndim(value) == 1
    except ValueError:  # a ragged list
        one = False
    return floats(name, np.atleast_2d(value) if one else value, (n, n_cols))


def angles(name: str, value, n: int | None = 0) -> np.ndarray:
    """A head angle (pan, tilt) in radians, (2,); with ``n`` not 0, ``n`` of them (n, 2)."""
    shape = (2,) if n == 0 else (n, 2)
    return floats(name, value, shape, what="angles (pan, tilt) in radians")


def same_lengths(**arrays) -> None:
    """Refuse 1-D arrays (or rows) of different lengths that a kernel reads by one length."""
    lengths = {k: len(v) for k, v in arrays.items()}
    if len(set(lengths.values())) > 1:
        raise ArgumentError(", ".join(f"{k}: {n}" for k, n in lengths.items())
                            + " entries; expected one entry per object in each")
