"""Stable-Baselines3 on the native vector environment: :class:`NativeVecEnv`.

Needs the ``rl`` extra (``pip install "jointattention[rl]"``). SB3 takes its own ``VecEnv``
class, not Gymnasium's vector environments; this one steps all sub-environments of
:class:`~jointattention.env.vector.JointAttentionVectorEnv` in one compiled call, where SB3's
``DummyVecEnv`` steps one Python environment after the other::

    from stable_baselines3 import PPO
    from jointattention.env.sb3 import NativeVecEnv

    env = NativeVecEnv("JointAttentionFace-N1-v2", num_envs=64, seed=0)
    PPO("MultiInputPolicy", env).learn(250_000)

It gives what SB3's ``Monitor`` and ``DummyVecEnv`` give: per sub-environment an ``info``
with ``"terminal_observation"`` and ``"TimeLimit.truncated"`` when an episode ends, and
``"episode"`` (``r``, ``l``, ``t``: return, length, seconds since the start), so that SB3's
logs and callbacks see the episodes.
"""

from __future__ import annotations

import time

import gymnasium as gym
import numpy as np
from gymnasium.vector import AutoresetMode

try:
    from stable_baselines3.common.callbacks import BaseCallback
    from stable_baselines3.common.vec_env import VecEnv
except ImportError:  # pragma: no cover - depends on the installed extras
    raise ImportError('jointattention.env.sb3 needs Stable-Baselines3; expected it installed: '
                      'pip install "jointattention[rl]"') from None

from .._checks import check_int, short_repr
from ..errors import ConfigError
from . import ENV_IDS
from ._args import check_action, first_seed
from .vector import MAX_ENVS

__all__ = ["EpisodeLog", "NativeVecEnv", "success_rate"]

# make_vec's arguments that NativeVecEnv gives itself, and what it gives
_ITS_OWN = {"autoreset_mode": "'SameStep', what SB3 expects",
            "vectorization_mode": "'vector_entry_point'", "vector_kwargs": "none",
            "wrappers": "none"}


def _same_step(mode) -> bool:
    """Whether ``mode`` is Gymnasium's same-step autoreset (NativeVecEnv's own; harmless)."""
    return mode is AutoresetMode.SAME_STEP or (isinstance(mode, str) and mode == "SameStep")


class NativeVecEnv(VecEnv):
    """A Stable-Baselines3 ``VecEnv`` of ``num_envs`` native sub-environments of ``env_id``.

    Args:
        env_id: a registered id without images (``JointAttentionFace...`` or
            ``JointAttentionDetections...``; the v2 ids for SB3's default networks).
        num_envs: how many sub-environments.
        seed: the first reset's seed (sub-environment ``i`` gets ``seed + i``), or None.
        **kwargs: arguments of the environment (``n_objects``, ``reward``, ``caregivers``
            for a held-out split, ...); not
            ``make_vec``'s ``autoreset_mode`` or ``vectorization_mode``, which it sets.

    Its arguments, seeds (here or by ``seed()``) and actions are checked as the environment's
    are: a wrong one is one :class:`~jointattention.errors.ConfigError` or
    :class:`~jointattention.errors.ArgumentError` naming it, before any work.
    """

    def __init__(self, env_id: str, num_envs: int = 64, seed: int | None = None, **kwargs):
        if (not isinstance(env_id, str) or env_id not in ENV_IDS
                or gym.spec(env_id).vector_entry_point is None):
            raise ConfigError(f"env_id={short_repr(env_id)}: expected a registered id without "
                              "images (JointAttentionFace... or JointAttentionDetections...)")
        check_int("num_envs", num_envs, 1, MAX_ENVS)
        seed = first_seed(seed, num_envs)
        for name in _ITS_OWN:
            if name in kwargs and not (name == "autoreset_mode" and _same_step(kwargs[name])):
                raise ConfigError(f"{name}={short_repr(kwargs[name])}: NativeVecEnv sets it "
                                  f"itself ({_ITS_OWN[name]}); expected it not given")
        kwargs.pop("autoreset_mode", None)
        self.venv = gym.make_vec(env_id, num_envs=num_envs,
                                 vectorization_mode="vector_entry_point",
                                 autoreset_mode="SameStep", **kwargs)
        super().__init__(num_envs, self.venv.single_observation_space,
                         self.venv.single_action_space)
        self._seed = seed
        self._actions: np.ndarray | None = None
        self._returns, self._lengths = np.zeros(num_envs), np.zeros(num_envs, np.int64)
        self._t0 = time.perf_counter()

    def reset(self):
        """Start every sub-environment, with the seed of ``seed()`` or the constructor, once."""
        seed = self._seeds[0] if self._seeds[0] is not None else self._seed
        obs, _ = self.venv.reset(seed=seed)
        self._reset_seeds()
        self._seed = None
        self._returns[:], self._lengths[:] = 0, 0
        return obs

    def seed(self, seed: int | None = None) -> list[int | None]:
        """Seed the next reset: sub-environment ``i`` gets ``seed + i`` (None: a random seed)."""
        return super().seed(first_seed(seed, self.num_envs))

    def step_async(self, actions: np.ndarray) -> None:
        """Keep the actions for :meth:`step_wait` (checked here: one error line if malformed)."""
        if isinstance(self.action_space, gym.spaces.Discrete):  # the -Discrete ids
            from .discrete import check_moves

            self._actions = check_moves(actions, self.num_envs)
        else:
            self._actions = check_action(actions, (self.num_envs, 2), "actions")

    def step_wait(self):
        """Step all sub-environments: (observations, rewards, dones, infos)."""
        obs, rewards, terminated, truncated, info = self.venv.step(self._actions)
        dones = terminated | truncated
        self._returns += rewards
        self._lengths += 1
        infos: list[dict] = [{} for _ in range(self.num_envs)]
        for i in np.flatnonzero(dones):
            infos[i] = {"terminal_observation": info["final_obs"][i],
                        "TimeLimit.truncated": bool(truncated[i] and not terminated[i]),
                        "episode": {"r": float(self._returns[i]), "l": int(self._lengths[i]),
                                    "t": round(time.perf_counter() - self._t0, 6)}}
        self._returns[dones], self._lengths[dones] = 0, 0
        return obs, rewards.astype(np.float32), dones, infos

    def close(self) -> None:
        """Close the vector environment."""
        self.venv.close()

    def render(self, mode: str | None = None):
        """The first sub-environment's face window as RGB (``render_mode="rgb_array"``)."""
        return self.venv.render()

    def get_attr(self, attr_name: str, indices=None) -> list:
        """The attribute of the vector environment, once per sub-environment asked for."""
        return [getattr(self.venv, attr_name, None)] * len(self._get_indices(indices))

    def set_attr(self, attr_name: str, value, indices=None) -> None:
        """Set the attribute on the vector environment (its sub-environments share it)."""
        setattr(self.venv, attr_name, value)

    def env_method(self, method_name: str, *method_args, indices=None, **method_kwargs) -> list:
        """Call a method of the vector environment, once per sub-environment asked for."""
        result = getattr(self.venv, method_name)(*method_args, **method_kwargs)
        return [result] * len(self._get_indices(indices))

    def env_is_wrapped(self, wrapper_class, indices=None) -> list[bool]:
        """No sub-environment is wrapped (it gives ``Monitor``'s ``"episode"`` itself)."""
        return [False] * len(self._get_indices(indices))


