"""The compiled engine for an agent whose whole trial is its own kernels: the RL model's.

It runs what :func:`~.cells.run_cell` runs step by step for an agent that declares
:class:`~jointattention.agent.protocol.TrialKernels` (the reinforcement learner,
:mod:`jointattention.models.rl`) as one compiled loop over trials (:mod:`._rl_loop`), drawing
from the same streams in the same order and calling the same kernels, so both give
byte-identical cells (``tests/test_compiled.py``). It learns the agent's own arrays in place,
and names none of its options: they are in the agent's state (``compiled_state``).
"""

from __future__ import annotations

import numpy as np

from ...agent.face_standardiser import NO_FACE_SEEN
from ...errors import ArgumentError
from ._loop import COLUMNS
from ._rl_loop import CANNOT_BEGIN, loop_for
from .inputs import LoopMechanisms, LoopWorld, placed, trial_records

__all__ = ["RLCell"]


class RLCell:
    """One cell of an agent whose whole trial is its own kernels, in the compiled engine.

    Args:
        agent: the cell's agent (its ``kernels``, a ``TrialKernels``; ``compiled_state``,
            ``act_rng``, ``mechanisms``, ``learning``, ``learning_time_steps``); it learns in
            place (frozen, it only acts).
        world: the data sets, the world and the condition (:func:`~.cell.pack_world`).
        trials: the stream that draws each trial's data set and scene.
        shuffle: the stream that draws a random face (``shuffle_faces`` conditions).
        max_trials: the most trials the cell may hold.
    """

    def __init__(self, agent, world: LoopWorld, trials: np.random.Generator,
                 shuffle: np.random.Generator, max_trials: int):
        self.agent, self._world = agent, world
        self._trials, self._shuffle = trials, shuffle
        shared = agent.mechanisms
        self._robot = LoopMechanisms(float(shared.d_th_px(world.width_px)),
                                     int(shared.max_steps), bool(agent.learning))
        self._state = agent.compiled_state(world.faces.shape[1])
        self._counters = np.array([agent.learning_time_steps, 0])  # learning time, records
        self._records = np.zeros((len(COLUMNS), max_trials), dtype=np.int64)

    def run_until(self, learning_time_steps: int) -> None:
        """Learn trial after trial until the learning time reaches ``learning_time_steps``."""
        loop = loop_for(self.agent.kernels)
        code = placed(loop(learning_time_steps, self._records.shape[1], self._world,
                           self._robot, self._state, self._trials, self._shuffle,
                           self.agent.act_rng, self._counters, self._records), self._world)
        if code == CANNOT_BEGIN:
            raise ArgumentError(NO_FACE_SEEN)
        self.agent.learning_time_steps = int(self._counters[0])

    def records(self) -> dict[str, np.ndarray]:
        """The trial records so far (:data:`~.trial.RECORD`)."""
        return trial_records(self._records[:, : self._counters[1]])
