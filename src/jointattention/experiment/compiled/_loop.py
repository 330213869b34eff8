"""The compiled engine's loop over a cell's trials.

:mod:`.cell` packs the inputs (:mod:`.inputs`) and drives the loop; this module is
the loop itself. Each step calls the kernels the step-by-step path calls
(:mod:`~jointattention.world.fast`, :mod:`~jointattention.world.placement`,
:mod:`~jointattention.agent.attention`, :mod:`~jointattention.agent.gates`,
:mod:`~jointattention.models.bootstrap`), in the order of its random draws, and the learning
module's at their place in the trial.

The learning module hands its kernels (:class:`~jointattention.agent.protocol.ModuleKernels`):
:func:`loop_for` compiles a copy of :func:`run_trials` whose globals ``module_begin``,
``module_observe``, ``module_passed_over``, ``module_command``, ``module_direction`` and
``module_learn`` are them (``_jit.specialise``), and the loop calls them on the module's own
state (its argument ``module``). The loop names no module's options: they are in its state.

The agent's own part beyond its module, how it sees the face and how the caregiver judges
(:class:`~jointattention.agent.protocol.AgentKernels`: a face window the robot sees
blurred, a caregiver whose judgement adapts), are bound likewise: ``agent_see`` and
``agent_judge``.

:func:`run_trials`'s arguments: ``sight`` the agent's state for its own kernels; ``module``
the learning module's state (its ``learn`` draws from ``module_rng``). A frozen
robot (``robot.learning`` False) learns nothing and its learning time stands still: it runs
``max_trials`` trials. Each trial is :func:`~.cells.random_scene`, a
:class:`~.trial.SceneTrial` and :func:`~.trial.run_trial` of a bootstrap agent, in that order
of random draws. Its parts that run once a trial (the face statistics, the trial's record)
are kernels of their own (below it, and :func:`~.steps.record_trial`).
"""

from __future__ import annotations

from functools import cache

import numpy as np

from ..._jit import jit, specialise
from ...agent.attention import interest_argmax, visual_feedback_rad
from ...agent.face_standardiser import welford_update
from ...agent.gates import (
    CONSTANT,
    EVIDENCE,
    PERFORMANCE,
    agreement_update,
    evidence_rate,
    performance_rate,
    sigmoid_rate,
)
from ...agent.moves import line_capture, random_step
from ...agent.protocol import AgentKernels
from ...models.bootstrap import LEARNING_TARGETS
from ...world.kinematics import separation_rad
from ..trial import END_FIRED, RUNNING, move_head
from .steps import draw_trial, look, look_arrays, look_camera, record_trial

__all__ = ["COLUMNS", "gate_rate", "loop_for", "run_trials"]

_VF, _LM, _RANDOM = 0, 1, 2  # the modules, as codes
# the records run_trials writes, one row each (the rest of trial.RECORD is computed from them)
COLUMNS = ("learning_time", "n_steps", "n_lm_steps", "n_random_steps", "attended", "target",
           "end")
_OBJECT_DIRECTION = LEARNING_TARGETS.index("object_direction")
# a learning module's kernels (agent.protocol.ModuleKernels) and the agent's own
# (agent.protocol.AgentKernels), bound by loop_for's copies
module_begin = module_observe = module_passed_over = None
module_command = module_direction = module_learn = None
agent_see = agent_judge = None


def loop_for(kernels, agent_kernels=AgentKernels()):  # noqa: B008 (a constant named tuple)
    """:func:`run_trials` for a learning module's kernels (a ``ModuleKernels``) and an agent's.

    ``agent_kernels``: an ``AgentKernels``, by default the bootstrap agent's. One loop for
    each pair, however it is asked for.
    """
    return _loop_for(kernels, agent_kernels)


@cache
def _loop_for(kernels, agent_kernels):
    """:func:`loop_for`, cached by its two sets of kernels."""
    return specialise(run_trials, module_begin=kernels.begin, module_observe=kernels.observe,
                      module_passed_over=kernels.passed_over, module_command=kernels.command,
                      module_direction=kernels.direction, module_learn=kernels.learn,
                      agent_see=agent_kernels.see, agent_judge=agent_kernels.judge)


