"""The environment's observation modes, registered variants, vector forms and copies."""

from __future__ import annotations

import copy
import pickle
import subprocess
import sys
import textwrap
import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from hypothesis import given, settings
from hypothesis import strategies as st

from jointattention.env import (
    ENV_IDS,
    MAX_DETECTIONS,
    EnvTrial,
    FaceWindowObservation,
    JointAttentionEnv,
)
from jointattention.errors import ArgumentError


@pytest.mark.usefixtures("needs_gl")
def test_check_env_passes_on_every_registered_id_and_the_readme_pattern():
    """Gymnasium's check_env passes on each registered id, wrapped as made and unwrapped."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # check_env warns about what it checks on purpose
        for env_id in ENV_IDS:
            env = gym.make(env_id)
            check_env(env)
            check_env(env.unwrapped)
            assert env.spec.max_episode_steps == 40
            env.close()
        readme = FaceWindowObservation(  # the manual's own code (docs/gymnasium.md)
            gym.make("JointAttention-v3", n_objects=3, render_quality="full"))
        check_env(readme)
        readme.close()


def test_fast_modes_give_the_data_sets_faces_and_random_initial_states():
    """Face mode: each episode is a data set's face and head angle; seeds give other ones."""
    env = JointAttentionEnv(obs_mode="face", n_objects=3)
    ds = env.unwrapped._datasets
    starts = set()
    for seed in range(8):
        obs, info = env.reset(seed=seed)
        k = int(np.flatnonzero((ds.face == obs["face"]).all(axis=(1, 2)))[0])
        assert np.allclose(obs["head_angle"], ds.theta_face_rad[k], atol=1e-6)
        assert info["n_detections"] <= MAX_DETECTIONS and not info["fired"]
        starts.add(k)
    assert len(starts) >= 6
    again, _ = env.reset(seed=3)
    assert np.array_equal(again["face"], env.reset(seed=3)[0]["face"])


def test_detections_observation_rows_match_the_info():
    """Detections mode: one present row per detection, zero rows after, equal to info's."""
    env = JointAttentionEnv(obs_mode="detections", n_objects=10)
    obs, info = env.reset(seed=1)
    env.action_space.seed(1)
    for _ in range(30):
        n = info["n_detections"]
        rows = obs["detections"]
        assert rows.shape == (MAX_DETECTIONS, 6) and obs in env.observation_space
        assert rows[:n, 0].all() and not rows[n:].any()
        assert np.allclose(rows[:n, 1:3], info["detections"]["centre_px"][:n], atol=1e-3)
        obs, _, terminated, truncated, info = env.step(env.action_space.sample())
        if terminated or truncated:
            obs, info = env.reset()


def test_normalized_actions_move_by_the_largest_step():
    """With normalize_actions, action (1, -1) turns the head by (+max_step_rad, -max_step_rad)."""
    env = JointAttentionEnv(obs_mode="face", n_objects=1, normalize_actions=True)
    obs, _ = env.reset(seed=0)
    assert np.array_equal(env.action_space.high, [1, 1])
    after, *_ = env.step(np.array([1.0, -1.0], np.float32))
    moved = after["head_angle"].astype(float) - obs["head_angle"]
    assert np.allclose(moved, env.max_step_rad * np.array([1, -1]), atol=1e-6)


def test_reset_options_are_refused_and_seeds_checked():
    """reset(options=...) with any option, or a seed that is not an integer, is an error."""
    env = JointAttentionEnv(obs_mode="face")
    with pytest.raises(ArgumentError, match="options"):
        env.reset(options={"n_objects": 3})
    with pytest.raises(ArgumentError, match="seed"):
        env.reset(seed=1.5)
    env.reset(options={})  # nothing asked: accepted


@pytest.mark.parametrize("mode", ["face", "detections"])
def test_vector_envs_stack_fixed_shape_infos(mode):
    """make_vec (sync and async) steps the modes without images; info stacks at any step."""
    for vectorization in ("sync", "async"):
        envs = gym.make_vec(f"JointAttention{mode.title()}-N10-v1", num_envs=3,
                            vectorization_mode=vectorization)
        envs.reset(seed=0)
        envs.action_space.seed(0)
        for _ in range(60):
            _, _, _, _, info = envs.step(envs.action_space.sample())
        assert info["detections"]["centre_px"].shape == (3, MAX_DETECTIONS, 2)
        assert info["n_detections"].shape == (3,)
        envs.close()