class EpisodeLog(BaseCallback):
    """A training callback that keeps every finished episode: ``ends`` and ``wins``.

    ``ends``: the environment steps (``num_timesteps``) when each episode ended; ``wins``:
    whether it paid a reward (success, for the external reward). Needs the ``"episode"`` info
    of SB3's ``Monitor`` (``make_vec_env``) or :class:`NativeVecEnv`.
    """

    def __init__(self):
        super().__init__()
        self.ends: list[int] = []
        self.wins: list[bool] = []

    def _on_step(self) -> bool:
        for info in self.locals["infos"]:
            if "episode" in info:
                self.ends.append(self.num_timesteps)
                self.wins.append(info["episode"]["r"] > 0)
        return True


def success_rate(model, env: gym.Env, episodes: int, seed: int | None = None,
                 deterministic: bool = False) -> float:
    """The share of ``episodes`` episodes of ``env`` in which ``model``'s policy is rewarded.

    ``env`` is a single Gymnasium environment (e.g. ``gym.make(id, caregivers="unseen")``, a
    held-out split); the first reset takes ``seed``. ``model`` None: uniform random actions (the
    action space seeded with ``seed``), the floor.

    ``deterministic`` is passed to ``model.predict``. The default, False, draws the actions as
    learning did (PPO's and A2C's Gaussian, SAC's squashed Gaussian, DQN's epsilon-greedy at
    its final epsilon): the policy that the algorithm optimised and whose success its learning
    curve shows. True takes the Gaussian's mean (or DQN's greedy move), another policy, which
    no training step ran: on the continuous ids PPO's mean stops short of the object in many
    more episodes than its samples fail; on the discrete ids, whose moves do not shrink, its
    most likely move stops far less often (``docs/results/rl/mean_action.md``, written by ``python
    scripts/mean_action.py``). Pass True for a policy meant to be run greedily, such as
    DQN's.
    """
    wins, (obs, _) = 0, env.reset(seed=seed)
    env.action_space.seed(seed)
    for _ in range(episodes):
        done = False
        while not done:
            action = (env.action_space.sample() if model is None else
                      model.predict(obs, deterministic=deterministic)[0])
            obs, reward, terminated, truncated, _ = env.step(action)
            done = terminated or truncated
        wins += reward > 0
        obs, _ = env.reset()
    return wins / episodes

