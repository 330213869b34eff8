"""The compiled engine's loop over a cell's trials of the reinforcement learner.

:mod:`.rl_cell` packs its inputs and drives it. Each trial draws as the step-by-step path
draws (:func:`~.cells.random_scene`, then :class:`~.trial.SceneTrial` and
:func:`~.trial.run_trial` of an :class:`~jointattention.models.rl.RLAgent`) and calls the same
kernels (:mod:`jointattention.models._rl_kernels`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..._jit import jit
from ...agent.face_standardiser import standardise, welford_update
from ...models._rl_kernels import rl_choice_odds, rl_choose, rl_learn, rl_values_into
from ..trial import END_FIRED, RUNNING, move_head
from .steps import draw_trial, look, look_arrays, look_camera

__all__ = ["NO_FACE_STATISTICS", "RLRobot", "RLState", "run_rl_trials"]

NO_FACE_STATISTICS = -2  # run_rl_trials' answer for a frozen learner that has seen no face


class RLRobot(NamedTuple):
    """The RL agent's options and mechanisms as the loop takes them."""

    d_th_px: float
    max_steps: int
    steps_rad: np.ndarray  # (n_directions, 2): one step along each shift direction
    min_std: float
    temperature: float
    face_reward: float
    face_habituation: float
    object_reward: float
    place_habituation: float
    place_recovery: float
    gamma: float
    learning_rate_shift: float
    learning_rate_stay: float
    lo_rad: np.ndarray  # the habituation grid's origin
    cell_rad: float
    learning: bool


class RLState(NamedTuple):
    """The RL agent's learned arrays and the counters, changed in place."""

    w: np.ndarray
    b: np.ndarray
    q_stay: np.ndarray
    habituation: np.ndarray
    mean: np.ndarray
    m2: np.ndarray
    counters: np.ndarray  # learning time, faces seen, records


@jit
def run_rl_trials(until_steps, max_trials, world, robot, state, trials_rng, shuffle_rng,
                  choice_rng, records) -> int:
    """Trials until the learning time reaches ``until_steps``; -1 if objects cannot be placed.

    A frozen robot runs ``max_trials`` trials (-2 if it has seen no face to standardise by).
    ``records`` take the compiled loop's columns (:data:`._loop.COLUMNS`).
    """
    n, n_pix = world.n_objects, world.faces.shape[1]
    obj_pos, obj_rad, edge = np.empty((n, 3)), np.empty(n), np.empty(n)
    arrays, camera = look_arrays(n), look_camera(world, robot.d_th_px)
    n_dir = len(robot.steps_rad)
    x, q, cdf = np.empty(n_pix), np.empty(n_dir), np.empty(n_dir)
    p_stay = np.empty(len(state.q_stay))
    c = state.counters
    while (c[0] < until_steps or not robot.learning) and c[2] < max_trials:
        start = c[0]
        # the scene (cells.random_scene, FastScene.sample)
        k, target, shown = draw_trial(world, trials_rng, shuffle_rng, obj_pos, obj_rad, edge)
        if target < 0:
            return -1
        face = world.faces[shown]
        # the agent begins (RLAgent.begin_trial)
        if robot.learning:
            c[1] += 1
            welford_update(face, state.mean, state.m2, c[1])
        if c[1] == 0:
            return NO_FACE_STATISTICS
        standardise(face, state.mean, state.m2, c[1], robot.min_std, x)
        rl_values_into(x, state.w, state.b, q)
        rl_choice_odds(q, state.q_stay, robot.temperature, cdf, p_stay)
        n_stays, shift, n_moves = 0, -1, 0
        # the trial (SceneTrial, run_trial)
        pan, tilt = world.theta_face_rad[k, 0], world.theta_face_rad[k, 1]
        n_steps, n_lm, end, attended = 0, 0, -1, -1
        limit_hit = False
        while True:
            _, _, end, attended = look(obj_pos, obj_rad, edge, pan, tilt, camera, limit_hit,
                                       n_steps, robot.max_steps, arrays)
            if end != RUNNING:
                break
            # the agent acts (RLAgent.act)
            c[0] += robot.learning
            if shift >= 0:
                n_moves += 1
            else:
                shift = rl_choose(choice_rng.random(),
                                  p_stay[min(n_stays, len(p_stay) - 1)], cdf)
                if shift < 0:
                    n_stays += 1
                else:
                    n_moves = 1
            d_pan = d_tilt = 0.0  # a stay
            if shift >= 0:
                d_pan, d_tilt = robot.steps_rad[shift, 0], robot.steps_rad[shift, 1]
                n_lm += 1
            lim = world.limits_rad
            pan, tilt, limit_hit = move_head(pan, tilt, d_pan, d_tilt, lim[0], lim[1], lim[2],
                                             lim[3])
            n_steps += 1
        if robot.learning:  # RLAgent.end_trial
            rl_learn(end == END_FIRED, pan, tilt, n_stays, shift, n_moves, x, q, state.w,
                     state.b, state.q_stay, state.habituation, robot.lo_rad, robot.cell_rad,
                     robot.face_reward, robot.face_habituation, robot.object_reward,
                     robot.place_habituation, robot.place_recovery, robot.gamma,
                     robot.learning_rate_shift, robot.learning_rate_stay)
        r = c[2]
        records[0, r], records[1, r], records[2, r], records[3, r] = start, n_steps, n_lm, 0
        records[4, r], records[5, r], records[6, r] = attended, target, end
        c[2] += 1
    return 0
