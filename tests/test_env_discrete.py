"""The ``-Discrete`` ids: nine head moves, the v2 twin's rules, seeds, vector forms, bad input."""

from __future__ import annotations

import copy
import pickle

import gymnasium as gym
import numpy as np
import pytest

import jointattention.env
from jointattention.config import Config
from jointattention.env import ENV_IDS
from jointattention.env.discrete import (
    MOVES_DEG,
    N_MOVES,
    DiscreteJointAttentionEnv,
    DiscreteJointAttentionVectorEnv,
)
from jointattention.errors import ArgumentError, ConfigError
from jointattention.experiment.held_out import held_out_sets

DISCRETE = [i for i in ENV_IDS if "-Discrete-" in i]


def _equal(a, b, atol: float = 0) -> bool:
    """Equal, nested; with ``atol``, floats within it (integers, booleans still exactly)."""
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_equal(a[k], b[k], atol) for k in a)
    if isinstance(a, tuple | list) or (isinstance(a, np.ndarray) and a.dtype == object):
        return len(a) == len(b) and all(_equal(x, y, atol) for x, y in zip(a, b, strict=True))
    if a is None or b is None:
        return a is b
    if atol and np.asarray(a).dtype.kind == "f":
        return np.shape(a) == np.shape(b) and np.allclose(a, b, rtol=0, atol=atol)
    return np.array_equal(a, b)


def _episodes(env, seed: int, moves) -> list:
    """Every reset and step of ``env`` under ``moves``, restarting episodes that end."""
    out = [env.reset(seed=seed)]
    for move in moves:
        out.append(env.step(move))
        if out[-1][2] or out[-1][3]:
            out.append(env.reset())
    return out


def test_the_discrete_ids_sit_beside_their_v2_twins():
    """Each face/detections v2 id has a -Discrete-v2 twin: Discrete(9), same threshold, 40 steps."""
    assert len(DISCRETE) == 10
    for env_id in DISCRETE:
        twin = env_id.replace("-Discrete", "")
        spec, twin_spec = gym.spec(env_id), gym.spec(twin)
        assert spec.reward_threshold == twin_spec.reward_threshold is not None
        assert spec.max_episode_steps == 40 and spec.vector_entry_point is not None
        env = gym.make(env_id)
        assert env.action_space == gym.spaces.Discrete(N_MOVES) == gym.spaces.Discrete(9)
        assert env.observation_space == gym.make(twin).observation_space
    assert "JointAttentionFace-N1-Discrete-v2" in DISCRETE


def test_each_move_turns_the_head_by_its_angle():
    """Move k turns the head by MOVES_DEG[k]: stay, 4 and 12 degrees right, left, up, down."""
    assert MOVES_DEG.tolist() == [[0, 0], [4, 0], [-4, 0], [0, 4], [0, -4],
                                  [12, 0], [-12, 0], [0, 12], [0, -12]]
    env = gym.make("JointAttentionFace-N1-Discrete-v2").unwrapped
    for move in range(N_MOVES):
        env.reset(seed=move)
        before = env._trial.theta_rad.copy()
        info = env.step(move)[4]
        if not info["limit_hit"]:
            assert np.allclose(np.rad2deg(env._trial.theta_rad - before), MOVES_DEG[move])
        assert env._trial.n_steps == 1


@pytest.mark.parametrize("split", ["training", "new-poses", "unseen"])
def test_a_move_is_the_continuous_twins_step_of_that_angle(split):
    """The same seed and the move as a normalised action give the v2 twin's episodes exactly."""
    moves = np.random.default_rng(1).integers(0, N_MOVES, 300)
    discrete = gym.make("JointAttentionDetections-N3-Discrete-v2", caregivers=split)
    box = gym.make("JointAttentionDetections-N3-v2", caregivers=split)
    scale = box.unwrapped.max_step_rad
    actions = [np.deg2rad(MOVES_DEG[m]) / scale for m in moves]
    a, b = _episodes(discrete, 4, moves), _episodes(box, 4, actions)
    # the same ends and rewards; angles within the rounding of deg -> [-1, 1] -> rad
    assert _equal(a, b, atol=1e-6)
    assert not _equal(a, _episodes(box, 5, actions), atol=1e-6)
    assert sum(step[1] for step in a if len(step) == 5) > 0  # some episodes succeed


def test_the_same_seed_gives_the_same_episodes_and_another_seed_others():
    """Seeded resets repeat episodes step for step; other seeds show other faces."""
    moves = np.random.default_rng(2).integers(0, N_MOVES, 200)
    runs = [_episodes(gym.make("JointAttentionFace-N5-Discrete-v2"), seed, moves)
            for seed in (7, 7, 8)]
    assert _equal(runs[0], runs[1])
    assert not np.array_equal(runs[0][0][0]["face"], runs[2][0][0]["face"])


