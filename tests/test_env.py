"""The Gymnasium environment: API contract, seeding, rewards, episode ends, the face wrapper."""

from __future__ import annotations

import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from jointattention.env import ENV_ID, FaceWindowObservation, JointAttentionEnv
from jointattention.errors import ConfigError

pytestmark = pytest.mark.usefixtures("needs_gl")


def _toward(env: JointAttentionEnv, obj: int) -> np.ndarray:
    """The action that turns the head toward object ``obj`` (the experimenter's knowledge)."""
    w = env.unwrapped._world
    want = w.kinematics.centring_angles(w.state.object_pos_m[obj]) - w.head_angle_rad
    return np.clip(want, -env.max_step_rad, env.max_step_rad).astype(np.float32)


def _drive_to(env: JointAttentionEnv, obj: int):
    for _ in range(env.max_steps):
        out = env.step(_toward(env, obj))
        if out[2] or out[3]:
            return out
    raise AssertionError("the episode did not end")


def test_check_env_passes():
    """Gymnasium's check_env passes for the registered env and for the face-window wrapper."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the wrapper is checked on purpose
        env = gym.make(ENV_ID, n_objects=3, render_mode="rgb_array")
        check_env(env.unwrapped)
        check_env(FaceWindowObservation(JointAttentionEnv(n_objects=3)))
        env.close()


def test_seeded_reset_is_reproducible_and_scenes_are_random():
    """reset(seed=s) gives the same first image and target; other seeds give other scenes."""
    env = JointAttentionEnv(n_objects=3)
    a, ia = env.reset(seed=7)
    b, ib = env.reset(seed=7)
    assert np.array_equal(a["image"], b["image"]) and ia["target"] == ib["target"]
    angles = {tuple(np.round(env.reset(seed=s)[0]["head_angle"], 4)) for s in range(6)}
    assert len(angles) == 6  # the caregiver (and so the start) differs from seed to seed
    positions = set()
    for _ in range(6):  # unseeded resets draw new scenes
        env.reset()
        positions.add(tuple(np.round(env.unwrapped._world.state.target_pos_m, 4)))
    assert len(positions) == 6


def test_reaching_the_target_gives_both_rewards():
    """Centring the caregiver's target fires the evaluator: external and intrinsic reward 1."""
    env = JointAttentionEnv(n_objects=3, reward="external")
    _, info = env.reset(seed=1)
    obs, reward, terminated, truncated, info = _drive_to(env, info["target"])
    assert terminated and not truncated and info["fired"]
    assert info["attended"] == info["target"]
    assert reward == 1.0 and info["intrinsic_reward"] == 1.0
    assert obs in env.observation_space


def test_reaching_a_distractor_gives_only_the_intrinsic_reward():
    """Centring another object: the evaluator fires (intrinsic 1) but no joint attention."""
    env = JointAttentionEnv(n_objects=3, reward="intrinsic")
    _, info = env.reset(seed=2)
    other = (info["target"] + 1) % 3
    _, reward, terminated, _, info = _drive_to(env, other)
    assert terminated and info["attended"] == other
    assert reward == 1.0 and info["external_reward"] == 0.0


def test_truncation_after_max_steps():
    """Keeping still ends the episode by truncation after max_steps, with no reward."""
    env = JointAttentionEnv(n_objects=2, max_steps=3)
    env.reset(seed=0)
    ends = [env.step(np.zeros(2, np.float32))[2:4] for _ in range(3)]
    assert ends == [(False, False), (False, False), (False, True)]


def test_a_joint_limit_ends_the_episode():
    """Turning the head into its pan limit terminates the episode at the limit."""
    env = JointAttentionEnv(n_objects=1)
    env.reset(seed=0)
    push = np.array([env.max_step_rad[0], 0.0], np.float32)
    for _ in range(env.max_steps):
        obs, reward, terminated, truncated, info = env.step(push)
        if terminated or truncated:
            break
    assert terminated and info["limit_hit"] and not info["fired"] and reward == 0.0
    assert obs["head_angle"][0] == pytest.approx(env.observation_space["head_angle"].high[0])


def test_face_window_is_kept_for_the_episode():
    """The wrapper's face window is a 25 x 30 uint8 image, the same at every step."""
    env = FaceWindowObservation(JointAttentionEnv(n_objects=3))
    obs, _ = env.reset(seed=3)
    assert obs["face"].shape == (25, 30) and obs["face"].dtype == np.uint8
    assert obs["face"].std() > 5  # a face, not a blank crop
    obs2, *_ = env.step(np.array([0.05, 0.0], np.float32))
    assert np.array_equal(obs["face"], obs2["face"])


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"reward": "extrinsic"}, "expected one of 'external', 'intrinsic'"),
    ({"n_objects": 0}, r"expected an integer in \[1, 20\]"),
    ({"render_mode": "screen"}, "expected one of None, 'rgb_array', 'human'"),
    ({"config": "no-such-preset"}, "no such preset"),
    ({"render_quality": "low"}, "expected one of 'full', 'fast'"),
    ({"render_quality": "fast", "obs_mode": "face"}, "expected 'full' with obs_mode='face'"),
])
def test_bad_arguments_are_refused(kwargs, match):
    """Bad constructor arguments raise one ConfigError naming what was expected."""
    with pytest.raises(ConfigError, match=match):
        JointAttentionEnv(**kwargs)


def test_a_pool_of_poses_keeps_targets_and_redraws_distractors():
    """With n_poses=2, episodes reuse two caregiver poses and targets.

    The distractors and the target's place in the object list change.
    """
    env = JointAttentionEnv(n_objects=4, n_poses=2)
    env.reset(seed=5)
    targets, scenes = set(), set()
    for _ in range(12):
        env.reset()
        state = env.unwrapped._world.state
        targets.add(tuple(np.round(state.target_pos_m, 6)))
        scenes.add(tuple(np.round(state.object_pos_m.ravel(), 6)))
    assert len(targets) == 2 and len(scenes) == 12


def test_an_agent_runs_the_same_trial_through_the_environment():
    """An agent's trial through the environment equals the same trial run directly.

    ``run_trial`` over ``EnvTrial`` (each step an ``env.step``) gives the trial that ``run_trial``
    over the episode's own scene gives: the environment's step is the trial loop's.
    """
    from functools import partial

    from jointattention.agent.attention import attended_object
    from jointattention.env import EnvTrial
    from jointattention.experiment.oracle import OracleAgent
    from jointattention.experiment.trial import SceneTrial, run_trial

    env = gym.make(ENV_ID, n_objects=5, max_steps=12)
    world = env.unwrapped._world
    step = np.deg2rad(4.0)
    for seed in range(6):
        trial = EnvTrial(env, seed=seed)
        start = trial.theta_rad
        aim = world.kinematics.centring_angles(world.state.target_pos_m)
        scene_trial = SceneTrial(world.fast_scene(), start, kinematics=world.kinematics,
                                 max_steps=12, evaluate=partial(attended_object,
                                                                d_th_px=320 / 6))
        direct = run_trial(scene_trial, OracleAgent(aim, step), np.zeros((25, 30)))
        through = run_trial(trial, OracleAgent(aim, step), np.zeros((25, 30)))
        assert (through.n_steps, through.attended, through.target, through.end) == (
            direct.n_steps, direct.attended, direct.target, direct.end)
        assert through.success == (trial.reward == 1.0)
    env.close()