@pytest.mark.usefixtures("needs_gl")
@pytest.mark.parametrize("mode", ["image", "face"])
def test_the_env_pickles_and_deep_copies_after_reset(mode):
    """Pickle and deepcopy work after reset (a copy is made anew from the arguments)."""
    env = JointAttentionEnv(obs_mode=mode, n_objects=3)
    env.reset(seed=0)
    env.step(env.action_space.sample())
    for other in (pickle.loads(pickle.dumps(env)), copy.deepcopy(env)):
        assert other.observation_space == env.observation_space
        a, _ = other.reset(seed=5)
        b, _ = JointAttentionEnv(obs_mode=mode, n_objects=3).reset(seed=5)
        assert all(np.array_equal(a[k], b[k]) for k in a)
        other.close()
    env.close()


def test_an_agent_runs_the_runners_trial_through_the_face_mode():
    """A trial through the face mode equals the runner's trial of the same data set and scene."""
    from jointattention.experiment.cells import random_scene
    from jointattention.experiment.oracle import OracleAgent
    from jointattention.experiment.trial import SceneTrial, run_trial

    env = gym.make("JointAttentionFace-N5-v1", max_steps=15)
    inner = env.unwrapped
    ds, kin, step = inner._datasets, inner.kinematics, np.deg2rad(4.0)
    for seed in range(6):
        k, scene, _ = random_scene(inner.config, ds, kin, 5, np.random.default_rng(seed))
        aim = ds.theta_face_rad[k] + ds.command_rad[k]
        direct = run_trial(SceneTrial(scene, ds.theta_face_rad[k], kinematics=kin,
                                      max_steps=15, evaluate=inner._evaluate),
                           OracleAgent(aim, step), ds.face[k])
        trial = EnvTrial(env, seed=seed)
        through = run_trial(trial, OracleAgent(aim, step), trial.observation["face"])
        assert (through.n_steps, through.attended, through.target, through.end) == (
            direct.n_steps, direct.attended, direct.target, direct.end)


SCRIPT = """
import sys
import gymnasium as gym
import jointattention.env

def main(context):
    parent = gym.make("JointAttentionFace-N3-v1")
    parent.reset(seed=0)
    print("mujoco" in sys.modules)
    if context is None:
        return
    image = gym.make("JointAttention-N3-v1")
    image.reset(seed=0)
    image.step(image.action_space.sample())  # the parent renders before the workers start
    envs = gym.make_vec("JointAttention-N3-v1", num_envs=2, vectorization_mode="async",
                        vector_kwargs={} if context == "fork" else {"context": context})
    try:
        envs.reset(seed=0)
        for _ in range(5):
            obs, *_ = envs.step(envs.action_space.sample())
        print(obs["image"].shape)
    finally:
        envs.close()

if __name__ == "__main__":
    main(None if sys.argv[1] == "none" else sys.argv[1])
"""


@pytest.mark.usefixtures("needs_gl")
def test_async_images_run_under_spawn_and_fork_fails_at_once(tmp_path):
    """Async image envs work with spawn; under fork after rendering, one error, no hang.

    The modes without images import no MuJoCo at all.
    """
    script = tmp_path / "vec.py"
    script.write_text(textwrap.dedent(SCRIPT))

    def run(context: str) -> subprocess.CompletedProcess:
        return subprocess.run([sys.executable, str(script), context], capture_output=True,
                              text=True, timeout=300)

    assert run("none").stdout.split() == ["False"]
    spawned = run("spawn")
    assert spawned.returncode == 0, spawned.stderr
    assert "(2, 240, 320, 3)" in spawned.stdout
    forked = run("fork")
    assert forked.returncode != 0 and "spawn or forkserver" in forked.stderr


def _rollout(env_id: str, mode: str, n_envs: int, n_steps: int, **kwargs) -> list:
    """Observations, rewards, ends and infos of a vector env under fixed random actions."""
    envs = gym.make_vec(env_id, num_envs=n_envs, vectorization_mode=mode, **kwargs)
    assert envs.metadata["autoreset_mode"] == gym.vector.AutoresetMode(
        kwargs.get("autoreset_mode") or kwargs.get("vector_kwargs", {}).get(
            "autoreset_mode", "NextStep"))
    obs, info = envs.reset(seed=3)
    rng = np.random.default_rng(0)
    out = [(obs, info)]
    for _ in range(n_steps):
        out.append(envs.step(rng.uniform(-1, 1, (n_envs, 2)).astype(np.float32)))
    envs.close()
    return out


