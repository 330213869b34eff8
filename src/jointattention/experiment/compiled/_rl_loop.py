"""The compiled engine's loop over a cell's trials of an agent whose whole trial is its own.

The reinforcement learner (:mod:`jointattention.models.rl`) is such an agent: no gate, no
visual controller, every step its own choice. It hands its part of a trial as kernels
(:class:`~jointattention.agent.protocol.TrialKernels`): :func:`loop_for` compiles a copy of
:func:`run_agent_trials` whose globals ``agent_begin``, ``agent_act`` and ``agent_learn`` are
them (``_jit.specialise``), and the loop calls them on the agent's own state (its argument
``agent``), which holds its options: the loop names none. It only sequences the trial, as
the step-by-step path does (:func:`~.cells.random_scene`, then :class:`~.trial.SceneTrial`
and :func:`~.trial.run_trial`, whose ``begin_trial``, ``act`` and ``end_trial`` call the same
kernels), in the same order of random draws, and keeps the learning time. :mod:`.rl_cell`
packs its inputs and drives it.
"""

from __future__ import annotations

from functools import cache

import numpy as np

from ..._jit import jit, specialise
from ..trial import END_FIRED, RUNNING, move_head
from .steps import draw_trial, look, look_arrays, look_camera, record_trial

__all__ = ["CANNOT_BEGIN", "loop_for", "run_agent_trials"]

CANNOT_BEGIN = -2  # run_agent_trials' answer when the agent cannot begin a trial
# the agent's kernels (agent.protocol.TrialKernels), bound by loop_for's copies
agent_begin = agent_act = agent_learn = None


def loop_for(kernels):
    """:func:`run_agent_trials` for an agent's kernels (a ``TrialKernels``), compiled once each."""
    return _loop_for(kernels)


@cache
def _loop_for(kernels):
    """:func:`loop_for`, cached by its kernels."""
    return specialise(run_agent_trials, agent_begin=kernels.begin, agent_act=kernels.act,
                      agent_learn=kernels.learn)


@jit
def run_agent_trials(until_steps, max_trials, world, robot, agent, trials_rng, shuffle_rng,
                     act_rng, counters, records) -> int:
    """Trials until the learning time reaches ``until_steps``; -1 if objects cannot be placed.

    ``robot``: the robot's mechanisms (:class:`~.inputs.LoopMechanisms`); ``agent``: the
    agent's state (its ``compiled_state``), whose ``act`` draws from ``act_rng``;
    ``counters``: the learning time and the trials so far. A frozen robot runs ``max_trials``
    trials; :data:`CANNOT_BEGIN` if the agent cannot begin one (a frozen agent that has seen
    no face). ``records`` take the compiled loop's columns (:data:`._loop.COLUMNS`).
    """
    n = world.n_objects
    obj_pos, obj_rad, edge = np.empty((n, 3)), np.empty(n), np.empty(n)
    arrays, camera = look_arrays(n), look_camera(world, robot.d_th_px)
    c, lim = counters, world.limits_rad
    while (c[0] < until_steps or not robot.learning) and c[1] < max_trials:
        start = c[0]
        # the scene (cells.random_scene, FastScene.sample)
        k, target, shown = draw_trial(world, trials_rng, shuffle_rng, obj_pos, obj_rad, edge)
        if target < 0:
            return -1
        # the agent begins (RLAgent.begin_trial)
        if not agent_begin(agent, world.faces[shown], robot.learning):
            return CANNOT_BEGIN
        # the trial (SceneTrial, run_trial)
        pan, tilt = world.theta_face_rad[k, 0], world.theta_face_rad[k, 1]
        n_steps, n_lm, end, attended, limit_hit = 0, 0, -1, -1, False
        while True:
            _, _, end, attended = look(obj_pos, obj_rad, edge, pan, tilt, camera, limit_hit,
                                       n_steps, robot.max_steps, arrays)
            if end != RUNNING:
                break
            # the agent acts (RLAgent.act); its other steps are neither LM nor random
            c[0] += robot.learning
            d_pan, d_tilt, lm = agent_act(agent, pan, tilt, act_rng)
            n_lm += lm
            # the head moves, stopping at its joint limits (SceneTrial.step)
            pan, tilt, limit_hit = move_head(pan, tilt, d_pan, d_tilt, lim[0], lim[1], lim[2],
                                             lim[3])
            n_steps += 1
        if robot.learning:  # the agent learns (RLAgent.end_trial)
            agent_learn(agent, end == END_FIRED, pan, tilt)
        record_trial(records, c, start, n_steps, n_lm, 0, attended, target, end)
    return 0