@pytest.mark.parametrize("split", ["training", "unseen"])
@pytest.mark.parametrize("autoreset_mode", ["NextStep", "SameStep"])
def test_the_native_vector_env_equals_sync_and_async_vector_envs(split, autoreset_mode):
    """make_vec in its three modes gives the same steps; 'unseen' shows the held-out faces."""
    moves = np.random.default_rng(3).integers(0, N_MOVES, (200, 3))
    runs = []
    for mode in ("vector_entry_point", "sync", "async"):
        kwargs = ({"autoreset_mode": autoreset_mode} if mode == "vector_entry_point" else
                  {"vector_kwargs": {"autoreset_mode": autoreset_mode}})
        envs = gym.make_vec("JointAttentionFace-N1-Discrete-v2", num_envs=3,
                            vectorization_mode=mode, caregivers=split, **kwargs)
        assert envs.single_action_space == gym.spaces.Discrete(N_MOVES)
        runs.append([envs.reset(seed=11)] + [envs.step(m) for m in moves])
        envs.close()
    assert isinstance(gym.make_vec("JointAttentionFace-Discrete-v2", num_envs=2,
                                   vectorization_mode="vector_entry_point"),
                      DiscreteJointAttentionVectorEnv)
    assert _equal(runs[0], runs[1]) and _equal(runs[0], runs[2])
    assert sum(int(step[2].sum()) for step in runs[0][1:]) > 0  # some end before the limit
    assert sum(int(step[3].sum()) for step in runs[0][1:]) > 0
    if split == "unseen":
        faces = set(map(bytes, held_out_sets(Config())["unseen caregivers"].face))
        shown = np.round((runs[0][0][0]["face"] + 0.5) * 255).astype(np.uint8)
        assert set(map(bytes, shown)) <= faces


def test_a_copy_continues_the_discrete_episode():
    """Pickled or deep-copied mid-episode, the single and the vector env's copies step alike."""
    moves = np.random.default_rng(4).integers(0, N_MOVES, (120, 4))
    one = gym.make("JointAttentionFace-N1-Discrete-v2").unwrapped
    envs = gym.make_vec("JointAttentionFace-N1-Discrete-v2", num_envs=4,
                        vectorization_mode="vector_entry_point")
    one.reset(seed=5)
    envs.reset(seed=5)
    one.step(1)
    envs.step(moves[0])
    for env, steps in ((one, moves[1:, 0]), (envs, moves[1:])):
        copies = [pickle.loads(pickle.dumps(env)), copy.deepcopy(env)]
        original = []
        for m in steps:
            original.append(env.step(m))
            if env is one and (original[-1][2] or original[-1][3]):
                break
        for other in copies:
            assert _equal([other.step(m) for m in steps[:len(original)]], original)


def test_bad_moves_and_arguments_are_one_error_line():
    """Floats, booleans, out-of-range or misshapen moves, normalize_actions: one named error."""
    env = gym.make("JointAttentionFace-N1-Discrete-v2")
    env.reset(seed=0)
    for bad in (1.0, np.float32(2), True, np.bool_(False), 9, -1, "1", None, [1],
                np.array([1]), np.array(2.0)):
        with pytest.raises(ArgumentError, match=r"action=.*expected an integer move in \[0, 8\]"
                           ) as err:
            env.step(bad)
        assert "\n" not in str(err.value)
    for good in (0, np.int64(8), np.array(3), np.uint8(5)):  # still usable after refusals
        *_, terminated, truncated, _ = env.step(good)
        if terminated or truncated:
            env.reset()
    envs = gym.make_vec("JointAttentionFace-N1-Discrete-v2", num_envs=3,
                        vectorization_mode="vector_entry_point")
    envs.reset(seed=0)
    for bad, named in ((np.ones(3), "dtype float64"), ([1, 2], r"shape \(2,\)"),
                       (np.ones(3, bool), "dtype bool"), ([0, 1, 9], "holds 9"),
                       ([[0, 1, 2]], r"shape \(1, 3\)"), ("x", "actions")):
        with pytest.raises(ArgumentError, match=named) as err:
            envs.step(bad)
        assert str(err.value).startswith("actions: ") and "\n" not in str(err.value)
    envs.step([0, 1, 2])
    for make in (lambda: gym.make("JointAttentionFace-Discrete-v2", normalize_actions=True),
                 lambda: DiscreteJointAttentionEnv(obs_mode="face", normalize_actions=1),
                 lambda: gym.make_vec("JointAttentionFace-Discrete-v2", num_envs=2,
                                      vectorization_mode="vector_entry_point",
                                      normalize_actions=True)):
        with pytest.raises(ConfigError, match=r"normalize_actions=.*expected it not given"):
            make()
    assert jointattention.env.REWARD_THRESHOLDS["JointAttentionFace-N1-Discrete-v2"] == 0.9