def _equal(a, b) -> bool:
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_equal(a[k], b[k]) for k in a)
    if isinstance(a, tuple):
        return all(_equal(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, np.ndarray) and a.dtype == object:  # final_obs: one dict per env
        return len(a) == len(b) and all(_equal(x, y) for x, y in zip(a, b, strict=True))
    if a is None or b is None:
        return a is b
    return np.array_equal(a, b)


@pytest.mark.parametrize("env_id", ["JointAttentionFace-N5-v1", "JointAttentionDetections-N10-v1",
                                    "JointAttentionFace-N3-Intrinsic-v1"])
def test_the_native_vector_env_equals_a_sync_vector_env(env_id):
    """The compiled vector env gives the sync vector env's observations, rewards, ends, infos."""
    native = _rollout(env_id, "vector_entry_point", 4, 250)
    sync = _rollout(env_id, "sync", 4, 250)
    assert sum(float(step[1].sum()) for step in native[1:]) > 0  # some episodes succeed
    for a, b in zip(native, sync, strict=True):
        assert _equal(a, b)


def test_the_native_vector_env_refuses_images_and_bad_actions():
    """Image mode, or actions of the wrong shape or not finite, are one error naming them."""
    from jointattention.env.vector import JointAttentionVectorEnv
    from jointattention.errors import ConfigError

    with pytest.raises(ConfigError, match="obs_mode='image'"):
        JointAttentionVectorEnv(num_envs=2)
    envs = gym.make_vec("JointAttentionFace-v1", num_envs=2,
                        vectorization_mode="vector_entry_point")
    envs.reset(seed=0)
    for bad in (np.zeros((3, 2)), np.full((2, 2), np.nan), "x"):
        with pytest.raises(ArgumentError, match="actions"):
            envs.step(bad)
    # a refused step changed nothing: the next steps are those of an env that never saw it
    twin = gym.make_vec("JointAttentionFace-v1", num_envs=2,
                        vectorization_mode="vector_entry_point")
    twin.reset(seed=0)
    for _ in range(30):
        move = np.full((2, 2), 0.01)
        (a, *_), (b, *_) = envs.step(move), twin.step(move)
        assert all(np.array_equal(a[key], b[key]) for key in a)


def test_the_native_vector_env_checks_seeds_and_refuses_boolean_actions():
    """Seeds of the wrong kind, range or count, and boolean actions, are one named error."""
    envs = gym.make_vec("JointAttentionFace-v2", num_envs=4,
                        vectorization_mode="vector_entry_point")
    for bad, named in (([1, 2], "2 seeds for 4"), (-1, r"seed=-1: .*\[0, "), (0.5, "seed=0.5"),
                       (2**70, "seed="), (2**63 - 3, "seed="), (True, "seed=True"),
                       ([0, 1, 2, -1], r"seed\[3\]"), ("x", "seed='x'")):
        with pytest.raises(ArgumentError, match=named) as err:
            envs.reset(seed=bad)
        assert "\n" not in str(err.value)
    envs.reset(seed=2**63 - 4)  # the last sub-environment's seed is the largest integer
    first, _ = envs.reset(seed=[5, None, 6, None])
    again, _ = envs.reset(seed=[5, 1, 6, 2])
    assert np.array_equal(first["face"][[0, 2]], again["face"][[0, 2]])
    with pytest.raises(ArgumentError, match="dtype bool"):
        envs.step(np.ones((4, 2), bool))
    one = JointAttentionEnv(obs_mode="face")
    one.reset(seed=0)
    with pytest.raises(ArgumentError, match="dtype bool"):
        one.step(np.array([True, False]))


@pytest.mark.parametrize("autoreset_mode", ["NextStep", "SameStep"])
@pytest.mark.parametrize("env_id", ["JointAttentionFace-N5-v2", "JointAttentionDetections-N3-v1"])
def test_a_copy_of_the_native_vector_env_continues_every_episode(env_id, autoreset_mode):
    """Pickled or deep-copied mid-episode, the vector env's copy steps as the original does."""
    envs = gym.make_vec(env_id, num_envs=4, vectorization_mode="vector_entry_point",
                        autoreset_mode=autoreset_mode)
    envs.reset(seed=3)
    rng = np.random.default_rng(0)
    for _ in range(25):
        envs.step(rng.uniform(-1, 1, (4, 2)))
    copies = [pickle.loads(pickle.dumps(envs)), copy.deepcopy(envs)]
    actions = rng.uniform(-1, 1, (150, 4, 2))
    original = [envs.step(a) for a in actions]
    # episodes restart in the copied part: the copies' generators carry on too
    assert sum(int((step[2] | step[3]).sum()) for step in original) > 20
    for other in copies:
        assert all(_equal(other.step(a), step) for a, step in zip(actions, original, strict=True))


@pytest.mark.parametrize("env_id", ["JointAttentionFace-N5-v2", "JointAttentionDetections-N10-v1"])
def test_same_step_autoreset_equals_a_sync_vector_env(env_id):
    """With autoreset_mode="SameStep" the native env restarts episodes as SyncVectorEnv does."""
    native = _rollout(env_id, "vector_entry_point", 4, 200, autoreset_mode="SameStep")
    sync = _rollout(env_id, "sync", 4, 200, vector_kwargs={"autoreset_mode": "SameStep"})
    assert sum(int(step[4].get("_final_obs", np.zeros(1)).sum()) for step in native[1:]) > 20
    for a, b in zip(native, sync, strict=True):
        assert _equal(a, b)


def test_the_native_vector_env_needs_a_reset_renders_and_checks_its_mode():
    """A step before reset is refused; render shows env 0's face; a bad autoreset mode is named."""
    from jointattention.errors import ConfigError

    envs = gym.make_vec("JointAttentionFace-N3-v2", num_envs=3,
                        vectorization_mode="vector_entry_point", render_mode="rgb_array")
    with pytest.raises(gym.error.ResetNeeded, match="reset"):
        envs.step(np.zeros((3, 2)))
    envs.reset(seed=0)
    one = gym.make("JointAttentionFace-N3-v2", render_mode="rgb_array")
    one.reset(seed=0)
    assert np.array_equal(envs.render(), one.render()) and envs.render().shape == (25, 30, 3)
    with pytest.raises(ConfigError, match="autoreset_mode"):
        gym.make_vec("JointAttentionFace-v2", num_envs=2, vectorization_mode="vector_entry_point",
                     autoreset_mode="Disabled")


@pytest.mark.usefixtures("needs_gl")
def test_every_observation_lies_in_its_space():
    """Over random episodes of every id (v1 and v2), each observation is inside its space."""
    for env_id in ENV_IDS:
        kwargs = {"width": 64, "height": 48} if "Face" not in env_id and (
            "Detections" not in env_id) else {}
        env = gym.make(env_id, **kwargs)
        env.action_space.seed(0)
        obs, _ = env.reset(seed=0)
        for _ in range(40 if kwargs else 300):
            assert env.observation_space.contains(obs), (env_id, obs)
            obs, _, terminated, truncated, _ = env.step(env.action_space.sample())
            if terminated or truncated:
                obs, _ = env.reset()
        env.close()


def test_v2_shows_v1_scaled():
    """v2 is v1 scaled: face g / 255 - 0.5, head angle in [-1, 1], centres from the middle."""
    v1, v2 = (gym.make(f"JointAttentionDetections-N5-v{v}") for v in (1, 2))
    (a, _), (b, _) = v1.reset(seed=4), v2.reset(seed=4)
    for _ in range(30):
        assert np.allclose(b["face"], a["face"] / 255 - 0.5, atol=1e-6)  # float32
        limits = v1.unwrapped.joint_limits_rad
        assert np.allclose(b["head_angle"], (a["head_angle"] - limits.mean(1))
                           / (np.diff(limits)[:, 0] / 2), atol=1e-6)
        present = a["detections"][:, 0] == 1
        assert np.allclose(b["detections"][present, 1], (a["detections"][present, 1] - 159.5)
                           / 160, atol=1e-6)
        assert np.all(b["detections"][~present] == 0)
        action = np.array([0.4, -0.2])
        (a, *end), (b, *_) = v1.step(action), v2.step(action)
        if end[1] or end[2]:
            (a, _), (b, _) = v1.reset(), v2.reset()


@pytest.mark.usefixtures("needs_gl")
def test_v3_renders_v2s_episodes_fast():
    """v3 gives v2's scenes, rewards and ends; its images differ from v2's at outlines alone."""
    v2, v3 = gym.make("JointAttention-N3-v2"), gym.make("JointAttention-N3-v3")
    assert v3.unwrapped.config.world.camera.antialias_samples == 0
    (a, _), (b, _) = v2.reset(seed=5), v3.reset(seed=5)
    actions = np.random.default_rng(1).uniform(-1, 1, (30, 2)).astype(np.float32)
    for action in actions:
        x, y = a["image"].astype(int), b["image"].astype(int)
        assert np.array_equal(a["head_angle"], b["head_angle"])
        assert np.mean(np.abs(x - y).max(axis=2) > 40) < 0.02  # most pixels agree
        (a, *end), (b, *end3) = v2.step(action), v3.step(action)
        assert end[:3] == end3[:3]
        if end[1] or end[2]:
            (a, _), (b, _) = v2.reset(), v3.reset()
    assert not np.array_equal(x, y)


@pytest.mark.parametrize("mode", ["face", "detections", "image"])
def test_a_copy_continues_the_episode(mode, request):
    """Pickled or deep-copied mid-episode, a copy gives the original's observations and ends."""
    if mode == "image":
        request.getfixturevalue("needs_gl")
    size = {"width": 64, "height": 48} if mode == "image" else {}
    env = JointAttentionEnv(obs_mode=mode, n_objects=3, normalize_actions=True, **size)
    env.reset(seed=1)
    env.step(np.array([0.3, 0.1]))
    copies = [pickle.loads(pickle.dumps(env)), copy.deepcopy(env)]
    actions = np.random.default_rng(0).uniform(-1, 1, (100, 2))

    def play(e) -> list:
        out = []
        for a in actions:
            step = e.step(a)
            out.append(step[:4])
            if step[2] or step[3]:
                out.append(e.reset())  # the generator carries on too
        return out

    original = play(env)
    assert sum(1 for x in original if len(x) == 2) >= 1  # an episode ended and restarted
    for other in copies:
        assert _equal(tuple(play(other)), tuple(original))
        other.close()
    env.close()


def _same(a, b) -> bool:
    """Equal to the byte: the same keys in order, types, dtypes, shapes and bits (signed zeros)."""
    if isinstance(a, dict):
        return list(a) == list(b) and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, tuple):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, np.ndarray):
        return (type(b) is np.ndarray and a.dtype == b.dtype and a.shape == b.shape
                and a.tobytes() == b.tobytes())
    return type(a) is type(b) and a == b


