"""A native vector environment: the modes without images, all episodes stepped in one kernel.

``gymnasium.make_vec("JointAttentionFace-v1", num_envs=N, vectorization_mode=
"vector_entry_point")`` gives :class:`JointAttentionVectorEnv`. Its sub-environments are those
of :class:`~.joint_attention.JointAttentionEnv` (the same episodes, steps and rewards as a
``SyncVectorEnv`` of them with the same seeds, tested); it moves every head, projects every
scene and evaluates every image in one compiled call per step, which first starts the episodes
that start (:mod:`._vector_kernels`): each drawn from its sub-environment's own
generator by the kernel that draws the single environment's and the runner's scenes
(:func:`~jointattention.world.fast.draw_objects`).
"""

from __future__ import annotations

from typing import ClassVar

import gymnasium as gym
import numpy as np
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode
from gymnasium.vector.utils import batch_space

from .._checks import check_int
from ..errors import ConfigError
from ._args import check_action, refuse_options, vector_seeds
from ._fast_trial import Episodes
from ._observation import DETECTION_MASKS, STEP_MASKS, info_dict
from ._vector_kernels import FLAGS, HOLD, NOT_FINITE, STATE, STEP, step_all
from .joint_attention import JointAttentionEnv

_N_MASKS = len(DETECTION_MASKS) + len(STEP_MASKS)  # Gymnasium's "_key" masks of info

__all__ = ["MAX_ENVS", "JointAttentionVectorEnv"]

MAX_ENVS = 100_000  # sub-environments: each holds a few arrays of n_objects rows


