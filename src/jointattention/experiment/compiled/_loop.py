"""The compiled engine's loop over a cell's trials.

:mod:`.cell` packs the inputs (:mod:`.inputs`) and drives the loop; this module is
the loop itself. Each step calls the kernels the step-by-step path calls
(:mod:`~jointattention.world.fast`, :mod:`~jointattention.world.placement`,
:mod:`~jointattention.agent.attention`, :mod:`~jointattention.models.network.learner`,
:mod:`~jointattention.models.memory.episodic`, :mod:`~jointattention.models.bootstrap`), in
the order of its random draws; the agent's gate, its module's command and the places it keeps
are :mod:`._agent`'s.

A learning module on the kernel protocol (:class:`~jointattention.agent.protocol.ModuleKernels`,
e.g. the population code) hands its kernels instead: :func:`loop_for` compiles a copy of
:func:`run_trials` whose globals ``module_begin``, ``module_command``, ``module_direction``
and ``module_learn`` are them (``_jit.specialise``), and the loop calls them on the module's
own state (its argument ``module``). Here they are None: the loop for the modules not on the
protocol (``module`` None) prunes their calls.

:func:`run_trials`'s arguments: ``memory`` is the episodic memory
(:class:`~.inputs.LoopMemory`), or None for the learners that back-propagate (its branches are
then pruned at compile time: its kernels are compiled only for a memory learner);
``development`` the developmental model's caregiver and blur
(:class:`~.inputs.LoopDevelopment`), or None, likewise; ``module`` the state of a learning
module on the kernel protocol, or None (its ``learn`` draws from ``module_rng``). A frozen
robot (``robot.learning`` False) learns nothing and its learning time stands still: it runs
``max_trials`` trials. Each trial is :func:`~.cells.random_scene`, a
:class:`~.trial.SceneTrial` and :func:`~.trial.run_trial` of a bootstrap agent, in that order
of random draws. Its parts that run once a trial (the memory's start, the face statistics, the
caregiver's approval, the network's and the memory's learning) are the private kernels below
it.
"""

from __future__ import annotations

from functools import cache

import numpy as np

from ..._jit import jit, specialise
from ...agent.attention import interest_argmax, visual_feedback_rad
from ...agent.face_standardiser import standardise, welford_update
from ...agent.gates import PERFORMANCE, agreement_update
from ...agent.moves import MAX_PLACES, learning_samples, places_into, random_step, scale_angle_into
from ...models.bootstrap import LEARNING_TARGETS
from ...models.developmental import blur_into, blur_px, caregiver_update
from ...models.memory._left_out import (
    drop_left_out_from,
    empty_arrival,
    leave_out,
    passed_over_into,
)
from ...models.memory.episodic import face_code_into, left_out_of
from ...models.network.learner import face_part, sgd_rows_from
from ...world.kinematics import separation_rad
from ..trial import END_FIRED, RUNNING, move_head
from ._agent import gate_rate, keep_place, lm_step, recall_place
from .steps import draw_trial, look, look_arrays, look_camera

__all__ = ["COLUMNS", "loop_for", "run_trials"]

_VF, _LM, _RANDOM = 0, 1, 2  # the modules, as codes
# the records run_trials writes, one row each (the rest of trial.RECORD is computed from them)
COLUMNS = ("learning_time", "n_steps", "n_lm_steps", "n_random_steps", "attended", "target",
           "end")
_OBJECT_DIRECTION = LEARNING_TARGETS.index("object_direction")
_EXECUTED_STEP = LEARNING_TARGETS.index("executed_step")
# a learning module's kernels (agent.protocol.ModuleKernels), bound by loop_for's copies
module_begin = module_command = module_direction = module_learn = None


@cache
def loop_for(kernels):
    """:func:`run_trials` for a learning module's kernels (a ``ModuleKernels``, or None)."""
    if kernels is None:
        return run_trials
    return specialise(run_trials, module_begin=kernels.begin, module_command=kernels.command,
                      module_direction=kernels.direction, module_learn=kernels.learn)


