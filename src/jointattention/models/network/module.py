"""The paper's learning module inside the bootstrap agent: a network from face and head angle.

:class:`NetworkModule` is what :class:`~..bootstrap.BootstrapAgent` composes with ``learner =
"backprop"``: a three-layer network (the agent's ``learner``, :class:`~.learner.LearningModule`)
from the standardised face window and the scaled head angle to a direction; its command is
that direction, one step long (:mod:`.command`). A trial the evaluator ends teaches each of its
steps toward the trial's aim (paper, section III-C). The episodic and the population-coded
modules (:mod:`..memory`, :mod:`..population`) answer the same calls.
"""

from __future__ import annotations

import numpy as np

from ...agent.face_standardiser import NO_FACE_SEEN
from ...agent.protocol import Outcome
from ...errors import ArgumentError
from ._trial import KERNELS, NetworkArrays
from .command import lm_commands_into, network_command
from .learner import face_part

__all__ = ["NetworkModule"]


class NetworkModule:
    """The network as a learning module: its commands and its learning.

    Args:
        host: the bootstrap agent it serves: its network (``learner``), face statistics
            (``faces``), head-angle scaling, step length and the trial's aim.

    The calls every learning module answers: :meth:`begin` (a trial's face window, flat
    and checked, and the head angle at the face), :meth:`step` and :meth:`direction` (its
    command at a head angle, with and without random draws), :meth:`learn` (a trial the
    evaluator ended), :meth:`commands` (face windows and head angles, checked) and
    :meth:`saved_arrays` / :meth:`saved_shapes` / :meth:`load_arrays` (what a model file keeps
    beyond the agent's network and face statistics). It declares its part of a trial as
    compiled kernels (:attr:`kernels`, over :meth:`compiled_state`; see
    :class:`~jointattention.agent.protocol.ModuleKernels`), which those of a trial call.
    """

    kernels = KERNELS  # its part of a trial, for the compiled engine

    def __init__(self, host):
        self.host = host
        self._state: NetworkArrays | None = None  # the trial's (begin makes it)

    @property
    def learn_rng(self) -> np.random.Generator:
        """The stream its ``learn`` kernel is handed: the agent's moves (it draws nothing)."""
        return self.host.move_rng

    def compiled_state(self, n_faces: int = 0) -> NetworkArrays:
        """The module's state as the kernels take it: the agent's own arrays (see ``sync``)."""
        h = self.host
        net, faces, o = h.learner, h.faces, h.options
        n_hidden, n_out = net.w2_.shape
        mean, m2 = faces.statistics(h.body.view_size)
        return NetworkArrays(
            np.asarray(h.theta_mid_rad, float), np.asarray(h.theta_half_rad, float),
            float(faces.min_std), float(net.learning_rate), float(net.momentum),
            int(o.n_passes), o.learning_target == "executed_step", *net._params(),
            *net.velocity_, mean, m2, faces.seen, np.array([net.n_updates_], np.int64),
            np.empty(h.body.view_size), np.empty(n_hidden), np.empty(n_hidden),
            np.empty(n_hidden), np.empty(n_out), np.empty(2))

    def sync(self, state: NetworkArrays) -> None:
        """Take back the updates the kernels counted."""
        self.host.learner.n_updates_ = int(state.counters[0])

    def _command(self, face_acc: np.ndarray, theta_rad) -> np.ndarray:
        h, n_hidden = self.host, len(face_acc)
        learner = h.learner
        return np.array(network_command(
            face_acc, float(theta_rad[0]), float(theta_rad[1]), learner.w1_, learner.b1_,
            learner.w2_, learner.b2_, h.theta_mid_rad, h.theta_half_rad, h.step_rad,
            np.empty(n_hidden), np.empty(2), np.empty(n_hidden), np.empty(2)))

    def begin(self, face: np.ndarray, theta_rad: np.ndarray) -> None:
        """A trial starts: the face (standardised by the agent's statistics) is fixed for it."""
        if not self.host.faces.n_seen_:
            raise ArgumentError(NO_FACE_SEEN)
        self._state = self.compiled_state()
        self.kernels.begin(self._state, np.ascontiguousarray(face, dtype=float), -1,
                           float(theta_rad[0]), float(theta_rad[1]), self.host.learning)

    def observe(self, det, theta_rad) -> None:
        """Nothing: the module makes nothing of a step's view, and attention may take any."""

    def step(self, theta_rad) -> np.ndarray:
        """The module's command at a head angle during the trial."""
        return np.array(self.kernels.command(self._state, float(theta_rad[0]),
                                             float(theta_rad[1]), self.host.step_rad,
                                             self.host.move_rng))

    def direction(self, theta_rad) -> np.ndarray:
        """The command without a random draw (the network draws none): the gate's measure."""
        return np.array(self.kernels.direction(self._state, float(theta_rad[0]),
                                               float(theta_rad[1]), self.host.step_rad))

    def learn(self, outcome: Outcome, thetas: np.ndarray, steps: np.ndarray) -> int:
        """Teach each step toward the trial's aim (or its own step); returns the samples taught."""
        n = self.kernels.learn(self._state, *self.host.trial_end(outcome),
                               np.ascontiguousarray(thetas, dtype=float),
                               np.ascontiguousarray(steps, dtype=float), self.learn_rng)
        self.sync(self._state)
        return n

    def command(self, face: np.ndarray, theta_rad: np.ndarray) -> np.ndarray:
        """The command for a checked flat face window and head angle, outside a trial."""
        acc = np.empty(len(self.host.learner.b1_))
        face_part(np.ascontiguousarray(self.host.faces.transform(face), dtype=float),
                  self.host.learner.w1_, acc)
        return self._command(acc, theta_rad)

    def commands(self, faces: np.ndarray, thetas: np.ndarray) -> np.ndarray:
        """:meth:`command` for K checked flat face windows (K, H * W) and head angles (K, 2)."""
        h = self.host
        out, f, net = np.empty((len(faces), 2)), h.faces, h.learner
        lm_commands_into(faces, thetas, f.mean_, f.m2_, f.n_seen_, float(f.min_std),
                         *net._params(), h.theta_mid_rad, h.theta_half_rad, float(h.step_rad),
                         out)
        return out

    def saved_arrays(self) -> dict[str, np.ndarray]:
        """Nothing beyond the agent's network and face statistics."""
        return {}

    def saved_shapes(self) -> dict[str, tuple[int, ...]]:
        """Nothing beyond the agent's network and face statistics."""
        return {}

    def load_arrays(self, arrays: dict[str, np.ndarray]) -> None:
        """Nothing beyond the agent's network and face statistics."""
