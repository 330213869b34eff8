"""Discrete head moves: the ``-Discrete`` ids, for algorithms that take a ``Discrete`` action.

``JointAttentionFace-N1-Discrete-v2`` and its siblings are the v2 ids with the action a choice
of :data:`N_MOVES` head moves (:data:`MOVES_DEG`) instead of a continuous head-angle change;
everything else (observations, scenes, seeds, trial rules, rewards, ``caregivers=``) is the
v2 id's. :class:`DiscreteJointAttentionEnv` is the single environment,
:class:`DiscreteJointAttentionVectorEnv` the native vector one (``make_vec``'s
``vector_entry_point``).

The moves, in degrees (pan, tilt; positive pan turns right, positive tilt looks up):

| action | move | size |
|---|---|---|
| 0 | stay | none (Gymnasium's NOOP; the step counts) |
| 1, 2, 3, 4 | right, left, up, down | 4° |
| 5, 6, 7, 8 | right, left, up, down | 12° |

4° is the paper's learning-module step (``agent.lm_step_deg``), the step of the oracle
gaze-line follower whose success sets every ceiling; 12° is three of them, to cross the
27°-48° from the face to the object (5th-95th percentile with one object) in a few moves.
Both sizes are below the internal evaluator's diameter (2 x 6.9° at the default camera:
``d_th`` = W/6 = 53 px at a focal length of 440 px), so no move can jump over an object on
its line: a head stepping towards an object always stops on it. The continuous ids' action
1.0 is the visual controller's largest command, 22.9° of pan and 17.2° of tilt: a 12° move
is about half of it, a 4° move a sixth of the pan's.
"""

from __future__ import annotations

import numbers

import numpy as np
from gymnasium import spaces
from gymnasium.vector.utils import batch_space

from .._checks import short_repr
from ..errors import ArgumentError, ConfigError
from .joint_attention import JointAttentionEnv
from .vector import JointAttentionVectorEnv

__all__ = ["MOVES_DEG", "N_MOVES", "DiscreteJointAttentionEnv",
           "DiscreteJointAttentionVectorEnv", "check_move", "check_moves"]

SMALL_DEG, LARGE_DEG = 4.0, 12.0
MOVES_DEG = np.array([(0, 0)] + [(s * p, s * t) for s in (SMALL_DEG, LARGE_DEG)
                                 for p, t in ((1, 0), (-1, 0), (0, 1), (0, -1))])
MOVES_DEG.setflags(write=False)
N_MOVES = len(MOVES_DEG)
_MOVES_RAD = np.deg2rad(MOVES_DEG)
_EXPECTED = f"an integer move in [0, {N_MOVES - 1}] (0 stay; 1-4 right, left, up, down by " \
            f"{SMALL_DEG:g}°; 5-8 by {LARGE_DEG:g}°)"


def check_move(action, name: str = "action") -> int:
    """One move: an integer (Python, NumPy, or a 0-d integer array) in [0, N_MOVES).

    Else one :class:`~jointattention.errors.ArgumentError` naming ``name`` (booleans and
    floats are refused: they are no move's number).
    """
    if isinstance(action, np.ndarray) and action.shape == () and action.dtype.kind in "iu":
        action = action[()]
    if (isinstance(action, bool | np.bool_) or not isinstance(action, numbers.Integral)
            or not 0 <= action < N_MOVES):
        raise ArgumentError(f"{name}={short_repr(action)}: expected {_EXPECTED}")
    return int(action)


def check_moves(actions, n: int, name: str = "actions") -> np.ndarray:
    """``n`` moves, one per sub-environment, as int64: else one ArgumentError naming ``name``."""
    a = None
    if not isinstance(actions, str | bytes):
        try:
            a = np.asarray(actions)
        except (TypeError, ValueError, OverflowError):  # ragged lists, huge integers
            a = None
    if a is None or a.dtype.kind not in "iu" or a.shape != (n,):
        got = f"shape {a.shape}, dtype {a.dtype}" if a is not None else \
            f"a {type(actions).__name__}"
        raise ArgumentError(f"{name}: {got}; expected ({n},) integers, each {_EXPECTED}")
    if a.size and not ((a >= 0) & (a < N_MOVES)).all():
        bad = a[(a < 0) | (a >= N_MOVES)][0]
        raise ArgumentError(f"{name}: holds {bad}; expected each {_EXPECTED}")
    return a.astype(np.int64)


def _refuse_normalize(normalize_actions) -> None:
    if normalize_actions is not False:
        raise ConfigError(f"normalize_actions={short_repr(normalize_actions)}: the discrete "
                          "ids' actions are moves, not scaled angles; expected it not given")


class DiscreteJointAttentionEnv(JointAttentionEnv):
    """:class:`~.joint_attention.JointAttentionEnv` with ``Discrete(9)`` head moves.

    **Action**: an integer in [0, 9), one of the moves of :data:`MOVES_DEG` (module
    docstring): 0 stays; 1, 2, 3, 4 turn the head right, left, up, down by 4°; 5, 6, 7, 8 the
    same by 12°. The head stops at its joint limits (which ends the episode, as in every id).
    Anything but such an integer (a float, a boolean, a number out of range) is one
    :class:`~jointattention.errors.ArgumentError` line.

    Everything else is :class:`~.joint_attention.JointAttentionEnv`'s, with the same
    arguments (``normalize_actions`` aside: there is nothing to scale): observations, the
    trial's rules, rewards, seeding, ``caregivers=``, copies that continue the episode.
    """

    def __init__(self, config=None, *, normalize_actions: bool = False, **kwargs):
        _refuse_normalize(normalize_actions)
        super().__init__(config, **kwargs)
        self.action_space = spaces.Discrete(N_MOVES)

    def _dtheta_rad(self, action) -> np.ndarray:
        """The move of ``action`` in radians (pan, tilt)."""
        return _MOVES_RAD[check_move(action)]


class DiscreteJointAttentionVectorEnv(JointAttentionVectorEnv):
    """:class:`~.vector.JointAttentionVectorEnv` with a move per sub-environment.

    ``step`` takes ``num_envs`` integers, each a move of :data:`MOVES_DEG`
    (``MultiDiscrete``); everything else is the vector environment's: the same episodes as a
    ``SyncVectorEnv`` of :class:`DiscreteJointAttentionEnv` with the same seeds.
    """

    def __init__(self, num_envs: int, max_episode_steps: int | None = None,
                 autoreset_mode="NextStep", *, normalize_actions: bool = False, **kwargs):
        _refuse_normalize(normalize_actions)
        super().__init__(num_envs, max_episode_steps, autoreset_mode, **kwargs)
        self.single_action_space = spaces.Discrete(N_MOVES)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self._clip = np.array([[-np.inf] * 2, [np.inf] * 2, [1.0] * 2])  # the moves as they are

    def _checked(self, actions) -> np.ndarray:
        """Every sub-environment's move in radians, (num_envs, 2)."""
        return _MOVES_RAD[check_moves(actions, self.num_envs)]