@pytest.mark.parametrize("kwargs", [
    {"obs_mode": "face", "max_steps": 8},
    {"obs_mode": "detections", "n_objects": 10, "max_steps": 8},
    {"obs_mode": "detections", "scaled_obs": True, "normalize_actions": True, "max_steps": 8},
    {"obs_mode": "face", "scaled_obs": True, "normalize_actions": True, "n_objects": 1,
     "reward": "intrinsic", "max_steps": 8},
])
def test_the_compiled_step_gives_the_trial_loops_episodes(kwargs):
    """One kernel per step gives SceneTrial's episodes, observations and info byte for byte."""
    fast, slow = JointAttentionEnv(**kwargs), JointAttentionEnv(**kwargs)
    slow._fast = None  # the reference: the runner's draw, SceneTrial, info_of and scaled
    wide = 1.5 if kwargs.get("normalize_actions") else 0.3  # beyond the box: clipped
    actions = np.random.default_rng(0).uniform(-wide, wide, (1500, 2)).astype(np.float32)
    ends = set()
    assert _same(fast.reset(seed=3), slow.reset(seed=3))
    for a in actions:
        step = fast.step(a)
        assert _same(step, slow.step(a))
        if step[2] or step[3]:
            info = step[4]
            ends.add("fired" if info["fired"] else "limit" if info["limit_hit"] else "steps")
            assert _same(fast.reset(), slow.reset())
    assert ends == {"fired", "limit", "steps"}  # every way an episode ends was compared


@given(n=st.integers(0, 20), seed=st.integers(0, 2**31))
@settings(max_examples=60, deadline=None)
def test_detection_rows_are_the_detections_rounded_then_clipped(n, seed):
    """The compiled rows equal numpy's: float32 rows of the detections, clipped to the space."""
    from jointattention.agent.detections import Detections
    from jointattention.env._observation import _row_bounds, detection_rows

    rng = np.random.default_rng(seed)
    c, a = rng.uniform(-5, 330, (n, 2)), rng.uniform(-1, 4e5, n)
    e, m = rng.uniform(-0.2, 1.3, n), rng.uniform(-0.2, 1.3, n)
    rows = np.zeros((20, 6), np.float32)
    rows[:n, 0], rows[:n, 1:3], rows[:n, 3], rows[:n, 4], rows[:n, 5] = 1, c, a, e, m
    want = np.clip(rows, *_row_bounds((240, 320)))
    got = detection_rows(Detections(c, a, e, m, (320, 240)))
    assert got.dtype == np.float32 and np.array_equal(got, want)