@jit
def run_trials(until_steps, max_trials, world, robot, state, sight, module, trials_rng,
               shuffle_rng, gate_rng, move_rng, module_rng, records) -> int:
    """Trials until the learning time reaches ``until_steps``; -1 if objects cannot be placed.

    See the module's docstring.
    """
    n, n_pix = world.n_objects, world.faces.shape[1]
    cx, cy = (world.width_px - 1) / 2, (world.height_px - 1) / 2
    obj_pos, obj_rad, edge = np.empty((n, 3)), np.empty(n), np.empty(n)
    arrays, camera = look_arrays(n), look_camera(world, robot.d_th_px)
    centre, seen_area, seen_edge, motion = arrays[1], arrays[2], arrays[3], np.zeros(n)
    no_objects, passed_over = np.zeros(n, np.bool_), np.zeros(n, np.bool_)  # attention's
    seen_face = np.empty(n_pix)  # the face as the agent sees it, if not as it is
    sweep, place = (0.0, 0.0), np.empty(2)
    thetas, steps = np.empty((robot.max_steps, 2)), np.empty((robot.max_steps, 2))
    c, a1, a2, a3 = state.counters, robot.weights[0], robot.weights[1], robot.weights[2]
    agreement, lim = state.agreement, world.limits_rad
    while (c[0] < until_steps or not robot.learning) and c[1] < max_trials:
        start = c[0]
        # the scene (cells.random_scene, FastScene.sample)
        k, target, shown = draw_trial(world, trials_rng, shuffle_rng, obj_pos, obj_rad, edge)
        if target < 0:
            return -1
        face, pan, tilt = world.faces[shown], world.theta_face_rad[k, 0], world.theta_face_rad[k, 1]
        face_id = shown
        if agent_see(sight, face, float(c[0]), seen_face):  # e.g. DevelopmentalAgent.see
            # seen anew as the learning time moves, it is no data set's face
            face, face_id = seen_face, -1 if robot.learning else shown
        # the agent begins (BootstrapAgent.begin_trial, the module's)
        _faces_begin(robot, state, face)
        evidence = module_begin(module, face, face_id, pan, tilt, robot.learning)
        if robot.vf_fallback_sweep:
            sweep = random_step(move_rng, robot.step_rad)
        trial_module = (_gated(robot, c[0], agreement[0], evidence, gate_rng)
                        if robot.gate_per_trial else -1)
        # the trial (SceneTrial, run_trial)
        pan_start, tilt_start, limit_hit, last_module = pan, tilt, False, -1
        n_steps, n_lm, n_random, end, attended, seen = 0, 0, 0, -1, -1, -1
        while True:
            m, seen, end, attended = look(obj_pos, obj_rad, edge, pan, tilt, camera, limit_hit,
                                          n_steps, robot.max_steps, arrays)
            if end != RUNNING:
                break
            # the agent acts (BootstrapAgent.act; first the module observes)
            evidence = module_observe(module, pan, tilt, robot.step_rad, centre[:m], cx, cy,
                                      robot.gain_rad_per_px, robot.learning)
            module_now = (trial_module if trial_module >= 0 else
                          _gated(robot, c[0], agreement[0], evidence, gate_rng))
            i = -1
            if module_now == _VF:
                passed = no_objects[:m]
                if module_passed_over(module, pan, tilt, centre[:m], cx, cy,
                                      robot.gain_rad_per_px, robot.learning, passed_over[:m]):
                    passed = passed_over[:m]
                i = interest_argmax(seen_area[:m], seen_edge[:m], motion[:m], a1, a2, a3, passed)
                if i < 0:
                    module_now = _LM if robot.vf_fallback_lm else _RANDOM
            if module_now == _VF:
                d_pan, d_tilt = visual_feedback_rad(centre[i, 0], centre[i, 1], cx, cy,
                                                    robot.gain_rad_per_px)
            elif module_now == _LM:
                j = -1
                if robot.capture_rad > 0:  # BootstrapAgent._captured
                    u_pan, u_tilt = module_direction(module, pan_start, tilt_start,
                                                     robot.step_rad)
                    j = line_capture(centre[:m], cx, cy, robot.gain_rad_per_px, pan, tilt,
                                     pan_start, tilt_start, u_pan, u_tilt, robot.capture_rad)
                if j >= 0:
                    d_pan, d_tilt = visual_feedback_rad(centre[j, 0], centre[j, 1], cx, cy,
                                                        robot.gain_rad_per_px)
                else:
                    d_pan, d_tilt = module_command(module, pan, tilt, robot.step_rad, move_rng)
            elif robot.vf_fallback_sweep:
                d_pan, d_tilt = sweep
            else:
                d_pan, d_tilt = random_step(move_rng, robot.step_rad)
            last_module = module_now
            thetas[n_steps, 0], thetas[n_steps, 1] = pan, tilt
            steps[n_steps, 0], steps[n_steps, 1] = d_pan, d_tilt
            c[0] += robot.learning
            n_lm += module_now == _LM
            n_random += module_now == _RANDOM
            # the head moves, stopping at its joint limits (SceneTrial.step)
            pan, tilt, limit_hit = move_head(pan, tilt, d_pan, d_tilt, lim[0], lim[1], lim[2],
                                             lim[3])
            n_steps += 1
        # the agent learns (BootstrapAgent.end_trial, the module's learn; TeacherAgent's too)
        # the caregiver judges (the agent's judge: TeacherAgent's, DevelopmentalAgent's)
        fired, on_target, error_rad = _told(end, attended, target, obj_pos)
        approved = agent_judge(sight, fired, on_target, error_rad, robot.learning)
        learns = _learns(robot, end, n_steps, approved, last_module)
        if learns:
            v_pan, v_tilt = _aim(robot, centre[seen], cx, cy, pan, tilt, place)
            if robot.gate_kind == PERFORMANCE:  # BootstrapAgent._measure
                u_pan, u_tilt = module_direction(module, pan_start, tilt_start, robot.step_rad)
                agreement[0] = agreement_update(
                    agreement[0], u_pan, u_tilt, pan + v_pan - pan_start,
                    tilt + v_tilt - tilt_start, robot.gate_a, robot.gate_window)
        if learns or _learns_unfound(robot, end, last_module):  # nothing found: seen -1
            module_learn(module, place, centre[:m], seen, pan, tilt, cx, cy,
                         robot.gain_rad_per_px, face, thetas[:n_steps], steps[:n_steps],
                         module_rng)
        record_trial(records, c, start, n_steps, n_lm, n_random, attended, target, end)
    return 0


