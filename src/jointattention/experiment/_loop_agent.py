"""The bootstrap agent in the compiled loop: its gate, its module's command, what it keeps.

:mod:`._compiled_loop` calls them: the gate's rate of choosing the learning module, the
network's command at a head angle (with the face's part of its input summed once a trial), and
the places the episodic memory and the population code keep from a trial. Each calls the
kernels the step-by-step agent calls (:mod:`~jointattention.agent.gates`,
:mod:`~jointattention.agent.learner`, :mod:`~jointattention.agent.memory`,
:mod:`~jointattention.models.population`).
"""

from __future__ import annotations

from .._jit import jit
from ..agent.attention import visual_feedback_rad
from ..agent.gates import (
    CONSTANT,
    EVIDENCE,
    PERFORMANCE,
    evidence_rate,
    performance_rate,
    sigmoid_rate,
)
from ..agent.learner import accumulate, forward
from ..agent.memory import memory_store
from ..agent.moves import scale_angle_into, unit_step
from ..models.population import line_step

__all__ = ["face_part", "gate_rate", "keep_place", "lm_step", "places_into"]


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
            memory, recalled, aim, line, acc, scaled, hid, out):
    """The learning module's command at a head angle (no step if the memory recalled nothing).

    As the learning module's ``direction`` computes it (:mod:`jointattention.models.network`):
    the network's weights, the head's scaling and ``face_acc``, the face's part of the hidden
    input (:func:`face_part`); ``memory`` is whether the learner is the episodic memory;
    ``line`` is whether it is the population code, the direction it read out and the trial's
    start. The arrays come one by one, not in the loop's records: each array taken from a
    record is counted in and out (two atomic operations), at every step.
    """
    if memory:
        if not recalled:
            return 0.0, 0.0
        return unit_step(aim[0] - pan, aim[1] - tilt, step_rad)
    if line[0]:
        return line_step(line[2], line[3], line[1], pan, tilt, step_rad)
    for i in range(len(acc)):  # element by element: quicker for numba to compile
        acc[i] = face_acc[i]
    scale_angle_into(pan, tilt, theta_mid_rad, theta_half_rad, scaled, 0)
    accumulate(scaled, w1, w1.shape[1] - 2, acc)
    forward(acc, b1, w2, b2, hid, out)
    return unit_step(out[0], out[1], step_rad)


@jit
def face_part(face_x, w1, out) -> None:
    """The face's part of the hidden units' input (:func:`accumulate` from zero).

    Into ``out``; fixed for a trial, as the weights change only at its end.
    """
    for i in range(len(out)):  # element by element: quicker for numba to compile
        out[i] = 0.0
    accumulate(face_x, w1, 0, out)


@jit
def keep_place(code, pan, tilt, memory, c) -> int:
    """:func:`~jointattention.agent.memory.memory_store` of a place; the codes in use."""
    n_codes = memory_store(code, pan, tilt, memory.codes, memory.counts, memory.links,
                           memory.aims, memory.base, c[4], c[5], memory.lo_rad, memory.cell_rad)
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
