"""The compiled engine's door: whole cells of learning in fast perception, in one loop.

It runs what :func:`~..cells.run_cell` runs step by step (scene sampling, projection and the fast
detector, Eq. 1-3, the gate, the learning module) as one compiled loop over trials (in
:mod:`._loop`; this module packs its inputs and drives it). It calls
the same kernels as the step-by-step path (:mod:`~jointattention.world.kinematics`,
:mod:`~jointattention.world.fast`, :mod:`~jointattention.world.placement`,
:mod:`~jointattention.agent.attention`, :mod:`~jointattention.models.network.learner`,
:mod:`~jointattention.models.bootstrap`) and draws from the same random streams in the same
order, so both give byte-identical cells (``tests/test_compiled.py``).

It learns in place the arrays of a :class:`~jointattention.models.bootstrap.BootstrapAgent`,
so the learned agent is the same object either way. It runs the bootstrap model (every gate,
reading, the network, the memory, and any learning module that declares its kernels, such
as the population code: :func:`~._loop.loop_for`), the teacher and the
developmental model, and the reinforcement learner through :mod:`.rl_cell`
(:func:`compiled_cell` picks the loop); anything else is refused (:func:`unsupported`).
"""

from __future__ import annotations

import numpy as np

from ...config import WorldConfig
from ...datasets import CaregiverDatasets
from ...errors import ConfigError
from ...models.bootstrap import LEARNING_TARGETS, BootstrapAgent
from ...models.registry import ModelOptions
from ...models.rl import RLAgent
from ...world.kinematics import HeadKinematics
from ...world.mjcf import HEAD_RADII_M
from ...world.placement import region_of
from ._loop import COLUMNS, loop_for
from .inputs import (
    LoopDevelopment,
    LoopMemory,
    LoopRobot,
    LoopState,
    LoopWorld,
    placed,
    trial_records,
)
from .rl_cell import RLCell

__all__ = ["CompiledCell", "compiled_cell", "pack_world", "unsupported"]


def unsupported(options: ModelOptions) -> str | None:
    """Why the compiled engine cannot run ``options`` (None if it can): their own say.

    See :meth:`~jointattention.models.registry.ModelOptions.compiled_refusal`.
    """
    return options.compiled_refusal()


def compiled_cell(agent, world: LoopWorld, trials: np.random.Generator,
                  shuffle: np.random.Generator, max_trials: int) -> CompiledCell | RLCell:
    """The compiled cell of ``agent``'s model (the arguments are :class:`CompiledCell`'s)."""
    if isinstance(agent, RLAgent):
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


def _loop_memory(memory, saccade_rad: float) -> LoopMemory:
    """The episodic memory as the loop takes it, with its module's longest move."""
    return LoopMemory(memory.projection, memory.lo_rad, float(memory.cell_rad),
                      int(memory.options.k_nearest), float(memory.radius_rad),
                      memory.options.keep == "in_view", *memory.kept_arrays()[:5],
                      memory.options.leave_out_empty, *memory.left_arrays()[:2],
                      memory.options.pass_over_left_out, memory.options.drop_left_out,
                      memory.options.recall_again, saccade_rad)


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
        memory = getattr(agent.module, "memory", None)  # the episodic module's
        caregiver = opts.caregiver_inputs(agent.body.face_size_px)
        self._robot = LoopRobot(
            np.asarray(shared.interest_weights, dtype=float), float(shared.vf_gain_rad_per_px),
            float(shared.d_th_px(world.width_px)), float(agent.step_rad), int(shared.max_steps),
            *opts.gate.compiled_inputs(), opts.gate_per == "trial",
            opts.vf_fallback == "lm", opts.vf_fallback == "sweep",
            LEARNING_TARGETS.index(opts.learning_target), opts.learn_from == "vf",
            int(opts.n_passes),
            agent.theta_mid_rad, agent.theta_half_rad, float(agent.faces.min_std),
            float(opts.learning_rate), float(opts.momentum),
            caregiver[0], bool(agent.learning))
        self._development = LoopDevelopment(*caregiver[2:]) if caregiver[1] else None
        learner, faces = agent.learner, agent.faces
        self._memory = (None if memory is None
                        else _loop_memory(memory, agent.module.saccade_rad))
        # a learning module on the kernel protocol (agent.protocol.ModuleKernels): its state
        self._kernels = agent.module.kernels
        self._module = None if self._kernels is None else agent.module.compiled_state()
        self._module_rng = getattr(agent.module, "replay_rng", agent.move_rng)  # a stand-in
        kept = (0, 0, 0) if memory is None else (*memory.kept_arrays()[5:], memory.n_left_)
        self._state = LoopState(
            learner.w1_, learner.b1_, learner.w2_, learner.b2_, *learner.velocity_,
            *faces.statistics(world.faces.shape[1]),
            np.array([agent.learning_time_steps, faces.n_seen_, learner.n_updates_, 0, *kept]),
            np.array([agent.agreement_]),
            np.array([getattr(agent, "criterion_rad_", 0.0),
                      getattr(agent, "approved_rate_", 0.0)]))
        self._records = np.zeros((len(COLUMNS), max_trials), dtype=np.int64)

    def run_until(self, learning_time_steps: int) -> None:
        """Learn trial after trial until the learning time reaches ``learning_time_steps``."""
        loop = loop_for(self._kernels)
        placed(loop(learning_time_steps, self._records.shape[1], self._world, self._robot,
                    self._state, self._memory, self._development, self._module, self._trials,
                    self._shuffle, self.agent.gate_rng, self.agent.move_rng, self._module_rng,
                    self._records), self._world)
        c = self._state.counters
        self.agent.learning_time_steps = int(c[0])
        self.agent.faces.n_seen_, self.agent.learner.n_updates_ = int(c[1]), int(c[2])
        self.agent.agreement_ = float(self._state.agreement[0])
        if hasattr(self.agent, "criterion_rad_"):  # the caregiver's criterion adapts
            self.agent.criterion_rad_, self.agent.approved_rate_ = map(float,
                                                                       self._state.caregiver)
        if self._module is not None:
            self.agent.module.sync(self._module)
        if hasattr(self.agent.module, "memory"):
            memory = self.agent.module.memory
            memory.n_stored_, memory.n_codes_, memory.n_left_ = int(c[4]), int(c[5]), int(c[6])

    def records(self) -> dict[str, np.ndarray]:
        """The trial records so far (:data:`~.trial.RECORD`)."""
        return trial_records(self._records[:, : self._state.counters[3]])

