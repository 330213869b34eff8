"""The episodic learning module of the bootstrap agent (``learner = "memory"``).

Visual attention, the evaluator, the gate and the readings are the paper's
(:class:`~..bootstrap.BootstrapAgent`, which composes this module); the module is an
:class:`~.episodic.EpisodicMemory`. At the start of a trial it recalls, from
the caregiver's face, the place to look at; its command is one step from the head angle toward
that place (``memory.saccade``: the whole way there, in moves as long as visual feedback's
longest). A trial the evaluator ends is kept as (face code, place): the place is the attended
object's (``object_direction``: the final head angle plus the visual controller's command that
centres it) or the final head angle (``final_direction``); with ``memory.keep = "in_view"`` (the
default) every other object in the last image is kept too, at its place. With
``memory.leave_out_empty``, a recalled place that the head reaches and finds empty is left out
of that face's recalls (:meth:`MemoryModule.observe`, :mod:`._left_out`).
"""

from __future__ import annotations

import numpy as np

from ..._jit import jit
from ...agent.attention import largest_feedback_rad
from ...agent.detections import Detections
from ...agent.moves import MAX_PLACES, place_step
from ...agent.protocol import Outcome
from ._trial import EVIDENCE, KERNELS, RECALLED, SUPPORT, MemoryArrays
from .episodic import (
    EpisodicMemory,
    code_distances_into,
    face_code_into,
    left_out_of,
    recall_at_distances,
)

__all__ = ["MemoryModule", "recall_commands_into"]


_BATCH = 32  # faces whose distances are measured in one pass over the codes


@jit
def recall_commands_into(faces, thetas, projection, codes, counts, links, aims, base,
                         n_stored, n_codes, lo_rad, cell_rad, k_nearest, radius_rad, left_codes,
                         left_aims, n_left, step_rad, saccade_rad, out) -> None:
    """One move toward the place recalled for each face window (K, pixels), into ``out``.

    From each head angle ``thetas`` (K, 2); no step for a face with no place recalled. A face
    whose code is the one before's (e.g. a blank face at many head angles) is not recalled
    again: the recall depends on the code alone (and the places left out of its recalls). The
    distances of a batch of faces are measured together (:func:`code_distances_into`: the
    same bits as one by one).
    """
    n_code = projection.shape[1]
    batch, last, aim = np.empty((_BATCH, n_code)), np.empty(n_code), np.empty(2)
    new, d2 = np.empty(_BATCH, np.int64), np.empty((_BATCH, n_codes))
    support = -1.0
    for r0 in range(0, len(faces), _BATCH):
        r1 = min(r0 + _BATCH, len(faces))
        for r in range(r0, r1):
            face_code_into(faces[r], projection, batch[r - r0])
        n_new = 0  # the faces whose code differs from the one before's
        for r in range(r0, r1):
            prev = last if r == r0 else batch[r - r0 - 1]
            if r == 0 or not np.array_equal(batch[r - r0], prev):
                new[n_new] = r - r0
                n_new += 1
        if n_new:
            code_distances_into(batch[new[:n_new]], codes, n_codes, d2)
        i = 0
        for r in range(r0, r1):
            if i < n_new and new[i] == r - r0:
                left_out = left_out_of(batch[r - r0], left_codes, left_aims, n_left)
                support, _ = recall_at_distances(d2[i], counts, links, aims, base, n_stored,
                                                 n_codes, lo_rad, cell_rad, k_nearest,
                                                 radius_rad, left_out, aim)
                i += 1
            if support < 0:
                out[r, 0], out[r, 1] = 0.0, 0.0
            else:
                out[r, 0], out[r, 1] = place_step(aim[0] - thetas[r, 0],
                                                  aim[1] - thetas[r, 1], step_rad, saccade_rad)
        last[:] = batch[r1 - r0 - 1]