class JointAttentionVectorEnv(gym.vector.VectorEnv):
    """``num_envs`` episodes of the ``"face"`` or ``"detections"`` mode, stepped together.

    Args:
        num_envs: how many sub-environments.
        max_episode_steps: the step limit (from the registration; ``max_steps`` wins if given).
        **kwargs: those of :class:`~.joint_attention.JointAttentionEnv` (not ``"image"`` mode).

        autoreset_mode: when an episode that ended starts anew (Gymnasium's modes):
            ``"NextStep"`` (default; the next ``step`` restarts it and ignores its action) or
            ``"SameStep"`` (it restarts in the step that ends it: the step returns the new
            episode's observation, and the last one in ``info["final_obs"]``, with the last
            info in ``info["final_info"]``; what Stable-Baselines3 expects).

    Seeds as ``SyncVectorEnv``: ``reset(seed=s)`` seeds sub-environment ``i`` with ``s + i``;
    a list gives one seed (or None) per sub-environment. A seed of another kind, a list of
    another length or a malformed action (not ``num_envs`` x 2 finite numbers; booleans are
    not numbers here) raises one :class:`~jointattention.errors.ArgumentError` naming it, as
    the single environment does. The environment pickles and deep-copies at any time, and a
    copy continues every episode as the original would.
    ``render()`` (``render_mode="rgb_array"``) shows the first sub-environment's face window.
    """

    metadata: ClassVar[dict] = {"autoreset_mode": AutoresetMode.NEXT_STEP,
                                "render_modes": ["rgb_array"]}

    def __init__(self, num_envs: int, max_episode_steps: int | None = None,
                 autoreset_mode: str | AutoresetMode = AutoresetMode.NEXT_STEP, **kwargs):
        self.num_envs = check_int("num_envs", num_envs, 1, MAX_ENVS)
        modes = (AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP)
        if autoreset_mode not in modes and autoreset_mode not in [m.value for m in modes]:
            raise ConfigError(f"autoreset_mode={autoreset_mode!r}: expected "
                              f"{' or '.join(repr(m.value) for m in modes)}")
        self.autoreset_mode = AutoresetMode(autoreset_mode)
        self.metadata = {**self.metadata, "autoreset_mode": self.autoreset_mode}
        if kwargs.get("max_steps") is None and max_episode_steps is not None:
            kwargs["max_steps"] = max_episode_steps
        if kwargs.get("obs_mode", "image") == "image":
            raise ConfigError("obs_mode='image': the native vector environment steps the modes "
                              "without images; expected 'face' or 'detections' (or make_vec's "
                              "async mode for images)")
        if kwargs.get("render_mode") == "human":
            raise ConfigError("render_mode='human': a window shows one environment; expected "
                              "None or 'rgb_array' (the first sub-environment's face window)")
        # One environment knows the spaces, the world and the data sets; each sub-environment
        # has only its own generator, drawn as Env.reset draws it.
        self._env = one = JointAttentionEnv(**kwargs)
        self._rngs: list[np.random.Generator | None] = [None] * self.num_envs
        self._rng_list = None  # the same generators, as the start kernel takes them
        self.obs_mode, self.max_steps, self.reward = one.obs_mode, one.max_steps, one.reward
        self.single_observation_space = one.observation_space
        self.single_action_space = one.action_space
        self.observation_space = batch_space(one.observation_space, self.num_envs)
        self.action_space = batch_space(one.action_space, self.num_envs)
        self._steps = one._fast  # the world, camera and data sets, as the kernels take them
        self._episodes = Episodes(self.num_envs, one.n_objects)
        self._scale = one.max_step_rad if one.normalize_actions else np.ones(2)
        self._needs_reset = np.ones(self.num_envs, bool)
        self._no_moves = np.zeros((self.num_envs, 2))
        self._moves = np.empty((self.num_envs, 2))  # a step's moves: the kernels' alone
        space = self.single_action_space  # the moves: actions clipped to it, then scaled
        self._clip = np.array([space.low, space.high, self._scale], float)
        self._reward_key = f"{one.reward}_reward"
        self._fixed = self._start_fixed = self._packed = None
        self._same_step = self.autoreset_mode == AutoresetMode.SAME_STEP
        self._started = False
        self.render_mode = one.render_mode

    def _start(self, starts: np.ndarray, seeds=None) -> None:
        """Start the episodes of the sub-environments where ``starts`` (bool) is true.

        Each from its own generator. ``seeds`` (one per sub-environment, or None) seeds them
        first; a sub-environment that has none yet gets one, as ``Env.reset`` seeds.
        """
        if seeds is not None or self._rng_list is None:
            for i in np.flatnonzero(starts):
                seed = None if seeds is None else seeds[i]
                if seed is not None or self._rngs[i] is None:
                    self._rngs[i], _ = seeding.np_random(seed)
                    self._rng_list = self._packed = None  # packed with the list: anew
        self._steps.start(self._episodes, self._generators(), starts)

    def _generators(self):
        """The sub-environments' generators in numba's list (their states shared)."""
        if self._rng_list is None:
            from numba.typed import List

            self._rng_list = List(self._rngs)
        return self._rng_list

    def _look(self, starts: np.ndarray, then: int = HOLD, actions: np.ndarray | None = None
              ) -> tuple[dict, dict]:
        """Look once at the episodes that ``starts``, step or hold the others (``then``).

        One compiled call (:func:`~._vector_kernels.step_all`) into new arrays; what the
        sub-environments show. With ``actions`` (a step's, checked but for being finite), the
        episodes of ``starts`` start in the same call, from their generators as they stand, and
        the others move (:func:`~._vector_kernels.start_step_all`). ``self._ends``:
        terminated, truncated, and the two together.
        """
        if self._fixed is None:  # the kernels' arguments that no step changes
            self._fixed = self._steps.kernel_args(self._episodes)
            self._start_fixed = self._steps.start_args()
        out = self._steps.outputs(self.num_envs, masks=_N_MASKS)
        if actions is None:
            step_all(starts, then, self._no_moves, *self._fixed, *out)
        else:
            if self._packed is None:  # one argument for the step's fixed ones (it imports numba)
                from ._vector_args import pack, step_packed

                gens, (targets, faces, radius, *region), (cam, *rest) = (
                    self._generators(), self._start_fixed, self._fixed)
                self._packed = (step_packed, pack(gens, targets, faces, radius, *region,
                                                  self._clip, self._moves, cam, *rest))
            step, packed = self._packed
            code = step(packed, starts, then, actions, *out)
            if code == NOT_FINITE:
                check_action(actions, self._moves.shape, "actions")  # one error naming them
            self._steps.check_started(code)
        head, face, rows, centre, det, ints, flags, floats = out
        obs = {"head_angle": head, "face": face}
        if self.obs_mode == "detections":
            obs["detections"] = rows
        # rows as lists of views: a third quicker than unpacking them one by one, at x64
        (area, edge, motion), (n_det, seen, attended, target) = list(det), list(ints)
        (intrinsic, external, error), f = list(floats), list(flags)
        # the flags (FLAGS), then Gymnasium's "_key" masks: every sub-environment has every key
        fired, limit_hit, masks = f[0], f[1], f[len(FLAGS):]
        self._ends = f[2], f[3], f[4]  # terminated, truncated, either
        return obs, info_dict((centre, area, edge, motion), (
            n_det, fired, seen, attended, target, limit_hit, intrinsic, external, error), masks)

    def reset(self, *, seed: int | list | None = None, options: dict | None = None):
        """Start an episode in every sub-environment (``seed + i`` for sub-environment i).

        ``seed``: None, an integer >= 0, or a list of ``num_envs`` seeds (each an integer >= 0
        or None). ``options``: none are taken (None or {}).
        """
        seeds = vector_seeds(seed, self.num_envs)
        refuse_options(options)
        every = np.ones(self.num_envs, bool)
        self._start(every, seeds)
        out = self._look(every)
        self._needs_reset = np.zeros(self.num_envs, bool)
        self._started = True
        return out

    def step(self, actions):
        """Step every sub-environment; those that ended start anew (see ``autoreset_mode``)."""
        if not self._started:
            raise gym.error.ResetNeeded("no episodes are running; expected reset() before "
                                        "step()")
        actions = self._checked(actions)  # before any work (finite: in the kernel, first)
        # those that ended start (in the same call) with a look, and are not stepped this time
        obs, infos = self._look(self._needs_reset, STEP, actions)
        terminated, truncated, self._needs_reset = self._ends
        rewards = infos[self._reward_key]  # the episodes just started: 0
        if self._same_step and self._needs_reset.any():
            obs, infos = self._restart_now(obs, infos)
        return obs, rewards, terminated, truncated, infos

    def _checked(self, actions) -> np.ndarray:
        """``actions`` as floats of shape (num_envs, 2), or one error naming what is wrong.

        Whether each is finite is checked by the step's kernel, before it changes anything.
        """
        shape = self._moves.shape
        if not (type(actions) is np.ndarray and actions.shape == shape
                and actions.dtype.char in "fd"):
            actions = check_action(actions, shape, "actions")
        return actions

    def _restart_now(self, obs: dict, infos: dict) -> tuple[dict, dict]:
        """Same-step autoreset: start the episodes that just ended, keeping their last look."""
        done = self._needs_reset.copy()
        final_obs = np.full(self.num_envs, None, object)
        for i in np.flatnonzero(done):
            final_obs[i] = {key: value[i] for key, value in obs.items()}
        self._start(done)
        obs, new = self._look(done)  # the others: their look as it stands
        self._needs_reset = np.zeros(self.num_envs, bool)
        return obs, {**new, "final_obs": final_obs, "_final_obs": done,
                     "final_info": _masked(infos, done), "_final_info": done}

    def render(self):
        """With ``render_mode="rgb_array"``: the first sub-environment's face window, as RGB."""
        if self.render_mode != "rgb_array":
            return None
        face = self._env._datasets.face[self._episodes.state[0, STATE.index("face_k")]]
        return np.repeat(face[..., None], 3, axis=2)

    def close_extras(self, **kwargs) -> None:
        """Nothing to free: no renderer."""

    def __getstate__(self) -> dict:
        """All of it but numba's list of the generators, which does not pickle.

        The generators themselves pickle (their states are the list's: see ``_start``), so a
        copy continues every episode as the original would; its list is made anew at its
        first start. The kernels' view of the world is its one environment's, not copied twice.
        """
        return {**self.__dict__, "_rng_list": None, "_steps": None, "_ends": None,
                "_fixed": None, "_start_fixed": None, "_packed": None}

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)
        self._steps = self._env._fast


def _masked(info: dict, mask: np.ndarray) -> dict:
    """``info`` for the sub-environments in ``mask`` only: zeros elsewhere, masks set to it."""
    def part(key: str, value: np.ndarray) -> np.ndarray:
        if key.startswith("_"):
            return mask.copy()
        return np.where(mask.reshape(-1, *[1] * (value.ndim - 1)), value, np.zeros_like(value))

    return {key: _masked(value, mask) if isinstance(value, dict) else part(key, value)
            for key, value in info.items()}

