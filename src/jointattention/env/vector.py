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
from ..experiment.cells import trial_geometries
from ..experiment.trial import END_FIRED, END_LIMIT, END_STEPS, RUNNING
from ..world.kinematics import separation_rad
from ..world.mjcf import HEAD_RADII_M
from ..world.placement import region_of
from ._args import check_action, refuse_options, vector_seeds
from ._looks import DETECTION_COLUMNS, MAX_DETECTIONS, _row_bounds, scaled
from ._vector_kernels import rows_all, start_all, step_all
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
        kin, cfg = one.kinematics, one.config
        n = one.n_objects
        self._kin, self._n = kin, n
        self._d_th_px = cfg.agent.d_th_px(kin.width_px)
        self._lo = np.array([kin.pan_limits_rad[0], kin.tilt_limits_rad[0]])
        self._hi = np.array([kin.pan_limits_rad[1], kin.tilt_limits_rad[1]])
        self._offset_m = np.asarray(kin.offset_m, float)
        self._scale = one.max_step_rad if one.normalize_actions else np.ones(2)
        self._targets_m, self._faces_m = trial_geometries(one._datasets, kin,
                                                          cfg.world.caregiver.distance_m)
        self._region = region_of(cfg.world)
        self._alloc(self.num_envs, n)
        self._needs_reset = np.ones(self.num_envs, bool)
        self._started = False
        self.render_mode = one.render_mode

    def _alloc(self, k: int, n: int) -> None:
        f, i = np.zeros, np.int64
        self._theta, self._pos, self._radius = f((k, 2)), f((k, n, 3)), f((k, n))
        self._edge, self._target, self._face_k = f((k, n)), np.zeros(k, i), np.zeros(k, i)
        self._n_steps, self._end = np.zeros(k, i), np.full(k, RUNNING, i)
        self._limit_hit, self._attended = np.zeros(k, bool), np.full(k, -1, i)
        self._seen, self._n_det = np.full(k, -1, i), np.zeros(k, i)
        self._centre, self._area = f((k, n, 2)), f((k, n))
        self._seen_edge, self._ids = f((k, n)), np.zeros((k, n), i)

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
        failed = start_all(self._rng_list, np.asarray(which, np.int64), self._targets_m,
                           self._faces_m, HEAD_RADII_M[2], *self._region,
                           self._env._datasets.theta_face_rad, self._lo, self._hi, self._pos,
                           self._radius, self._edge, self._face_k, self._target, self._theta,
                           self._n_steps, self._end, self._attended, self._limit_hit)
        if failed >= 0:
            raise ConfigError(
                f"objects: could not place {self._n} objects apart within the object region; "
                "expected fewer objects, a wider region or smaller gaps")

    def _look(self, which: np.ndarray) -> None:
        """The first look of the episodes just started: project and evaluate, no move."""
        end = np.full(self.num_envs, 0, np.int64)
        end[which] = RUNNING
        steps = self._n_steps.copy()
        steps[which] -= 1  # the kernel counts a step: take it back
        self._kernel(np.zeros((self.num_envs, 2)), end, steps)
        self._end[which] = np.where(end[which] == END_FIRED, END_FIRED, RUNNING)
        self._limit_hit[which] = False

    def _kernel(self, dtheta: np.ndarray, end: np.ndarray, steps: np.ndarray) -> None:
        kin = self._kin
        step_all(self._theta, dtheta, self._lo, self._hi, self._pos, self._radius, self._edge,
                  self._n, self._offset_m, float(kin.focal_px), kin.width_px,
                  kin.height_px, self._d_th_px, self.max_steps, steps, end, self._limit_hit,
                  self._attended, self._seen, self._n_det, self._centre, self._area,
                  self._seen_edge, self._ids)
        self._n_steps[:] = steps

    def reset(self, *, seed: int | list | None = None, options: dict | None = None):
        """Start an episode in every sub-environment (``seed + i`` for sub-environment i).

        ``seed``: None, an integer >= 0, or a list of ``num_envs`` seeds (each an integer >= 0
        or None). ``options``: none are taken (None or {}).
        """
        seeds = vector_seeds(seed, self.num_envs)
        refuse_options(options)
        self._start(np.arange(self.num_envs), seeds)
        self._look(np.arange(self.num_envs))
        self._needs_reset[:] = False
        self._started = True
        return self._observations(), self._infos()

    def step(self, actions):
        """Step every sub-environment; those that ended start anew (see ``autoreset_mode``)."""
        if not self._started:
            raise gym.error.ResetNeeded("no episodes are running; expected reset() before "
                                        "step()")
        dtheta = self._dtheta_rad(actions)  # checked before any work
        restart = np.flatnonzero(self._needs_reset)
        if len(restart):
            self._start(restart)
            self._look(restart)
        end = self._end.copy()
        end[restart] = END_FIRED  # not stepped this time
        running = end == RUNNING
        steps = self._n_steps.copy()
        self._kernel(dtheta, end, steps)
        self._end = np.where(running, end, self._end)
        terminated = running & ((self._end == END_FIRED) | (self._end == END_LIMIT))
        truncated = running & (self._end == END_STEPS)
        self._needs_reset = terminated | truncated
        infos = self._infos()  # the episodes just started have not fired: reward 0
        rewards = infos[f"{self.reward}_reward"]
        if self.autoreset_mode == AutoresetMode.SAME_STEP and self._needs_reset.any():
            infos = self._restart_now(infos)
        return self._observations(), rewards, terminated, truncated, infos

    def _dtheta_rad(self, actions) -> np.ndarray:
        """Every head's move (pan, tilt) in radians for ``actions``: checked, clipped, scaled."""
        actions = check_action(actions, (self.num_envs, 2), "actions")
        space = self.single_action_space
        return np.clip(actions, space.low, space.high) * self._scale

    def _restart_now(self, infos: dict) -> dict:
        """Same-step autoreset: start the episodes that just ended, keeping their last look."""
        done, last = self._needs_reset.copy(), self._observations()
        final_obs = np.full(self.num_envs, None, object)
        for i in np.flatnonzero(done):
            final_obs[i] = {key: value[i] for key, value in last.items()}
        self._start(np.flatnonzero(done))
        self._look(np.flatnonzero(done))
        self._needs_reset[:] = False
        return {**self._infos(), "final_obs": final_obs, "_final_obs": done,
                "final_info": _masked(infos, done), "_final_info": done}

    def render(self):
        """With ``render_mode="rgb_array"``: the first sub-environment's face window, as RGB."""
        if self.render_mode != "rgb_array":
            return None
        face = self._env._datasets.face[self._face_k[0]]
        return np.repeat(face[..., None], 3, axis=2)

    def _observations(self) -> dict:
        ds = self._env._datasets
        obs = {"head_angle": self._theta.astype(np.float32), "face": ds.face[self._face_k]}
        if self.obs_mode == "detections":
            rows = np.zeros((self.num_envs, MAX_DETECTIONS, len(DETECTION_COLUMNS)), np.float32)
            rows_all(self._centre, self._area, self._seen_edge, self._n_det,
                     *_row_bounds((self._kin.height_px, self._kin.width_px)), rows)
            obs["detections"] = rows
        if self._env.scaled_obs:
            obs = scaled(obs, self._env.joint_limits_rad, (self._kin.height_px, self._kin.width_px))
        return obs

    def _infos(self) -> dict:
        k, n = self.num_envs, self._n
        padded = {}
        for name, a in (("centre_px", self._centre), ("colour_area_px", self._area),
                        ("edge", self._seen_edge), ("motion", np.zeros((k, n)))):
            out = np.zeros((k, MAX_DETECTIONS, *a.shape[2:]))
            mask = np.arange(n)[None, :] < self._n_det[:, None]
            out[:, :n] = np.where(mask.reshape(k, n, *([1] * (a.ndim - 2))), a, 0)
            padded[name] = out
        fired = self._end == END_FIRED
        info = {"detections": padded, "n_detections": self._n_det.copy(), "fired": fired,
                "seen": np.where(fired, self._seen, -1), "attended": self._attended.copy(),
                "target": self._target.copy(), "limit_hit": self._limit_hit.copy(),
                "intrinsic_reward": fired.astype(float),
                "external_reward": (fired & (self._attended == self._target)).astype(float),
                "caregiver_error_rad": self._caregiver_errors(fired)}
        return _with_masks(info, k)

    def _caregiver_errors(self, fired: np.ndarray) -> np.ndarray:
        """Per sub-environment, her error at the attended object (-1 where nothing fired)."""
        error = np.full(self.num_envs, -1.0)
        for i in np.flatnonzero(fired):  # only episodes that end: few per step
            error[i] = separation_rad(self._pos[i, self._attended[i]],
                                      self._pos[i, self._target[i]])
        return error

    def close_extras(self, **kwargs) -> None:
        """Nothing to free: no renderer."""

    def __getstate__(self) -> dict:
        """All of it but numba's list of the generators, which does not pickle.

        The generators themselves pickle (their states are the list's: see ``_start``), so a
        copy continues every episode as the original would; its list is made anew at its
        first start.
        """
        return {**self.__dict__, "_rng_list": None}

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)


def _masked(info: dict, mask: np.ndarray) -> dict:
    """``info`` for the sub-environments in ``mask`` only: zeros elsewhere, masks set to it."""
    def part(key: str, value: np.ndarray) -> np.ndarray:
        if key.startswith("_"):
            return mask.copy()
        return np.where(mask.reshape(-1, *[1] * (value.ndim - 1)), value, np.zeros_like(value))

    return {key: _masked(value, mask) if isinstance(value, dict) else part(key, value)
            for key, value in info.items()}


def _with_masks(info: dict, k: int) -> dict:
    """``info`` with Gymnasium's ``_key`` masks (every sub-environment has every key)."""
    out = {}
    for key, value in info.items():
        out[key] = _with_masks(value, k) if isinstance(value, dict) else value
        out[f"_{key}"] = np.ones(k, bool)
    return out