class MemoryModule:
    """The bootstrap agent's learning module as an episodic memory.

    Args:
        host: the bootstrap agent it serves (its body, options, step length, random steps
            and the trial's places).
        rng: the generator left after the agent's streams: one more split, for the face
            code's projection.

    It answers :class:`~..network.module.NetworkModule`'s calls, and declares its part of a
    trial as compiled kernels (:attr:`kernels`, over :meth:`compiled_state`; see
    :class:`~jointattention.agent.protocol.ModuleKernels`), which those of a trial call.

    Attributes:
        memory: the memory.
        support_: the support of the place recalled for the current trial's face (-1 before
            anything is kept).
        evidence_: that place's evidence, in trials (the evidence gate's measure).
    """

    kernels = KERNELS  # its part of a trial, for the compiled engine

    def __init__(self, host, rng: np.random.Generator):
        self.host = host
        (code_rng,) = rng.spawn(1)
        body = host.body
        self.memory = EpisodicMemory(body.view_size, host.options.memory,
                                     body.joint_limits_rad, code_rng)
        self._code, self._aim = np.empty(host.options.memory.code_dims), np.empty(2)
        self._trial = np.array([0.0, 0.0, -1.0])  # recalled, evidence, support (_trial.py)
        self._places, self._mine = np.empty((MAX_PLACES, 2)), np.empty((0, 2))
        self._state: MemoryArrays | None = None  # the trial's (begin makes it)

    @property
    def support_(self) -> float:
        """The support of the place recalled for the current trial's face."""
        return float(self._trial[SUPPORT])

    @property
    def evidence_(self) -> float:
        """That place's evidence, in trials (the evidence gate's measure)."""
        return float(self._trial[EVIDENCE])

    @property
    def _aim_rad(self) -> np.ndarray | None:
        """The place recalled for the current trial's face; None without one."""
        return self._aim.copy() if self._trial[RECALLED] else None

    @property
    def saccade_rad(self) -> float:
        """The longest move to a recalled place: visual feedback's with ``memory.saccade``.

        0 without: one step at a time.
        """
        if not self.memory.options.saccade:
            return 0.0
        return largest_feedback_rad(*self.host.body.image_size_px,
                                    self.host.mechanisms.vf_gain_rad_per_px)

    @property
    def learn_rng(self) -> np.random.Generator:
        """The stream its ``learn`` kernel is handed: the agent's moves (it draws nothing)."""
        return self.host.move_rng

    def compiled_state(self, n_faces: int = 0) -> MemoryArrays:
        """The module's state as the kernels take it: the memory's own arrays (see ``sync``).

        For ``n_faces`` faces (ids), what a face's trial start computes is kept: its recall
        while frozen, its code while learning.
        """
        # what the module does by the agent's options, what the memory keeps by its own
        m, o, learning = self.memory, self.host.options.memory, self.host.learning
        if len(self._mine) != len(m.left_aims_):  # a memory of another capacity or code
            self._mine = np.empty((len(m.left_aims_), 2))
        if len(self._code) != m.projection.shape[1]:
            self._code = np.empty(m.projection.shape[1])
        n_recalled, n_coded = (0, n_faces) if learning else (n_faces, 0)
        return MemoryArrays(
            m.projection, m.lo_rad, float(m.cell_rad), int(m.options.k_nearest),
            float(m.radius_rad),
            o.keep == "in_view", *m.kept_arrays()[:5], o.leave_out_empty, *m.left_arrays()[:2],
            o.pass_over_left_out, o.drop_left_out, o.recall_again, float(self.saccade_rad),
            np.array([m.n_stored_, m.n_codes_, m.n_left_, 0], np.int64), self._code, self._aim,
            self._trial, self._mine, self._places, np.zeros(n_recalled, np.int8),
            np.empty((n_recalled, 4)), np.zeros(n_coded, np.bool_),
            np.empty((n_coded, len(self._code))))

    def sync(self, state: MemoryArrays) -> None:
        """Take back the counters the kernels moved (trials kept, codes, places left out)."""
        m = self.memory
        m.n_stored_, m.n_codes_, m.n_left_ = (int(c) for c in state.counters[:3])

    def begin(self, face: np.ndarray, theta_rad: np.ndarray) -> None:
        """Recall the place for the caregiver's face."""
        self._state = self.compiled_state()
        self.kernels.begin(self._state, np.ascontiguousarray(face, dtype=float), -1,
                           float(theta_rad[0]), float(theta_rad[1]), self.host.learning)

    def observe(self, det: Detections, theta_rad) -> np.ndarray | None:
        """Leave the recalled place out if the head found it empty; what attention passes over.

        While learning (:mod:`._left_out`): with ``memory.leave_out_empty``
        the trial then has no recalled place, and no evidence for the gate (with
        ``memory.recall_again``, the face's next place and its evidence); with
        ``memory.pass_over_left_out`` the answer flags the detections at the face's places left
        out (None: attention may take any).
        """
        host, s = self.host, self._state
        cx, cy = (float(c) for c in det.image_centre_px)
        centre_px = np.ascontiguousarray(det.centre_px, dtype=float)
        pan, tilt = float(theta_rad[0]), float(theta_rad[1])
        gain = float(host.mechanisms.vf_gain_rad_per_px)
        self.kernels.observe(s, pan, tilt, host.step_rad, centre_px, cx, cy, gain, host.learning)
        self.sync(s)
        passed = np.zeros(len(centre_px), dtype=bool)
        if not self.kernels.passed_over(s, pan, tilt, centre_px, cx, cy, gain, host.learning,
                                        passed):
            return None
        return passed

    def step(self, theta_rad) -> np.ndarray:
        """A move toward the recalled place; a random step while nothing is kept."""
        return np.array(self.kernels.command(self._state, float(theta_rad[0]),
                                             float(theta_rad[1]), self.host.step_rad,
                                             self.host.move_rng))

    def direction(self, theta_rad) -> np.ndarray:
        """A move toward the recalled place; none while nothing is kept."""
        return np.array(self.kernels.direction(self._state, float(theta_rad[0]),
                                               float(theta_rad[1]), self.host.step_rad))

    def learn(self, outcome: Outcome, thetas: np.ndarray, steps: np.ndarray) -> int:
        """Keep the trial's place; returns the number of places kept.

        With ``memory.keep = "in_view"`` the places of the other objects in the last image are
        kept too, after the attended one's; with ``memory.drop_left_out`` none that lies at a
        place left out of the face's recalls.
        """
        n = self.kernels.learn(self._state, *self.host.trial_end(outcome),
                               np.ascontiguousarray(thetas, dtype=float),
                               np.ascontiguousarray(steps, dtype=float), self.learn_rng)
        self.sync(self._state)
        return n

    def command(self, face: np.ndarray, theta_rad: np.ndarray) -> np.ndarray:
        """The command for a checked flat face window and head angle (zero with no memory)."""
        return self.commands(np.reshape(face, (1, -1)), np.reshape(theta_rad, (1, 2)))[0]

    def commands(self, faces: np.ndarray, thetas: np.ndarray) -> np.ndarray:
        """:meth:`command` for K checked flat face windows and head angles, (K, 2)."""
        m, out = self.memory, np.empty((len(faces), 2))
        recall_commands_into(np.ascontiguousarray(faces, dtype=float),
                             np.ascontiguousarray(thetas, dtype=float), m.projection,
                             *m.kept_arrays(), m.lo_rad, m.cell_rad, m.options.k_nearest,
                             m.radius_rad, *m.left_arrays(), self.host.step_rad,
                             self.saccade_rad, out)
        return out

    def saved_arrays(self) -> dict[str, np.ndarray]:
        """Nothing: a memory is not saved in a model file."""
        return {}

    def saved_shapes(self) -> dict[str, tuple[int, ...]]:
        """Nothing: a memory is not saved in a model file."""
        return {}

    def load_arrays(self, arrays: dict[str, np.ndarray]) -> None:
        """Nothing: a memory is not saved in a model file."""
