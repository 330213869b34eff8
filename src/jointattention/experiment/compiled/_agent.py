"""The bootstrap agent in the compiled loop: its gate, its module's command, what it keeps.

:mod:`._loop` calls them: the gate's rate of choosing the learning module, the
network's command at a head angle (with the face's part of its input summed once a trial), and
the places the episodic memory keeps from a trial. Each calls the
kernels the step-by-step agent calls (:mod:`~jointattention.agent.gates`,
:mod:`~jointattention.agent.moves`, :mod:`~jointattention.models.memory.episodic`).
"""

from __future__ import annotations

from ..._jit import jit
from ...agent.gates import (
    CONSTANT,
    EVIDENCE,
    PERFORMANCE,
    evidence_rate,
    performance_rate,
    sigmoid_rate,
)
from ...agent.moves import place_step
from ...models.memory.episodic import memory_recall, memory_store
from ...models.network.command import network_command

__all__ = ["gate_rate", "keep_place", "lm_step", "recall_place"]


@jit
def gate_rate(robot, t, agreement, evidence):
    """The gate's rate of choosing the learning module at learning time ``t``.

    ``agreement``: the performance gate's measure; ``evidence``: the memory's for the face.
    """
    if robot.gate_kind == CONSTANT:
        return robot.gate_a
    if robot.gate_kind == PERFORMANCE:
        return performance_rate(agreement, robot.gate_a, robot.gate_b)
    if robot.gate_kind == EVIDENCE:
        return evidence_rate(evidence, robot.gate_a, robot.gate_b)
    return sigmoid_rate(float(t), robot.gate_a, robot.gate_b)


@jit
def lm_step(w1, b1, w2, b2, theta_mid_rad, theta_half_rad, step_rad, face_acc, pan, tilt,
            memory, recalled, aim, saccade_rad, acc, scaled, hid, out):
    """The learning module's command at a head angle (no step if the memory recalled nothing).

    As the learning module's ``direction`` computes it
    (:mod:`jointattention.models.network.module`): the network's
    (:func:`~jointattention.models.network.command.network_command`, from ``face_acc``, the
    face's part of the hidden input); ``memory`` is whether the learner is the episodic
    memory (``saccade_rad``: its longest move, 0 for one step). The arrays come one by
    one, not in the loop's records: each array taken from a record is counted in and out (two
    atomic operations), at every step.
    """
    if memory:
        if not recalled:
            return 0.0, 0.0
        return place_step(aim[0] - pan, aim[1] - tilt, step_rad, saccade_rad)
    return network_command(face_acc, pan, tilt, w1, b1, w2, b2, theta_mid_rad, theta_half_rad,
                           step_rad, acc, scaled, hid, out)


@jit
def recall_place(code, memory, c, left_out, aim) -> tuple[float, float]:
    """:func:`~jointattention.models.memory.episodic.memory_recall` of a face code, into ``aim``.

    Its support and evidence; the places ``left_out`` (m, 2) do not win.
    """
    return memory_recall(code, memory.codes, memory.counts, memory.links, memory.aims,
                         memory.base, c[4], c[5], memory.lo_rad, memory.cell_rad, memory.k,
                         memory.radius_rad, left_out, aim)


@jit
def keep_place(code, pan, tilt, memory, c) -> int:
    """:func:`~jointattention.models.memory.episodic.memory_store` of a place; the codes in use."""
    n_codes = memory_store(code, pan, tilt, memory.codes, memory.counts, memory.links,
                           memory.aims, memory.base, c[4], c[5], memory.lo_rad, memory.cell_rad,
                           memory.radius_rad)
    c[4] += 1
    return n_codes