@jit
def gate_rate(robot, t, agreement, evidence):
    """The gate's rate of choosing the learning module at learning time ``t``.

    ``agreement``: the performance gate's measure; ``evidence``: the module's for the face.
    The gate's inputs are those it declares (``Gate.compiled_inputs``).
    """
    if robot.gate_kind == CONSTANT:
        return robot.gate_a
    if robot.gate_kind == PERFORMANCE:
        return performance_rate(agreement, robot.gate_a, robot.gate_b)
    if robot.gate_kind == EVIDENCE:
        return evidence_rate(evidence, robot.gate_a, robot.gate_b)
    return sigmoid_rate(float(t), robot.gate_a, robot.gate_b)


@jit(inline=True)
def _faces_begin(robot, state, face) -> None:
    """The face statistics learn the face (``BootstrapAgent.begin_trial``)."""
    if robot.learning:
        state.faces_seen[0] += 1
        welford_update(face, state.mean, state.m2, state.faces_seen[0])


@jit(inline=True)
def _aim(robot, centre_seen, cx, cy, pan, tilt, place) -> tuple[float, float]:
    """Eq. 2's command to the attended object; what the trial aims at into ``place``.

    ``BootstrapAgent.aim_of``: the attended object's place, or the final head angle.
    """
    v_pan, v_tilt = visual_feedback_rad(centre_seen[0], centre_seen[1], cx, cy,
                                        robot.gain_rad_per_px)
    place[0], place[1] = pan, tilt
    if robot.learning_target == _OBJECT_DIRECTION:
        place[0], place[1] = pan + v_pan, tilt + v_tilt
    return v_pan, v_tilt


@jit(inline=True)
def _gated(robot, t, agreement, evidence, gate_rng) -> int:
    """The module the gate chooses at learning time ``t``: one draw from ``gate_rng``."""
    rate = gate_rate(robot, t, agreement, evidence)
    return _LM if gate_rng.random() < rate else _VF


@jit(inline=True)
def _learns_unfound(robot, end, last_module) -> bool:
    """Whether the module learns from a trial it drove that found nothing.

    (``BootstrapAgent._learns_unfound``.) Such a trial did not fire, so its ``seen`` is -1
    (:func:`~jointattention.experiment.trial.end_after_look`).
    """
    return robot.learning and robot.learn_unfound and end != END_FIRED and last_module == _LM


@jit(inline=True)
def _learns(robot, end, n_steps, approved, last_module) -> bool:
    """Whether the agent learns from the trial (``BootstrapAgent._learns``).

    A learning agent learns from a trial the evaluator ended, if the caregiver approves it
    (when she judges: the teacher) and, with ``learn_from = "vf"``, if visual attention made
    its last move.
    """
    return (robot.learning and end == END_FIRED and n_steps > 0
            and (not robot.caregiver_judges or approved)
            and (not robot.learn_from_vf or last_module == _VF))


@jit(inline=True)
def _told(end, attended, target, obj_pos) -> tuple[bool, bool, float]:
    """What the caregiver is told of a trial: fired, on her target, and else how far from it.

    How far: the angle at the robot's head between the object the evaluator fired on and her
    target (``Outcome.caregiver_error_rad``; 0.0 where not asked).
    """
    fired = end == END_FIRED
    on_target = fired and attended == target
    error_rad = (separation_rad(obj_pos[attended], obj_pos[target]) if fired and not on_target
                 else 0.0)
    return fired, on_target, error_rad
