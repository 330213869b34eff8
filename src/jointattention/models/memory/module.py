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
from ...agent.moves import place_step, random_step
from ...agent.protocol import Outcome
from ._left_out import drop_left_out_from, empty_arrival, passed_over_into
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

    It answers :class:`~..network.module.NetworkModule`'s calls.

    Attributes:
        memory: the memory.
        support_: the support of the place recalled for the current trial's face (-1 before
            anything is kept).
        evidence_: that place's evidence, in trials (the evidence gate's measure).
    """

    kernels = None  # not on the kernel protocol: the compiled loop runs it itself

    def __init__(self, host, rng: np.random.Generator):
        self.host = host
        (code_rng,) = rng.spawn(1)
        body = host.body
        self.memory = EpisodicMemory(body.view_size, host.options.memory,
                                     body.joint_limits_rad, code_rng)
        self.support_, self.evidence_ = -1.0, 0.0
        self._left_out = None  # the current face's places left out (fetched as needed)

    @property
    def saccade_rad(self) -> float:
        """The longest move to a recalled place: visual feedback's with ``memory.saccade``.

        0 without: one step at a time.
        """
        if not self.memory.options.saccade:
            return 0.0
        return largest_feedback_rad(*self.host.body.image_size_px,
                                    self.host.mechanisms.vf_gain_rad_per_px)

    def _toward(self, aim_rad, theta_rad) -> np.ndarray:
        """A move toward the recalled place; none without one."""
        if aim_rad is None:
            return np.zeros(2)
        return np.array(place_step(aim_rad[0] - theta_rad[0], aim_rad[1] - theta_rad[1],
                                   self.host.step_rad, self.saccade_rad))

    def begin(self, face: np.ndarray, theta_rad: np.ndarray) -> None:
        """Recall the place for the caregiver's face."""
        self._face_code = self.memory.code(face)
        self.begin_again()
        self._left_out = None

    def begin_again(self) -> None:
        """Recall the place for the trial's face again (after a place was left out)."""
        self._aim_rad, self.support_, self.evidence_ = self.memory.recall_evidence(
            self._face_code)

    def observe(self, det: Detections, theta_rad) -> np.ndarray | None:
        """Leave the recalled place out if the head found it empty; what attention passes over.

        While learning (:mod:`._left_out`): with ``memory.leave_out_empty``
        the trial then has no recalled place, and no evidence for the gate (with
        ``memory.recall_again``, the face's next place and its evidence); with
        ``memory.pass_over_left_out`` the answer flags the detections at the face's places left
        out (None: attention may take any).
        """
        aim, host, options = self._aim_rad, self.host, self.host.options.memory
        if not host.learning:
            return None
        cx, cy = det.image_centre_px
        centre_px, gain = np.asarray(det.centre_px, dtype=float), host.mechanisms.vf_gain_rad_per_px
        pan, tilt = float(theta_rad[0]), float(theta_rad[1])
        if aim is not None and options.leave_out_empty and empty_arrival(
                aim[0], aim[1], pan, tilt, host.step_rad, centre_px, cx, cy,
                self.memory.radius_rad / gain):
            self.memory.leave_out(self._face_code, aim)
            if options.recall_again:  # the next place, the one left out no longer winning
                self.begin_again()
            else:
                self._aim_rad, self.support_, self.evidence_ = None, -1.0, 0.0
            self._left_out = None
        if not options.pass_over_left_out:
            return None
        if self._left_out is None:  # the face's places left out, fetched once until one more
            self._left_out = self.memory.left_out(self._face_code)
        passed = np.zeros(len(centre_px), dtype=bool)
        passed_over_into(centre_px, cx, cy, gain, pan, tilt, self._left_out,
                         self.memory.radius_rad, passed)
        return passed

    def step(self, theta_rad) -> np.ndarray:
        """A move toward the recalled place; a random step while nothing is kept."""
        if self._aim_rad is None:
            return np.array(random_step(self.host.move_rng, self.host.step_rad))
        return self._toward(self._aim_rad, theta_rad)

    def direction(self, theta_rad) -> np.ndarray:
        """A move toward the recalled place; none while nothing is kept."""
        return self._toward(self._aim_rad, theta_rad)

    def learn(self, outcome: Outcome, thetas: np.ndarray, steps: np.ndarray) -> int:
        """Keep the trial's place; returns the number of places kept.

        With ``memory.keep = "in_view"`` the places of the other objects in the last image are
        kept too, after the attended one's; with ``memory.drop_left_out`` none that lies at a
        place left out of the face's recalls.
        """
        host, options = self.host, self.host.options.memory
        places = [host.aim_of(outcome)]
        if options.keep == "in_view":
            places += [host.place_of(outcome, i) for i in range(len(outcome.detections))
                       if i != outcome.seen]
        places, n = np.array(places, dtype=float), len(places)
        if options.drop_left_out:
            n = drop_left_out_from(places, n, self.memory.left_out(self._face_code),
                                   self.memory.radius_rad)
        for place in places[:n]:
            self.memory.store(self._face_code, place)
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
