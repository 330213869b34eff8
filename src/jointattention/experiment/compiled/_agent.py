"""The bootstrap agent in the compiled loop: its gate, its module's command, what it keeps.

:mod:`._loop` calls them: the gate's rate of choosing the learning module, the
network's command at a head angle (with the face's part of its input summed once a trial), and
the places the episodic memory and the population code keep from a trial. Each calls the
kernels the step-by-step agent calls (:mod:`~jointattention.agent.gates`,
:mod:`~jointattention.agent.moves`, :mod:`~jointattention.models.memory.episodic`,
:mod:`~jointattention.models.population.module`).
"""

from __future__ import annotations

from ..._jit import jit
from ...agent.attention import visual_feedback_rad
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
from ...models.population.module import line_step

__all__ = ["gate_rate", "keep_place", "lm_step", "places_into", "recall_place"]


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
            memory, recalled, aim, saccade_rad, line, acc, scaled, hid, out):
    """The learning module's command at a head angle (no step if the memory recalled nothing).

    As the learning module's ``direction`` computes it
    (:mod:`jointattention.models.network.module`): the network's
    (:func:`~jointattention.models.network.command.network_command`, from ``face_acc``, the
    face's part of the hidden input); ``memory`` is whether the learner is the episodic
    memory (``saccade_rad``: its longest move, 0 for one step); ``line`` is whether it is the
    population code, the direction it read out and the trial's start. The arrays come one by
    one, not in the loop's records: each array taken from a record is counted in and out (two
    atomic operations), at every step.
    """
    if memory:
        if not recalled:
            return 0.0, 0.0
        return place_step(aim[0] - pan, aim[1] - tilt, step_rad, saccade_rad)
    if line[0]:
        return line_step(line[2], line[3], line[1], pan, tilt, step_rad)
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


@jit
def places_into(place, centre, seen, in_view, pan, tilt, cx, cy, gain_rad_per_px,
                places) -> int:
    """``place``, then (``in_view``) every other object of the last image but ``seen``.

    Into ``places``, as ``BootstrapAgent.place_of`` finds them; returns how many.
    """
    places[0, 0], places[0, 1], n = place[0], place[1], 1
    for i in range(len(centre) if in_view else 0):
        if i != seen and n < len(places):
            v_pan, v_tilt = visual_feedback_rad(centre[i, 0], centre[i, 1], cx, cy,
                                                gain_rad_per_px)
            places[n, 0], places[n, 1] = pan + v_pan, tilt + v_tilt
            n += 1
    return n
