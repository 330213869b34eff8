"""The compiled engine's door: whole cells of learning in fast perception, in one loop.

It runs what :func:`~..cells.run_cell` runs step by step (scene sampling, projection and the fast
detector, Eq. 1-3, the gate, the learning module) as one compiled loop over trials (in
:mod:`._loop`; this module packs its inputs and drives it). It calls
the same kernels as the step-by-step path (:mod:`~jointattention.world.kinematics`,
:mod:`~jointattention.world.fast`, :mod:`~jointattention.world.placement`,
:mod:`~jointattention.agent.attention`, :mod:`~jointattention.models.bootstrap`, and the
learning module's own) and draws from the same random streams in the same order, so both give
byte-identical cells (``tests/test_compiled.py``).

It learns in place the arrays of a :class:`~jointattention.models.bootstrap.BootstrapAgent`,
so the learned agent is the same object either way. It runs the bootstrap model (every gate,
reading, and any learning module, which declares its kernels and state:
:class:`~jointattention.agent.protocol.ModuleKernels`, :func:`~._loop.loop_for`), its kin
that declare their own kernels (:class:`~jointattention.agent.protocol.AgentKernels`: the
teacher, and the one whose sight and caregiver change with time), and through :mod:`.rl_cell`
an agent whose whole trial is its own kernels
(:class:`~jointattention.agent.protocol.TrialKernels`: the reinforcement learner);
:func:`compiled_cell` picks the loop by the kernels the agent declares. Anything else is
refused (:func:`unsupported`).
"""

from __future__ import annotations

import numpy as np

from ...agent.protocol import TrialKernels
from ...config import WorldConfig
from ...datasets import CaregiverDatasets
from ...errors import ConfigError
from ...models.bootstrap import LEARNING_TARGETS, BootstrapAgent
from ...models.registry import ModelOptions
from ...world.kinematics import HeadKinematics
from ...world.mjcf import HEAD_RADII_M
from ...world.placement import region_of
from ._loop import COLUMNS, loop_for
from .inputs import LoopRobot, LoopState, LoopWorld, placed, trial_records
from .rl_cell import RLCell

__all__ = ["CompiledCell", "compiled_cell", "pack_world", "unsupported"]


def unsupported(options: ModelOptions) -> str | None:
    """Why the compiled engine cannot run ``options`` (None if it can): their own say.

    See :meth:`~jointattention.models.registry.ModelOptions.compiled_refusal`.
    """
    return options.compiled_refusal()


def compiled_cell(agent, world: LoopWorld, trials: np.random.Generator,
                  shuffle: np.random.Generator, max_trials: int) -> CompiledCell | RLCell:
    """The compiled cell of ``agent``'s model (the arguments are :class:`CompiledCell`'s).

    An agent whose kernels are a ``TrialKernels`` runs in an :class:`~.rl_cell.RLCell`.
    """
    if isinstance(getattr(agent, "kernels", None), TrialKernels):
        return RLCell(agent, world, trials, shuffle, max_trials)
    return CompiledCell(agent, world, trials, shuffle, max_trials)


def pack_world(world: WorldConfig, ds: CaregiverDatasets, target_m, face_m, n_objects: int,
               shuffle_faces: bool) -> LoopWorld:
    """The world, the data sets and the condition as the compiled loop takes them.

    ``target_m`` and ``face_m`` (K, 3) are where each data set's target and face are.
    """
    kin = HeadKinematics.from_config(world)
    region, offset, limits = region_of(world)
    return LoopWorld(int(n_objects), region, offset, limits, float(kin.focal_px), kin.width_px,
                  kin.height_px, HEAD_RADII_M[2], np.ascontiguousarray(ds.theta_face_rad, float),
                  np.ascontiguousarray(target_m, float), np.ascontiguousarray(face_m, float),
                  ds.views.reshape(len(ds), -1).astype(float), bool(shuffle_faces))


class CompiledCell:
    """One cell (a condition and a seed) learning in the compiled engine.

    Args:
        agent: the cell's untrained bootstrap agent (:func:`~.cells.make_agent`); it learns in
            place.
        world: the data sets, the world and the condition as :func:`pack_world` packs them.
        trials: the stream that draws each trial's data set and scene.
        shuffle: the stream that draws a random face (``shuffle_faces`` conditions).
        max_trials: the most trials the cell may hold.

    :meth:`run_until` learns up to a learning time; :meth:`records` are the trial records.
    """

    def __init__(self, agent: BootstrapAgent, world: LoopWorld, trials: np.random.Generator,
                 shuffle: np.random.Generator, max_trials: int):
        refusal = unsupported(agent.options)
        if refusal is not None:
            raise ConfigError(refusal)
        self.agent, self._world = agent, world
        self._trials, self._shuffle = trials, shuffle
        opts, shared = agent.options, agent.mechanisms
        self._robot = LoopRobot(
            np.asarray(shared.interest_weights, dtype=float), float(shared.vf_gain_rad_per_px),
            float(shared.d_th_px(world.width_px)), float(agent.step_rad),
            float(np.deg2rad(shared.line_capture_deg)), int(shared.max_steps),
            *opts.gate.compiled_inputs(), opts.gate_per == "trial",
            opts.vf_fallback == "lm", opts.vf_fallback == "sweep",
            LEARNING_TARGETS.index(opts.learning_target), opts.learn_from == "vf",
            bool(opts.taught), agent.learns_unfound, bool(agent.learning))
        faces = agent.faces
        self._state = LoopState(
            *faces.statistics(world.faces.shape[1]), faces.seen,
            np.array([agent.learning_time_steps, 0]), np.array([agent.agreement_]))
        # the agent's own part beyond its module (agent.protocol.AgentKernels): its state
        self._sight = agent.compiled_state(world.faces.shape[1])
        # the learning module's part (agent.protocol.ModuleKernels): its kernels and its state,
        # told how many faces the run shows (ids: the data sets' indices)
        self._module = agent.module.compiled_state(len(world.faces))
        self._records = np.zeros((len(COLUMNS), max_trials), dtype=np.int64)

    def run_until(self, learning_time_steps: int) -> None:
        """Learn trial after trial until the learning time reaches ``learning_time_steps``."""
        agent = self.agent
        loop = loop_for(agent.module.kernels, agent.kernels)
        placed(loop(learning_time_steps, self._records.shape[1], self._world, self._robot,
                    self._state, self._sight, self._module, self._trials, self._shuffle,
                    agent.gate_rng, agent.move_rng, agent.module.learn_rng, self._records),
               self._world)
        agent.learning_time_steps = int(self._state.counters[0])
        agent.agreement_ = float(self._state.agreement[0])
        agent.sync(self._sight)
        agent.module.sync(self._module)

    def records(self) -> dict[str, np.ndarray]:
        """The trial records so far (:data:`~.trial.RECORD`)."""
        return trial_records(self._records[:, : self._state.counters[1]])

