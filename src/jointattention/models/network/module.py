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

from ...agent.moves import learning_samples, scale_angle_into
from ...agent.protocol import Outcome
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
    beyond the agent's network and face statistics).
    """

    kernels = None  # not on the kernel protocol: the compiled loop runs it itself

    def __init__(self, host):
        self.host = host

    def _inputs(self, face_x: np.ndarray, thetas: np.ndarray) -> np.ndarray:
        h = self.host
        thetas = np.atleast_2d(thetas)
        inputs = np.empty((len(thetas), len(face_x) + 2))
        inputs[:, :len(face_x)] = face_x
        for row, (pan, tilt) in zip(inputs, thetas, strict=True):
            scale_angle_into(float(pan), float(tilt), h.theta_mid_rad, h.theta_half_rad,
                             row, len(face_x))
        return inputs

    def _face_part(self, face_x: np.ndarray) -> np.ndarray:
        """The face's part of the hidden units' input: fixed for a trial (it learns at the end)."""
        acc = np.empty(len(self.host.learner.b1_))
        face_part(np.ascontiguousarray(face_x, dtype=float), self.host.learner.w1_, acc)
        return acc

    def _command(self, face_acc: np.ndarray, theta_rad) -> np.ndarray:
        h, n_hidden = self.host, len(face_acc)
        learner = h.learner
        return np.array(network_command(
            face_acc, float(theta_rad[0]), float(theta_rad[1]), learner.w1_, learner.b1_,
            learner.w2_, learner.b2_, h.theta_mid_rad, h.theta_half_rad, h.step_rad,
            np.empty(n_hidden), np.empty(2), np.empty(n_hidden), np.empty(2)))

    def begin(self, face: np.ndarray, theta_rad: np.ndarray) -> None:
        """A trial starts: the face (standardised by the agent's statistics) is fixed for it."""
        self._face_x = self.host.faces.transform(face)
        self._face_acc = self._face_part(self._face_x)

    def observe(self, det, theta_rad) -> None:
        """Nothing: the module makes nothing of a step's view, and attention may take any."""

    def step(self, theta_rad) -> np.ndarray:
        """The module's command at a head angle during the trial."""
        return self._command(self._face_acc, theta_rad)

    def direction(self, theta_rad) -> np.ndarray:
        """The command without a random draw (the network draws none): the gate's measure."""
        return self.step(theta_rad)

    def learn(self, outcome: Outcome, thetas: np.ndarray, steps: np.ndarray) -> int:
        """Teach each step toward the trial's aim (or its own step); returns the samples taught."""
        h = self.host
        executed = h.options.learning_target == "executed_step"
        y = np.empty_like(thetas)
        keep = learning_samples(thetas, steps, h.aim_of(outcome), executed, y)
        x = self._inputs(self._face_x, thetas[keep])
        for _ in range(h.options.n_passes):  # the face is every row's: shared inputs
            h.learner.partial_fit(x, y[keep], shared_inputs=len(self._face_x))
        return int(keep.sum())

    def command(self, face: np.ndarray, theta_rad: np.ndarray) -> np.ndarray:
        """The command for a checked flat face window and head angle, outside a trial."""
        return self._command(self._face_part(self.host.faces.transform(face)), theta_rad)

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
