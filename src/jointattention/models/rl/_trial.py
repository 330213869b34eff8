"""The reinforcement learner's part of a trial (:mod:`.agent`), as compiled kernels of its state.

:class:`~.agent.RLAgent` (step by step) and the compiled engine's loop
(:mod:`jointattention.experiment.compiled._rl_loop`) call the same kernels on the same arrays
(:class:`RLArrays`), so both give the same cells. :data:`KERNELS` are its whole trial
(:class:`~jointattention.agent.protocol.TrialKernels`): the compiled loop is handed them and
names none of the model's options. The equations are :mod:`._kernels`'.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..._jit import jit
from ...agent.face_standardiser import standardise, welford_update
from ...agent.protocol import TrialKernels
from ._kernels import rl_choice_odds, rl_choose, rl_learn, rl_values_into

__all__ = ["KERNELS", "MOVES", "SHIFT", "STAYS", "RLArrays", "rl_act", "rl_begin", "rl_end"]

STAYS, SHIFT, MOVES = range(3)  # the entries of RLArrays.trial


class RLArrays(NamedTuple):
    """The RL agent's options, learned arrays and a trial's decisions, as its kernels take them.

    The arrays are the agent's own (changed in place): its values, its habituation, its face
    statistics (:class:`~jointattention.agent.face_standardiser.FaceStandardiser`'s) and the
    trial's scratch (see :meth:`~.agent.RLAgent.compiled_state`).
    """

    steps_rad: np.ndarray  # (n_directions, 2): one step along each shift direction
    min_std: float  # the face statistics' least s.d.
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
    cell_rad: float  # its cells' side
    w: np.ndarray  # (n_directions, pixels): the shift values' weights
    b: np.ndarray  # (n_directions,): their biases
    q_stay: np.ndarray  # (max_steps + 1,): the stay values
    habituation: np.ndarray  # (pan cells, tilt cells): the places' habituation
    mean: np.ndarray  # the faces' running statistics
    m2: np.ndarray
    faces_seen: np.ndarray  # (1,): FaceStandardiser.seen, the same array
    x: np.ndarray  # the trial's face, standardised
    q: np.ndarray  # its shift values
    cdf: np.ndarray  # the shift values' cumulative softmax
    p_stay: np.ndarray  # the odds of staying after k stays
    trial: np.ndarray  # (3,) int: stays so far, the shift's direction (-1: none), its moves


@jit
def rl_begin(s, face, learning) -> bool:
    """The trial starts at the caregiver's face: its shift values and the choice odds.

    Learning, the face statistics take in the face first. Per step, staying has probability
    ``p_stay[k]``; a shift's direction is drawn from the softmax over the shift values alone
    (``cdf``): together, the softmax over all actions (:func:`~._kernels.rl_choice_odds`).
    False if no face was ever seen (a frozen agent has nothing to standardise by).
    """
    if learning:
        s.faces_seen[0] += 1
        welford_update(face, s.mean, s.m2, s.faces_seen[0])
    if s.faces_seen[0] == 0:
        return False
    standardise(face, s.mean, s.m2, s.faces_seen[0], s.min_std, s.x)
    rl_values_into(s.x, s.w, s.b, s.q)
    rl_choice_odds(s.q, s.q_stay, s.temperature, s.cdf, s.p_stay)
    s.trial[STAYS], s.trial[SHIFT], s.trial[MOVES] = 0, -1, 0
    return True


@jit(inline=True)  # into the compiled loop: its arrays not counted in and out at each step
def rl_act(s, pan, tilt, rng) -> tuple[float, float, bool]:
    """One step: stay, shift (a softmax draw from ``rng``) or keep moving along the shift.

    Returns the step and whether it moves (a shift, module ``lm``); a stay is no move. The
    head angle is not used: the decisions depend on the face alone.
    """
    t = s.trial
    if t[SHIFT] >= 0:
        t[MOVES] += 1
    else:
        d = rl_choose(rng.random(), s.p_stay[min(t[STAYS], len(s.p_stay) - 1)], s.cdf)
        if d < 0:
            t[STAYS] += 1
            return 0.0, 0.0, False
        t[SHIFT], t[MOVES] = d, 1
    return s.steps_rad[t[SHIFT], 0], s.steps_rad[t[SHIFT], 1], True


@jit
def rl_end(s, fired, pan, tilt) -> None:
    """A learning trial's end at head angle (``pan``, ``tilt``): reward, habituate, SARSA.

    Reads only whether the evaluator ``fired``, never the caregiver's judgement
    (:func:`~._kernels.rl_learn`).
    """
    t = s.trial
    rl_learn(fired, pan, tilt, t[STAYS], t[SHIFT], t[MOVES], s.x, s.q, s.w, s.b, s.q_stay,
             s.habituation, s.lo_rad, s.cell_rad, s.face_reward, s.face_habituation,
             s.object_reward, s.place_habituation, s.place_recovery, s.gamma,
             s.learning_rate_shift, s.learning_rate_stay)


KERNELS = TrialKernels(rl_begin, rl_act, rl_end)
