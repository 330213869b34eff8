"""The compiled engine for the reinforcement learner (:mod:`jointattention.models.rl`).

It runs what :func:`~.cells.run_cell` runs step by step for an
:class:`~jointattention.models.rl.RLAgent` as one compiled loop over trials
(:mod:`._rl_loop`), drawing from the same streams in the same order and calling the same
kernels (:mod:`jointattention.models._rl_kernels`), so both give byte-identical cells
(``tests/test_compiled.py``). It learns the agent's own arrays in place.
"""

from __future__ import annotations

import numpy as np

from ...agent.face_standardiser import NO_FACE_SEEN
from ...errors import ArgumentError
from ...models.rl import RLAgent
from ._loop import COLUMNS
from ._rl_loop import NO_FACE_STATISTICS, RLRobot, RLState, run_rl_trials
from .inputs import LoopWorld, placed, trial_records

__all__ = ["RLCell", "loop_robot", "loop_state"]


class RLCell:
    """One cell of the reinforcement learner in the compiled engine.

    Args:
        agent: the cell's agent; it learns in place (frozen, it only acts).
        world: the data sets, the world and the condition (:func:`~.cell.pack_world`).
        trials: the stream that draws each trial's data set and scene.
        shuffle: the stream that draws a random face (``shuffle_faces`` conditions).
        max_trials: the most trials the cell may hold.
    """

    def __init__(self, agent: RLAgent, world: LoopWorld, trials: np.random.Generator,
                 shuffle: np.random.Generator, max_trials: int):
        self.agent, self._world = agent, world
        self._trials, self._shuffle = trials, shuffle
        self._robot = loop_robot(agent, world.width_px)
        self._state = loop_state(agent, world.faces.shape[1])
        self._records = np.zeros((len(COLUMNS), max_trials), dtype=np.int64)

    def run_until(self, learning_time_steps: int) -> None:
        """Learn trial after trial until the learning time reaches ``learning_time_steps``."""
        code = placed(run_rl_trials(learning_time_steps, self._records.shape[1], self._world,
                                    self._robot, self._state, self._trials, self._shuffle,
                                    self.agent.choice_rng, self._records), self._world)
        if code == NO_FACE_STATISTICS:
            raise ArgumentError(NO_FACE_SEEN)
        c = self._state.counters
        self.agent.learning_time_steps, self.agent.faces.n_seen_ = int(c[0]), int(c[1])

    def records(self) -> dict[str, np.ndarray]:
        """The trial records so far (:data:`~.trial.RECORD`)."""
        return trial_records(self._records[:, : self._state.counters[2]])


def loop_robot(agent: RLAgent, width_px: int) -> RLRobot:
    """The agent's options and mechanisms as the loop takes them, for images ``width_px`` wide."""
    o, faces = agent.options, agent.faces
    return RLRobot(
        float(agent.mechanisms.d_th_px(width_px)), int(agent.mechanisms.max_steps),
        np.ascontiguousarray(agent.steps_rad), float(faces.min_std), float(o.temperature),
        float(o.face_reward), float(o.face_habituation), float(o.object_reward),
        float(o.place_habituation), float(o.place_recovery), float(o.gamma),
        float(o.learning_rate_shift), float(o.learning_rate_stay), agent.lo_rad,
        float(agent.cell_rad), bool(agent.learning))


def loop_state(agent: RLAgent, n_pixels: int) -> RLState:
    """The agent's own learned arrays (changed in place) and counters, as the loop takes them."""
    return RLState(agent.W_, agent.b_, agent.q_stay_, agent.place_habituation_,
                   *agent.faces.statistics(n_pixels),
                   np.array([agent.learning_time_steps, agent.faces.n_seen_, 0]))