@jit
def run_trials(until_steps, max_trials, world, robot, state, memory, development, module,
               trials_rng, shuffle_rng, gate_rng, move_rng, module_rng, records) -> int:
    """Trials until the learning time reaches ``until_steps``; -1 if objects cannot be placed.

    See the module's docstring.
    """
    n, n_pix, n_hidden = world.n_objects, world.faces.shape[1], len(state.b1)
    cx, cy = (world.width_px - 1) / 2, (world.height_px - 1) / 2
    obj_pos, obj_rad, edge = np.empty((n, 3)), np.empty(n), np.empty(n)
    arrays, camera = look_arrays(n), look_camera(world, robot.d_th_px)
    centre, seen_area, seen_edge, motion = arrays[1], arrays[2], arrays[3], np.zeros(n)
    no_objects, passed_over = np.zeros(n, np.bool_), np.zeros(n, np.bool_)  # attention's
    face_x, face_acc, acc, hid, out, scaled, seen_face, blur_tmp = _scratch(n_pix, n_hidden)
    recall, saccade_rad = _recall_scratch(memory, robot.learning, development is None,
                                          len(world.faces))
    code, has_memory, sweep, place = recall[0], memory is not None, (0.0, 0.0), np.empty(2)
    aim, places = np.empty(2), np.empty((MAX_PLACES, 2))  # the place recalled, those found
    thetas, steps, y, angles_x = _steps_scratch(robot.max_steps)
    c, a1, a2, a3 = state.counters, robot.weights[0], robot.weights[1], robot.weights[2]
    # the arrays of every step, taken from the records once (each taking is counted in and out)
    w1, b1, w2, b2, agreement = state.w1, state.b1, state.w2, state.b2, state.agreement
    mid, half, lim = robot.theta_mid_rad, robot.theta_half_rad, world.limits_rad
    while (c[0] < until_steps or not robot.learning) and c[3] < max_trials:
        start = c[0]
        # the scene (cells.random_scene, FastScene.sample)
        k, target, shown = draw_trial(world, trials_rng, shuffle_rng, obj_pos, obj_rad, edge)
        if target < 0:
            return -1
        face, pan, tilt = world.faces[shown], world.theta_face_rad[k, 0], world.theta_face_rad[k, 1]
        if development is not None and development.blur_start_px > 0:  # DevelopmentalAgent.see
            face = _blurred(development, face, float(c[0]), blur_tmp, seen_face)
        recalled, evidence, mine = False, 0.0, recall[5]  # mine: the face's places left out
        if memory is not None:  # the agent begins (BootstrapAgent.begin_trial, the modules')
            recalled, evidence, mine = _memory_begin(memory, face, shown, c, recall, aim)
        if module is not None:
            evidence = module_begin(module, face, pan, tilt, robot.learning)
        _faces_begin(robot, state, face, not has_memory and module is None, face_x, face_acc)
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
            # the agent acts (BootstrapAgent.act; first MemoryModule.observe)
            if (memory is not None and memory.leave_out_empty and robot.learning and recalled
                    and empty_arrival(aim[0], aim[1], pan, tilt, robot.step_rad, centre[:m], cx,
                                      cy, memory.radius_rad / robot.gain_rad_per_px)):
                recalled, evidence, mine = _memory_left_out(memory, c, code, aim, mine)
            module_now = (trial_module if trial_module >= 0 else
                          _gated(robot, c[0], agreement[0], evidence, gate_rng))
            i = -1
            if module_now == _VF:
                passed = no_objects[:m]
                if memory is not None and memory.pass_over and robot.learning:
                    passed = passed_over[:m]
                    passed_over_into(centre[:m], cx, cy, robot.gain_rad_per_px, pan, tilt, mine,
                                     memory.radius_rad, passed)
                i = interest_argmax(seen_area[:m], seen_edge[:m], motion[:m], a1, a2, a3, passed)
                if i < 0:
                    module_now = _LM if robot.vf_fallback_lm else _RANDOM
            if module_now == _VF:
                d_pan, d_tilt = visual_feedback_rad(centre[i, 0], centre[i, 1], cx, cy,
                                                    robot.gain_rad_per_px)
            elif module_now == _LM and module is not None:
                d_pan, d_tilt = module_command(module, pan, tilt, robot.step_rad, move_rng)
            elif module_now == _LM and has_memory and not recalled:
                d_pan, d_tilt = random_step(move_rng, robot.step_rad)
            elif module_now == _LM:
                d_pan, d_tilt = lm_step(w1, b1, w2, b2, mid, half, robot.step_rad, face_acc, pan,
                                        tilt, has_memory, recalled, aim, saccade_rad, acc,
                                        scaled, hid, out)
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
        approved = _approved(development, state.caregiver, robot.learning, end, attended,
                             target, obj_pos)
        learns = _learns(robot, end, n_steps, approved, last_module)
        if learns:
            v_pan, v_tilt = _aim(robot, centre[seen], cx, cy, pan, tilt, place)
            if robot.gate_kind == PERFORMANCE:  # BootstrapAgent._measure
                if module is not None:
                    u_pan, u_tilt = module_direction(module, pan_start, tilt_start, robot.step_rad)
                else:
                    u_pan, u_tilt = lm_step(w1, b1, w2, b2, mid, half, robot.step_rad, face_acc,
                                            pan_start, tilt_start, has_memory, recalled, aim,
                                            saccade_rad, acc, scaled, hid, out)
                agreement[0] = agreement_update(
                    agreement[0], u_pan, u_tilt, pan + v_pan - pan_start,
                    tilt + v_tilt - tilt_start, robot.gate_a, robot.gate_window)
        if learns and memory is not None:  # MemoryModule.learn
            _memory_learn(memory, c, code, place, centre[:m], seen, pan, tilt, cx, cy,
                          robot.gain_rad_per_px, mine, places)
        elif learns and module is not None:  # the module's learn
            module_learn(module, place, centre[:m], seen, pan, tilt, cx, cy,
                         robot.gain_rad_per_px, face, module_rng)
        elif learns:
            _network_learn(robot, state, face_x, face_acc, thetas[:n_steps], steps[:n_steps],
                           place, y[:n_steps], angles_x)
        _record(records, c, start, n_steps, n_lm, n_random, attended, target, end)
    return 0


