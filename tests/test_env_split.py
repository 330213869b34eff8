"""The held-out split in one argument (``caregivers=``) and every spec's ``reward_threshold``."""

from __future__ import annotations

import json
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import jointattention.env
from jointattention.config import Config
from jointattention.datasets import default_datasets
from jointattention.env import ENV_IDS, REWARD_THRESHOLDS, JointAttentionEnv
from jointattention.errors import ArgumentError
from jointattention.experiment.cells import measure_ceiling
from jointattention.experiment.held_out import held_out_sets

KIND = {"new-poses": "new poses", "unseen": "unseen caregivers"}


def _faces_served(env, n_episodes: int) -> list[int]:
    """Which of the env's data sets each of ``n_episodes`` seeded episodes shows."""
    ds = env.unwrapped._datasets
    served = []
    for seed in range(n_episodes):
        obs, _ = env.reset(seed=seed)
        face = obs["face"] if obs["face"].dtype == np.uint8 else None
        if face is None:  # v2: grey / 255 - 0.5
            face = np.round((obs["face"] + 0.5) * 255).astype(np.uint8)
        served.append(int(np.flatnonzero((ds.face == face).all(axis=(1, 2)))[0]))
    return served


@pytest.mark.parametrize("split", ["new-poses", "unseen"])
@pytest.mark.parametrize("env_id", ["JointAttentionFace-v2", "JointAttentionDetections-N3-v2"])
def test_a_held_out_env_serves_the_held_out_sets_faces(env_id, split):
    """caregivers='new-poses'/'unseen': each episode is one of that kind's held-out sets."""
    sets = held_out_sets(Config())[KIND[split]]
    env = gym.make(env_id, caregivers=split)
    assert env.unwrapped._datasets is sets and len(sets) != len(default_datasets())
    served = _faces_served(env, 40)
    assert len(set(served)) >= 30  # many of the sets, not one
    training = default_datasets().face.reshape(len(default_datasets()), -1)
    for k in served[:5]:  # a held-out face is none of the training faces
        assert not (training == sets.face[k].ravel()).all(axis=1).any()


def test_the_training_split_is_the_default_and_changes_nothing():
    """caregivers='training' gives the episodes of no argument, step for step."""
    actions = np.random.default_rng(2).uniform(-1, 1, (120, 2)).astype(np.float32)
    runs = []
    for kwargs in ({}, {"caregivers": "training"}):
        env = gym.make("JointAttentionDetections-N5-v2", **kwargs)
        assert np.array_equal(env.unwrapped._datasets.face, default_datasets().face)
        out = [env.reset(seed=9)]
        for action in actions:
            out.append(env.step(action))
            if out[-1][2] or out[-1][3]:
                out.append(env.reset())
        runs.append(out)
    for a, b in zip(*runs, strict=True):
        assert repr(a) == repr(b)


@pytest.mark.parametrize("split", ["training", "new-poses", "unseen"])
def test_the_native_vector_env_agrees_with_the_single_env_per_split(split):
    """make_vec(..., caregivers=split): the native and the sync vector env give the same steps."""
    runs = []
    for mode in ("vector_entry_point", "sync"):
        envs = gym.make_vec("JointAttentionFace-N3-v2", num_envs=3, vectorization_mode=mode,
                            caregivers=split)
        obs, _ = envs.reset(seed=11)
        rng = np.random.default_rng(0)
        steps = [obs]
        for _ in range(120):
            steps.append(envs.step(rng.uniform(-1, 1, (3, 2)).astype(np.float32))[:4])
        runs.append(steps)
        envs.close()
    (native, sync), faces = runs, set()
    for a, b in zip(native, sync, strict=True):
        a, b = (x if isinstance(x, tuple) else (x,) for x in (a, b))
        for x, y in zip(a, b, strict=True):
            if isinstance(x, dict):
                assert all(np.array_equal(x[k], y[k]) for k in x)
                faces.update(map(bytes, np.round((x["face"] + 0.5) * 255).astype(np.uint8)))
            else:
                assert np.array_equal(x, y)
    ds = (default_datasets() if split == "training" else held_out_sets(Config())[KIND[split]])
    shown = set(map(bytes, ds.face))
    assert faces <= shown and len(faces) > 10  # the split's faces, many of them


@pytest.mark.usefixtures("needs_gl")
@pytest.mark.parametrize("split", ["new-poses", "unseen"])
def test_a_held_out_image_env_shows_the_splits_people(split):
    """Image mode: every scene is posed by a caregiver of the split's held-out sets."""
    from jointattention.world.recording import caregivers_of

    config = Config()
    people = caregivers_of(held_out_sets(config)[KIND[split]], config.world)
    env = gym.make("JointAttention-N3-v3", caregivers=split, width=64, height=48)
    shown = []
    env.reset(seed=0)
    for _ in range(12):
        shown.append(env.unwrapped._scene_state.caregiver)
        env.reset()
    env.close()
    assert all(person in people for person in shown)
    if split == "new-poses":  # the training sets' one caregiver
        assert people == caregivers_of(default_datasets(), config.world)
    else:
        assert len(people) == 16 and len({id(p) for p in shown}) > 3


def test_a_bad_split_is_one_argument_error_naming_the_choices():
    """caregivers= anything but the three names: one ArgumentError line naming them."""
    makers = (lambda v: JointAttentionEnv(obs_mode="face", caregivers=v),
              lambda v: gym.make("JointAttentionFace-v2", caregivers=v),
              lambda v: gym.make_vec("JointAttentionFace-v2", num_envs=2,
                                     vectorization_mode="vector_entry_point", caregivers=v))
    for make in makers:
        for bad in ("held-out", None, 1, "Unseen"):
            with pytest.raises(ArgumentError) as err:
                make(bad)
            line = str(err.value)
            assert line.startswith("caregivers=") and "\n" not in line
            assert "'training', 'new-poses', 'unseen'" in line


def test_reward_threshold_is_set_on_every_v2_and_v3_spec():
    """Every v2/v3 spec's reward_threshold is 0.9 x the oracle's ceiling at its count; v1 none."""
    data = json.loads((Path(jointattention.env.__file__).parent
                       / "reward_thresholds.json").read_text())
    for env_id in ENV_IDS:
        spec = gym.spec(env_id)
        if env_id.endswith("-v1"):
            assert spec.reward_threshold is None
            continue
        kwargs = spec.kwargs
        ceiling = data["ceiling"][kwargs.get("reward", "external")][
            str(kwargs.get("n_objects", 5))]
        assert spec.reward_threshold == REWARD_THRESHOLDS[env_id]
        assert spec.reward_threshold == pytest.approx(0.9 * ceiling, abs=1e-4)
        assert 0.5 < spec.reward_threshold <= 0.9
    assert gym.spec("JointAttentionFace-N10-v2").reward_threshold < gym.spec(
        "JointAttentionFace-N1-v2").reward_threshold  # distractors lower the ceiling


def test_the_shipped_ceilings_agree_with_a_fresh_measurement():
    """reward_thresholds.json's ceilings are measure_ceiling's, again with 4,000 trials."""
    data = json.loads((Path(jointattention.env.__file__).parent
                       / "reward_thresholds.json").read_text())
    config = Config()
    for reward, ceilings in data["ceiling"].items():
        for n, shipped in ceilings.items():
            fresh = measure_ceiling(config, int(n), 4000, reward)
            # 4 standard errors of a share of 4,000 trials: at most 0.032
            assert abs(fresh - shipped) <= 4 * np.sqrt(0.25 / 4000) + 1e-9, (reward, n)
