"""What the compiled loops take (the world, the robot, its state) and what they give back.

Plain named tuples of numbers and arrays, which numba compiles as records; :mod:`.cell`
packs them from the configuration and the agent. The loops (:mod:`._loop`,
:mod:`._rl_loop`) write one row per trial of :data:`~._loop.COLUMNS`, which
:func:`trial_records` turns into the trial records.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ...errors import ConfigError
from ..trial import END_FIRED, RECORD
from ._loop import COLUMNS

__all__ = ["LoopMechanisms", "LoopRobot", "LoopState", "LoopWorld", "placed", "trial_records"]


class LoopWorld(NamedTuple):
    """The world as the compiled loop takes it."""

    n_objects: int
    region: np.ndarray  # place_into's object region
    offset_m: np.ndarray
    limits_rad: np.ndarray  # pan lo, pan hi, tilt lo, tilt hi
    focal_px: float
    width_px: int
    height_px: int
    face_radius_m: float
    theta_face_rad: np.ndarray  # (K, 2) per data set
    target_m: np.ndarray  # (K, 3)
    face_m: np.ndarray  # (K, 3)
    faces: np.ndarray  # (K, pixels) float
    shuffle_faces: bool


class LoopRobot(NamedTuple):
    """The agent's mechanisms and options as the compiled loop takes them.

    Its learning module's are in the module's own state (``compiled_state``).
    """

    weights: np.ndarray  # Eq. 1's (a1, a2, a3)
    gain_rad_per_px: float
    d_th_px: float
    step_rad: float
    capture_rad: float  # line_capture_deg (0: none)
    max_steps: int
    gate_kind: int  # SIGMOID, CONSTANT, PERFORMANCE or EVIDENCE (agent/gates.py)
    gate_a: float  # the constant rate, the sigmoid's midpoint, the performance's agree_rad or
    # the evidence's floor
    gate_b: float  # the sigmoid's width, the performance's full agreement or the half evidence
    gate_window: float  # the performance's window (trials)
    gate_per_trial: bool
    vf_fallback_lm: bool
    vf_fallback_sweep: bool
    learning_target: int  # its index in LEARNING_TARGETS
    learn_from_vf: bool  # learn only from trials whose last move the visual controller made
    caregiver_judges: bool  # a taught model: learn only when the caregiver approves
    learn_unfound: bool  # a trial the module drove that found nothing teaches it (seen -1)
    learning: bool  # False: frozen, nothing learned and the learning time stands still


class LoopMechanisms(NamedTuple):
    """The robot's mechanisms as the loop of an agent's own trial kernels takes them.

    (:mod:`._rl_loop`; the agent's options are in its own state, ``compiled_state``.)
    """

    d_th_px: float  # Eq. 3's distance from the image centre, in pixels
    max_steps: int
    learning: bool  # False: frozen, nothing learned and the learning time stands still


class LoopState(NamedTuple):
    """The agent's face statistics (its own arrays) and the counters, changed in place."""

    mean: np.ndarray
    m2: np.ndarray
    faces_seen: np.ndarray  # (1,): FaceStandardiser.seen, the same array
    counters: np.ndarray  # learning time, records
    agreement: np.ndarray  # (1,): the performance gate's measure


def placed(code: int, world: LoopWorld) -> int:
    """A compiled loop's answer, or the error of a scene whose objects could not be placed."""
    if code == -1:
        raise ConfigError(
            f"objects: could not place {world.n_objects} objects apart within the "
            "object region; expected fewer objects, a wider region or smaller gaps")
    return code


def trial_records(rows: np.ndarray) -> dict[str, np.ndarray]:
    """The trial records (:data:`~.trial.RECORD`) of a compiled loop's rows (:data:`COLUMNS`)."""
    cols = dict(zip(COLUMNS, rows, strict=True))
    cols["success"] = cols["attended"] == cols["target"]
    cols["fired"] = cols["end"] == END_FIRED
    return {name: cols[name].astype(dtype) for name, (dtype, _) in RECORD.items()}