@jit
def _blurred(development, face, t, tmp, out):
    """The face through the developmental model's blur at learning time ``t`` (into ``out``)."""
    d = development
    blur_into(face, d.face_width_px, d.face_height_px,
              blur_px(d.blur_start_px, d.blur_sharp_steps, t), tmp, out)
    return out


@jit(inline=True)
def _faces_begin(robot, state, face, network, face_x, face_acc) -> None:
    """The face statistics learn the face (``BootstrapAgent.begin_trial``).

    With ``network``, the network's input ``face_x`` and its part of the hidden sums
    ``face_acc`` (``NetworkModule.begin``).
    """
    c = state.counters
    if robot.learning:
        c[1] += 1
        welford_update(face, state.mean, state.m2, c[1])
    if network:
        standardise(face, state.mean, state.m2, c[1], robot.min_std, face_x)
        face_part(face_x, state.w1, face_acc)


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


@jit
def _memory_learn(memory, c, code, place, centre, seen, pan, tilt, cx, cy, gain_rad_per_px,
                  mine, places) -> None:
    """The episodic memory keeps the trial's places (``MemoryModule.learn``)."""
    n_places = places_into(place, centre, seen, memory.in_view, pan, tilt, cx, cy,
                           gain_rad_per_px, places)
    if memory.drop_left_out:
        n_places = drop_left_out_from(places, n_places, mine, memory.radius_rad)
    for i in range(n_places):
        c[5] = keep_place(code, places[i, 0], places[i, 1], memory, c)


@jit(inline=True)
def _record(records, c, start, n_steps, n_lm, n_random, attended, target, end) -> None:
    """A trial's row of :data:`COLUMNS`; one more trial counted."""
    r = c[3]
    records[0, r], records[1, r], records[2, r], records[3, r] = start, n_steps, n_lm, n_random
    records[4, r], records[5, r], records[6, r] = attended, target, end
    c[3] += 1


@jit
def _scratch(n_pix, n_hidden):
    """The network's scratch, then the face seen through the blur and the blur's scratch.

    The network's: its face input, hidden sums (the face's part, all), hidden outputs,
    outputs, the scaled head angle.
    """
    return (np.empty(n_pix), np.empty(n_hidden), np.empty(n_hidden), np.empty(n_hidden),
            np.empty(2), np.empty(2), np.empty(n_pix), np.empty(n_pix))


@jit
def _steps_scratch(max_steps):
    """A trial's head angles and steps, and the network's aims and scaled angles of them."""
    return (np.empty((max_steps, 2)), np.empty((max_steps, 2)), np.empty((max_steps, 2)),
            np.empty((max_steps, 2)))


@jit
def _recall_scratch(memory, learning, same_faces, n_faces):
    """What the episodic memory's trial start keeps between trials; its longest move.

    The face code, the faces recalled once (a frozen memory recalls a face alike each time:
    whether and what, its aim and evidence) and the faces coded once (learning, a data set's
    face is the same each time unless the developmental model blurs it), and no places left
    out. Empty for a learner without a memory (``memory`` None).
    """
    n_code = n_cached = n_coded = 0
    saccade_rad = 0.0  # the memory's longest move to its place (0: one step)
    if memory is not None:
        n_code, saccade_rad = memory.projection.shape[1], memory.saccade_rad
        if not learning:
            n_cached = n_faces
        elif same_faces:
            n_coded = n_faces
    return (np.empty(n_code), np.zeros(n_cached, np.int8), np.empty((n_cached, 3)),
            np.zeros(n_coded, np.bool_), np.empty((n_coded, n_code)),
            np.empty((0, 2))), saccade_rad


