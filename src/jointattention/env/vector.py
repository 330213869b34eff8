"""A native vector environment: the modes without images, all episodes stepped in one kernel.

``gymnasium.make_vec("JointAttentionFace-v1", num_envs=N, vectorization_mode=
"vector_entry_point")`` gives :class:`JointAttentionVectorEnv`. Its sub-environments are those
of :class:`~.joint_attention.JointAttentionEnv` (the same episodes, steps and rewards as a
``SyncVectorEnv`` of them with the same seeds, tested); it moves every head, projects every
scene and evaluates every image in one compiled call per step, and starts the episodes that
start in one more (:mod:`._vector_kernels`): each drawn from its sub-environment's own
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
from ._vector_kernels import LOOK, STATE, STEP, clip_moves
from .joint_attention import JointAttentionEnv

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
        self._started = False
        self.render_mode = one.render_mode

    def _start(self, which: np.ndarray, seeds=None) -> None:
        """Start the episodes of sub-environments ``which`` from their own generators.

        ``seeds`` (one per sub-environment of ``which``, or None) seeds them first; a
        sub-environment that has none yet gets one, as ``Env.reset`` seeds.
        """
        for j, i in enumerate(which):
            seed = None if seeds is None else seeds[j]
            if seed is not None or self._rngs[i] is None:
                self._rngs[i], _ = seeding.np_random(seed)
                self._rng_list = None
        if self._rng_list is None:  # numba's list of the same generators (their states shared)
            from numba.typed import List

            self._rng_list = List(self._rngs)
        self._steps.start(self._episodes, self._rng_list, np.asarray(which, np.int64))

    def _look(self, mode: np.ndarray, dtheta: np.ndarray | None = None) -> tuple[dict, dict]:
        """Step, start or hold each sub-environment as ``mode`` says; what they show.

        One compiled call (:func:`~._vector_kernels.step_all`) into new arrays.
        """
        k = self.num_envs
        out = self._steps.outputs(k)
        self._steps.step(self._episodes, mode, np.zeros((k, 2)) if dtheta is None else dtheta,
                         out)
        self._out = out
        obs = {"head_angle": out["head"], "face": out["face"]}
        if self.obs_mode == "detections":
            obs["detections"] = out["rows"]
        area, edge, motion = out["det"]
        n_det, seen, attended, target = out["ints"]
        fired, limit_hit = out["flags"][:2]
        intrinsic, external, error = out["floats"]
        masks = iter(np.ones((15, k), bool))  # Gymnasium's "_key": every one has every key
        detections = {"centre_px": out["centre"], "_centre_px": next(masks),
                      "colour_area_px": area, "_colour_area_px": next(masks), "edge": edge,
                      "_edge": next(masks), "motion": motion, "_motion": next(masks)}
        info = {"detections": detections, "_detections": next(masks), "n_detections": n_det,
                "_n_detections": next(masks), "fired": fired, "_fired": next(masks),
                "seen": seen, "_seen": next(masks), "attended": attended,
                "_attended": next(masks), "target": target, "_target": next(masks),
                "limit_hit": limit_hit, "_limit_hit": next(masks),
                "intrinsic_reward": intrinsic, "_intrinsic_reward": next(masks),
                "external_reward": external, "_external_reward": next(masks),
                "caregiver_error_rad": error, "_caregiver_error_rad": next(masks)}
        return obs, info

    def reset(self, *, seed: int | list | None = None, options: dict | None = None):
        """Start an episode in every sub-environment (``seed + i`` for sub-environment i).

        ``seed``: None, an integer >= 0, or a list of ``num_envs`` seeds (each an integer >= 0
        or None). ``options``: none are taken (None or {}).
        """
        seeds = vector_seeds(seed, self.num_envs)
        refuse_options(options)
        self._start(np.arange(self.num_envs), seeds)
        out = self._look(np.full(self.num_envs, LOOK, np.int64))
        self._needs_reset[:] = False
        self._started = True
        return out

    def step(self, actions):
        """Step every sub-environment; those that ended start anew (see ``autoreset_mode``)."""
        if not self._started:
            raise gym.error.ResetNeeded("no episodes are running; expected reset() before "
                                        "step()")
        dtheta = self._dtheta_rad(actions)  # checked before any work
        restart = self._needs_reset
        if restart.any():
            self._start(np.flatnonzero(restart))
        # those that ended start with a look, and are not stepped this time
        obs, infos = self._look(STEP - restart, dtheta)
        terminated, truncated = self._out["flags"][2:]
        self._needs_reset = terminated | truncated
        rewards = infos[f"{self.reward}_reward"]  # the episodes just started: 0
        if self.autoreset_mode == AutoresetMode.SAME_STEP and self._needs_reset.any():
            obs, infos = self._restart_now(obs, infos)
        return obs, rewards, terminated, truncated, infos

    def _dtheta_rad(self, actions) -> np.ndarray:
        """Every head's move (pan, tilt) in radians for ``actions``: checked, clipped, scaled."""
        shape = (self.num_envs, 2)
        if not (type(actions) is np.ndarray and actions.shape == shape
                and actions.dtype.char in "fd"):
            actions = check_action(actions, shape, "actions")
        space, dtheta = self.single_action_space, np.empty(shape)
        if not clip_moves(actions, space.low, space.high, self._scale, dtheta):
            check_action(actions, shape, "actions")  # not finite: one error naming them
        return dtheta

    def _restart_now(self, obs: dict, infos: dict) -> tuple[dict, dict]:
        """Same-step autoreset: start the episodes that just ended, keeping their last look."""
        done = self._needs_reset.copy()
        final_obs = np.full(self.num_envs, None, object)
        for i in np.flatnonzero(done):
            final_obs[i] = {key: value[i] for key, value in obs.items()}
        self._start(np.flatnonzero(done))
        obs, new = self._look(done * LOOK)  # the others: their look as it stands (HOLD)
        self._needs_reset[:] = False
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
        return {**self.__dict__, "_rng_list": None, "_steps": None, "_out": None}

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

