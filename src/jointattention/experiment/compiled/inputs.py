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

__all__ = ["LoopDevelopment", "LoopMemory", "LoopRobot", "LoopState", "LoopWorld", "placed",
           "trial_records"]


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
    """The agent's mechanisms and options as the compiled loop takes them."""

    weights: np.ndarray  # Eq. 1's (a1, a2, a3)
    gain_rad_per_px: float
    d_th_px: float
    step_rad: float
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
    n_passes: int  # back-propagation passes over a trial's samples
    theta_mid_rad: np.ndarray
    theta_half_rad: np.ndarray
    min_std: float
    learning_rate: float
    momentum: float
    caregiver_judges: bool  # the teacher: learn only when the caregiver approves
    learning: bool  # False: frozen, nothing learned and the learning time stands still


class LoopState(NamedTuple):
    """The learned state (the agent's own arrays) and the counters, changed in place."""

    w1: np.ndarray
    b1: np.ndarray
    w2: np.ndarray
    b2: np.ndarray
    v1: np.ndarray
    vb1: np.ndarray
    v2: np.ndarray
    vb2: np.ndarray
    mean: np.ndarray
    m2: np.ndarray
    counters: np.ndarray  # learning time, faces seen, updates, records, trials kept, codes,
    # places left out
    agreement: np.ndarray  # (1,): the performance gate's measure
    caregiver: np.ndarray  # (2,): her criterion (rad) and rate of approving


class LoopMemory(NamedTuple):
    """The episodic memory (models.memory.episodic), its options and kept trials (changed in place).

    The loop takes None instead for a learner without one: numba then prunes the memory's
    branches, and compiles none of its kernels for the network learners.
    """

    projection: np.ndarray  # the face code
    lo_rad: np.ndarray
    cell_rad: float
    k: int
    radius_rad: float
    in_view: bool  # keep every object in view, not only the attended one
    codes: np.ndarray  # the kept trials (models/memory/_recall.py)
    counts: np.ndarray
    links: np.ndarray
    aims: np.ndarray
    base: np.ndarray
    leave_out_empty: bool  # leave out a recalled place found empty (models/memory/_left_out.py)
    left_codes: np.ndarray
    left_aims: np.ndarray
    pass_over: bool  # visual attention passes over objects at places left out
    drop_left_out: bool  # nor does the memory keep their places
    recall_again: bool  # a place left out, the face's next place is recalled at once
    saccade_rad: float  # the longest move to a recalled place (memory.saccade); 0: one step


class LoopDevelopment(NamedTuple):
    """The developmental model's caregiver, whose criterion narrows, and its blurred face.

    None for the other models, as :class:`LoopMemory`.
    """

    criterion_level: float  # models.developmental.caregiver_update's
    criterion_window_trials: float
    criterion_shrink: float
    blur_start_px: float  # the visual development (0: none)
    blur_sharp_steps: float
    face_width_px: int
    face_height_px: int


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