@jit
def _memory_begin(memory, face, shown, c, recall, aim):
    """The episodic memory's trial start (``MemoryModule.begin``): recalled, evidence, left out.

    ``recall`` is :func:`_recall_scratch`'s; the place recalled goes into ``aim``.
    """
    code, cached, cached_aim, coded, codes_of, mine = recall
    n_cached, n_coded = len(cached), len(coded)
    if n_cached and cached[shown]:
        aim[0], aim[1] = cached_aim[shown, 0], cached_aim[shown, 1]
        return cached[shown] == 1, cached_aim[shown, 2], mine
    if n_coded and coded[shown]:
        code[:] = codes_of[shown]
    else:
        face_code_into(face, memory.projection, code)
        if n_coded:
            codes_of[shown], coded[shown] = code, True
    left_out = left_out_of(code, memory.left_codes, memory.left_aims, c[6])
    support, evidence = recall_place(code, memory, c, left_out, aim)
    recalled = support >= 0
    if n_cached:
        cached[shown] = 1 if recalled else 2
        cached_aim[shown, 0], cached_aim[shown, 1] = aim[0], aim[1]
        cached_aim[shown, 2] = evidence
    return recalled, evidence, left_out


@jit
def _memory_left_out(memory, c, code, aim, mine):
    """A recalled place found empty is left out (``MemoryModule.observe``, ``begin_again``).

    Recalled, evidence and the face's places left out, after.
    """
    c[6] = leave_out(code, aim[0], aim[1], memory.left_codes, memory.left_aims, c[6])
    if memory.pass_over or memory.drop_left_out or memory.recall_again:
        mine = left_out_of(code, memory.left_codes, memory.left_aims, c[6])
    if memory.recall_again:  # MemoryModule.begin_again
        support, evidence = recall_place(code, memory, c, mine, aim)
        return support >= 0, evidence, mine
    return False, 0.0, mine


@jit(inline=True)
def _gated(robot, t, agreement, evidence, gate_rng) -> int:
    """The module the gate chooses at learning time ``t``: one draw from ``gate_rng``."""
    rate = gate_rate(robot, t, agreement, evidence)
    return _LM if gate_rng.random() < rate else _VF


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


@jit
def _approved(development, caregiver, learning, end, attended, target, obj_pos) -> bool:
    """Whether the caregiver approves the trial: it ended on her target.

    The developmental caregiver (``development`` not None) approves an object near it too,
    within her criterion, which adapts.
    """
    if development is None:
        return end == END_FIRED and attended == target
    approved = end == END_FIRED and (attended == target or separation_rad(
        obj_pos[attended], obj_pos[target]) <= caregiver[0])
    if learning:
        d = development
        caregiver[0], caregiver[1] = caregiver_update(
            approved, caregiver[0], caregiver[1], d.criterion_level, d.criterion_window_trials,
            d.criterion_shrink)
    return approved


@jit(inline=True)
def _network_learn(robot, state, face_x, face_acc, thetas, steps, place, y, angles_x) -> None:
    """The network learns from a trial's steps (``NetworkModule.learn``); ``y``: scratch."""
    n_steps = len(thetas)
    keep = learning_samples(thetas, steps, place, robot.learning_target == _EXECUTED_STEP, y)
    n_kept = 0
    for s in range(n_steps):  # the kept steps' scaled head angles and aims, in order
        if keep[s]:
            scale_angle_into(thetas[s, 0], thetas[s, 1], robot.theta_mid_rad,
                             robot.theta_half_rad, angles_x[n_kept], 0)
            y[n_kept, 0], y[n_kept, 1], n_kept = y[s, 0], y[s, 1], n_kept + 1
    for p in range(robot.n_passes):  # the face is every row's: shared inputs
        if p > 0:  # face_acc, the face's part summed at the trial's start, is stale
            face_part(face_x, state.w1, face_acc)
        sgd_rows_from(face_acc, face_x, angles_x[:n_kept], y[:n_kept], state.w1, state.b1,
                      state.w2, state.b2, state.v1, state.vb1, state.v2, state.vb2,
                      robot.learning_rate, robot.momentum)
        state.counters[2] += n_kept
