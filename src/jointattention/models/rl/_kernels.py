"""The reinforcement learner's arithmetic (:mod:`.agent`), compiled.

One implementation of each of its equations, called by :class:`~.agent.RLAgent` step by step and
by the compiled engine's loop (:mod:`jointattention.experiment.compiled._rl_loop`), so that
both give the same cells.
"""

from __future__ import annotations

import math

from ..._jit import jit

__all__ = ["object_reward", "rl_cell", "rl_choice_odds", "rl_choose", "rl_learn",
           "rl_values_into", "stay_reward"]


@jit
def stay_reward(face_reward: float, face_habituation: float, k: int) -> float:
    """What looking at the caregiver pays after ``k`` steps of looking in the trial."""
    return face_reward * face_habituation ** float(k)


@jit
def object_reward(reward: float, habituation: float) -> float:
    """What finding an object pays at a place habituated ``habituation`` (0 to 1)."""
    return reward * (1.0 - habituation)


@jit
def rl_values_into(x, w, b, q) -> None:
    """The shift values ``q[d] = w[d] . x + b[d]`` of a standardised face ``x``."""
    for d in range(len(q)):
        s = 0.0
        for i in range(len(x)):
            s += w[d, i] * x[i]
        q[d] = s + b[d]


@jit
def _log1p_exp(z: float) -> float:
    """``log(1 + e^z)``, without overflow."""
    if z > 0:
        return z + math.log1p(math.exp(-z))
    return math.log1p(math.exp(z))


@jit
def rl_choice_odds(q, q_stay, temperature: float, cdf, p_stay) -> None:
    """The softmax over all actions, as a trial's draws use it.

    ``cdf``: the cumulative softmax over the shift values alone (its last value 1);
    ``p_stay[k]``: the probability of staying after ``k`` stays,
    ``1 / (1 + sum_d exp((q[d] - q_stay[k]) / temperature))``.
    """
    top = q[0]
    for d in range(len(q)):
        top = max(top, q[d])
    total = 0.0
    for d in range(len(q)):
        total += math.exp((q[d] - top) / temperature)
        cdf[d] = total
    for d in range(len(q)):
        cdf[d] /= total
    cdf[len(q) - 1] = 1.0
    log_total = math.log(total)
    for k in range(len(p_stay)):
        p_stay[k] = math.exp(-_log1p_exp(log_total + (top - q_stay[k]) / temperature))


@jit
def rl_choose(u: float, p_stay: float, cdf) -> int:
    """The choice of a uniform draw ``u``: -1 to stay, else the shift's direction.

    Staying has probability ``p_stay``; otherwise ``u`` rescaled picks a direction from the
    shift values' cumulative softmax ``cdf`` (the first entry above it).
    """
    if u < p_stay:
        return -1
    v = (u - p_stay) / (1.0 - p_stay)
    lo, hi = 0, len(cdf)
    while lo < hi:  # bisect_right
        mid = (lo + hi) // 2
        if v < cdf[mid]:
            hi = mid
        else:
            lo = mid + 1
    return min(lo, len(cdf) - 1)


@jit
def rl_cell(pan_rad: float, tilt_rad: float, lo_rad, cell_rad: float, shape) -> tuple[int, int]:
    """The habituation grid's cell of a head angle (clipped to the grid)."""
    i = min(max(math.floor((pan_rad - lo_rad[0]) / cell_rad), 0), shape[0] - 1)
    j = min(max(math.floor((tilt_rad - lo_rad[1]) / cell_rad), 0), shape[1] - 1)
    return int(i), int(j)


@jit
def rl_learn(fired: bool, pan_rad: float, tilt_rad: float, n_stays: int, shift: int,
             n_moves: int, x, q, w, b, q_stay, habituation, lo_rad, cell_rad: float,
             face_reward: float, face_habituation: float, reward: float,
             place_habituation: float, place_recovery: float, gamma: float,
             learning_rate_shift: float, learning_rate_stay: float) -> None:
    """A trial's end: its reward, the places' habituation and the SARSA updates.

    ``n_stays`` stays, then the shift ``shift`` (-1: none) moved ``n_moves`` steps; the head
    ended at (``pan_rad``, ``tilt_rad``), where the evaluator ``fired`` or not. ``reward``
    is what an object pays at an unhabituated place.
    """
    i, j = rl_cell(pan_rad, tilt_rad, lo_rad, cell_rad, habituation.shape)
    r_end = object_reward(reward, habituation[i, j]) if fired else 0.0
    for a in range(habituation.shape[0]):
        for c in range(habituation.shape[1]):
            habituation[a, c] *= place_recovery
    if fired:
        h = habituation[i, j]
        habituation[i, j] = h + place_habituation * (1.0 - h)
    n = min(n_stays, len(q_stay))
    for k in range(n):  # each stay toward r_k + gamma Q(next decision); q_stay[k + 1] not yet
        nxt = q_stay[k + 1] if k < n - 1 else (q[shift] if shift >= 0 else 0.0)
        r = stay_reward(face_reward, face_habituation, k)
        q_stay[k] += learning_rate_stay * (r + gamma * nxt - q_stay[k])
    if shift >= 0:  # the shift toward its return, by normalised LMS
        delta = gamma ** float(n_moves - 1) * r_end - q[shift]
        xx = 0.0
        for p in range(len(x)):
            xx += x[p] * x[p]
        rate = learning_rate_shift * delta / (xx + 1.0)
        for p in range(len(x)):
            w[shift, p] += rate * x[p]
        b[shift] += rate
