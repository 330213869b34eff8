"""Stable-Baselines3 on the environments: the default recipe learns, the native adapter agrees.

These need the rl extra (PyTorch); ``make test-rl`` runs them, ``make test`` skips them.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

pytestmark = pytest.mark.rl
sb3 = pytest.importorskip("stable_baselines3", reason="needs the rl extra: make test-rl")

import jointattention.env  # noqa: E402, F401  (registers the environments)
from jointattention.env.sb3 import NativeVecEnv, success_rate  # noqa: E402
from jointattention.errors import ArgumentError  # noqa: E402


def _equal(a, b) -> bool:
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_equal(a[k], b[k]) for k in a)
    return np.array_equal(a, b)


@pytest.mark.parametrize("env_id", ["JointAttentionFace-N5-v2", "JointAttentionDetections-N3-v2"])
def test_the_native_adapter_steps_as_sb3s_dummy_vec_env(env_id):
    """NativeVecEnv gives DummyVecEnv's observations, rewards, dones and terminal observations."""
    from stable_baselines3.common.env_util import make_vec_env

    native = NativeVecEnv(env_id, num_envs=4, seed=7)
    dummy = make_vec_env(env_id, 4, seed=7)
    assert _equal(native.reset(), dummy.reset())
    rng = np.random.default_rng(0)
    episodes = 0
    for _ in range(150):
        actions = rng.uniform(-1, 1, (4, 2)).astype(np.float32)
        (o1, r1, d1, i1), (o2, r2, d2, i2) = native.step(actions), dummy.step(actions)
        assert _equal(o1, o2) and np.array_equal(r1, r2) and np.array_equal(d1, d2)
        for a, b in zip(i1, i2, strict=True):
            assert ("terminal_observation" in a) == ("terminal_observation" in b)
            if "terminal_observation" in a:
                episodes += 1
                assert _equal(a["terminal_observation"], b["terminal_observation"])
                assert a["TimeLimit.truncated"] == b["TimeLimit.truncated"]
                assert a["episode"]["r"] == b["episode"]["r"]
                assert a["episode"]["l"] == b["episode"]["l"]
    assert episodes > 20


def test_the_native_adapter_checks_its_arguments_at_the_door():
    """Bad seeds, make_vec's own arguments and boolean actions are one named error line."""
    from gymnasium.vector import AutoresetMode

    from jointattention.errors import ArgumentError, ConfigError

    env_id = "JointAttentionFace-N1-v2"
    for seed in (-1, 0.5, 2**70, True, "x"):
        with pytest.raises(ArgumentError, match=r"seed=.*expected an integer in \[0, "):
            NativeVecEnv(env_id, num_envs=2, seed=seed)
    for name, value in (("autoreset_mode", "NextStep"), ("vectorization_mode", "sync"),
                        ("wrappers", [])):
        with pytest.raises(ConfigError, match=f"{name}=.*expected it not given"):
            NativeVecEnv(env_id, num_envs=2, **{name: value})
    with pytest.raises(ConfigError, match="num_envs"):
        NativeVecEnv(env_id, num_envs="2")
    env = NativeVecEnv(env_id, num_envs=2, seed=0, autoreset_mode=AutoresetMode.SAME_STEP)
    with pytest.raises(ArgumentError, match="seed=-1"):
        env.seed(-1)
    env.reset()
    with pytest.raises(ArgumentError, match="dtype bool"):
        env.step(np.ones((2, 2), bool))
    env.step(np.zeros((2, 2), np.float32))  # still usable after a refusal


def test_ppo_trains_through_the_native_adapter():
    """PPO learns a few rollouts on 64 native environments; SB3's evaluation runs on them."""
    from stable_baselines3 import PPO
    from stable_baselines3.common.evaluation import evaluate_policy

    env = NativeVecEnv("JointAttentionFace-N1-v2", num_envs=64, seed=0)
    model = PPO("MultiInputPolicy", env, n_steps=32, seed=0, device="cpu").learn(4096)
    assert model.num_timesteps >= 4096 and len(model.ep_info_buffer) > 50
    mean, _ = evaluate_policy(model, env, n_eval_episodes=64, warn=False)
    assert 0 <= mean <= 1


def test_ppo_with_sb3_defaults_learns_the_one_object_face_env():
    """The first recipe: PPO("MultiInputPolicy", make_vec_env(v2 id, 8)), defaults, 2.5e5 steps.

    Its frozen policy (actions drawn from it, as in learning) finds the caregiver's target in
    at least 80% of 300 new episodes.
    """
    from stable_baselines3 import PPO
    from stable_baselines3.common.env_util import make_vec_env

    model = PPO("MultiInputPolicy", make_vec_env("JointAttentionFace-N1-v2", 8, seed=0), seed=0,
                device="cpu").learn(250_000)
    env = gym.make("JointAttentionFace-N1-v2")
    assert success_rate(model, env, 300, seed=10_000, deterministic=False) >= 0.8


@pytest.mark.parametrize("split", ["new-poses", "unseen"])
def test_the_native_adapter_takes_the_held_out_split(split):
    """NativeVecEnv(..., caregivers=split) steps as DummyVecEnv on the split's held-out faces."""
    from stable_baselines3.common.env_util import make_vec_env

    from jointattention.config import Config
    from jointattention.experiment.held_out import held_out_sets

    env_id = "JointAttentionFace-N3-v2"
    native = NativeVecEnv(env_id, num_envs=4, seed=5, caregivers=split)
    dummy = make_vec_env(env_id, 4, seed=5, env_kwargs={"caregivers": split})
    obs = native.reset()
    assert _equal(obs, dummy.reset())
    kind = {"new-poses": "new poses", "unseen": "unseen caregivers"}[split]
    faces = set(map(bytes, held_out_sets(Config())[kind].face))
    rng = np.random.default_rng(1)
    for _ in range(60):
        shown = np.round((obs["face"] + 0.5) * 255).astype(np.uint8)
        assert set(map(bytes, shown)) <= faces
        actions = rng.uniform(-1, 1, (4, 2)).astype(np.float32)
        (obs, r1, d1, _), (o2, r2, d2, _) = native.step(actions), dummy.step(actions)
        assert _equal(obs, o2) and np.array_equal(r1, r2) and np.array_equal(d1, d2)


def test_dqn_trains_on_the_discrete_id_alone_and_through_the_native_adapter():
    """DQN (SB3's defaults) learns a few hundred steps of N1-Discrete; its frozen policy runs."""
    from stable_baselines3 import DQN
    from stable_baselines3.common.env_util import make_vec_env

    env_id = "JointAttentionFace-N1-Discrete-v2"
    for env in (make_vec_env(env_id, 1, seed=0), NativeVecEnv(env_id, num_envs=4, seed=0)):
        model = DQN("MultiInputPolicy", env, seed=0, device="cpu", learning_starts=100)
        model.learn(400)
        assert model.num_timesteps >= 400 and model._n_updates > 0
        assert len(model.ep_info_buffer) > 0  # episodes ended and were logged
    one = gym.make(env_id)
    for deterministic in (True, False):
        assert 0 <= success_rate(model, one, 5, seed=1, deterministic=deterministic) <= 1
    native = NativeVecEnv(env_id, num_envs=2, seed=0)
    native.reset()
    with pytest.raises(ArgumentError, match=r"actions: .*dtype float"):
        native.step(np.zeros(2))
    native.step(np.array([1, 5]))  # still usable after a refusal
