"""What the experimenter measures of a learner while it learns, beside the trial records.

The learning module's angle error at the caregiver's face: the angle between its output and the
command that centres the caregiver's target, over the data sets. Only the experimenter knows
the command; the robot never sees it.
"""

from __future__ import annotations

import numpy as np

from ..datasets import CaregiverDatasets
from ..rng import stream
from ..world.kinematics import angle_rad

__all__ = ["angle_deg", "angle_errors", "axis_errors_deg", "bias_of", "lm_errors_deg",
           "median_error_deg", "probe_sets"]


def probe_sets(ds: CaregiverDatasets, limit: int, seed: int) -> CaregiverDatasets:
    """The data sets the per-bin probe measures: all, or ``limit`` of them if there are more.

    Drawn once from ``seed``'s ``probe`` stream (the same for every cell of a run), in their
    order; 0: all. A run of 16,000 data sets probed 50 times measured the module on 800,000
    faces a cell; a median over 2,000 of them moves by a fraction of a degree.
    """
    if not limit or len(ds) <= limit:
        return ds
    keep = np.sort(stream(seed, "probe").choice(len(ds), limit, replace=False))
    return ds.subset(keep)


def angle_deg(a, b) -> np.ndarray:
    """The angle (deg) between each vector of ``a`` (..., k) and the vector ``b`` (k,)."""
    return np.rad2deg(angle_rad(a, b))


def _outputs(agent, ds: CaregiverDatasets) -> np.ndarray:
    """The module's output at each data set's face and head angle, (N, 2)."""
    if hasattr(agent, "lm_commands"):
        return agent.lm_commands(ds.views, ds.theta_face_rad)
    return np.array([agent.lm_command(f, t) for f, t in zip(ds.views, ds.theta_face_rad,
                                                             strict=True)])


def axis_errors_deg(agent, ds: CaregiverDatasets) -> tuple[float, float]:
    """Median horizontal and vertical error (deg): where a turn along the output ends.

    The head turned from the face along the module's direction, as far as the command to the
    target, lands ``e = |c| u / |u| - c`` from the target; the pan and tilt parts of ``e``
    are the horizontal and vertical errors (the developmental model's measure: Nagai, Asada,
    Hosoda 2006 report the horizontal learned before the vertical).
    """
    return _axis_errors_of(_outputs(agent, ds), ds)


def _axis_errors_of(u: np.ndarray, ds: CaregiverDatasets) -> tuple[float, float]:
    """:func:`axis_errors_deg` of the module's outputs ``u`` (N, 2)."""
    c = np.asarray(ds.command_rad, dtype=float)
    norm = np.maximum(np.linalg.norm(u, axis=1, keepdims=True), 1e-12)
    e = np.linalg.norm(c, axis=1, keepdims=True) * u / norm - c
    return tuple(float(np.median(np.rad2deg(np.abs(e[:, i])))) for i in (0, 1))


def angle_errors(agent, ds: CaregiverDatasets, outputs: np.ndarray | None = None) -> np.ndarray:
    """Per data set, the angle (deg) from the module's output to the command to the target.

    The output is taken at the face (``agent.lm_commands``, or ``agent.lm_command`` one face
    at a time; or ``outputs``, those outputs already taken), the command is the one that
    centres the target.
    """
    return _angle_errors_of(_outputs(agent, ds) if outputs is None else outputs, ds)


def _angle_errors_of(out: np.ndarray, ds: CaregiverDatasets) -> np.ndarray:
    """:func:`angle_errors` of the module's outputs ``out`` (N, 2).

    Row by row, as :func:`angle_deg` of each output and its command (the same bits), in
    one pass over the arrays.
    """
    out, c = np.asarray(out, dtype=float), np.asarray(ds.command_rad, dtype=float)
    dot = out[:, 0] * c[:, 0] + out[:, 1] * c[:, 1]
    norms = np.linalg.norm(out, axis=-1) * np.sqrt(c[:, 0] * c[:, 0] + c[:, 1] * c[:, 1])
    return np.rad2deg(np.arccos(np.clip(dot / norms, -1.0, 1.0)))


def median_error_deg(agent, ds: CaregiverDatasets) -> float:
    """The median of :func:`angle_errors`; NaN for an agent without a learning module."""
    if not hasattr(agent, "lm_command"):
        return float("nan")
    return float(np.median(angle_errors(agent, ds)))


def bias_of(u) -> float:
    """How alike the directions ``u`` (N, 2) are: the length of their unit vectors' mean.

    1: one direction whatever the face (a bias that ignores the face); near 0: spread out.
    """
    u = np.asarray(u, dtype=float)
    unit = u / np.maximum(np.linalg.norm(u, axis=1, keepdims=True), 1e-12)
    return float(np.linalg.norm(unit.mean(axis=0)))


def lm_errors_deg(agent, ds: CaregiverDatasets) -> tuple[float, float, float, float]:
    """:func:`median_error_deg`, :func:`axis_errors_deg` and the outputs' :func:`bias_of`.

    All from one pass of the module over the data sets' faces; NaN for an agent without a
    learning module.
    """
    if not hasattr(agent, "lm_command"):
        return float("nan"), float("nan"), float("nan"), float("nan")
    out = _outputs(agent, ds)
    return (float(np.median(_angle_errors_of(out, ds))), *_axis_errors_of(out, ds),
            bias_of(out))
