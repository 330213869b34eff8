"""The bootstrap learning agent run through the Gymnasium environment ``JointAttention-v1``.

The agent knows only what the environment gives it: the spaces (image size, joint limits,
face-window size), the face window, the head angle and the detector's report in ``info``.
Its success (the external reward) is compared with the library's own runner
(``jointattention reproduce``) for the same configuration, object count and schedule.

    python examples/gym_bootstrap.py --config quick --n-objects 3 --seeds 3

prints the success over the last ``--tail-steps`` of learning time, for each seed, through the
environment and through the runner, and the runner's 95% interval over its seeds.
"""

from __future__ import annotations

import argparse
import dataclasses
import os

import gymnasium as gym
import numpy as np

from jointattention import Body, BootstrapOptions, ConditionConfig, load_config, run_cell
from jointattention.analysis.metrics import T975, mean_interval
from jointattention.config import model_options
from jointattention.env import EnvTrial, FaceWindowObservation
from jointattention.experiment.trial import run_trial
from jointattention.rng import stream
from jointattention.world.gl import suggested_backend

# A program chooses its process's OpenGL backend (the library only reads MUJOCO_GL).
os.environ.setdefault("MUJOCO_GL", suggested_backend())


def run_through_env(config, n_objects: int, seed: int, n_poses: int | None,
                    mode: str = "image") -> tuple[np.ndarray, np.ndarray]:
    """Learn for ``experiment.n_steps`` steps; returns (learning time, success) per trial."""
    if mode == "image":
        env = FaceWindowObservation(gym.make("JointAttention-v1", config=config,
                                             n_objects=n_objects, n_poses=n_poses))
    else:  # the fast world's face window comes with the observation
        env = gym.make("JointAttentionFace-v1", config=config, n_objects=n_objects)
    spaces, kin = env.observation_space, env.unwrapped.kinematics
    head = spaces["head_angle"]
    body = Body(image_size_px=(kin.width_px, kin.height_px),
                joint_limits_rad=tuple(zip(head.low.astype(float), head.high.astype(float),
                                           strict=True)),
                face_size_px=spaces["face"].shape[::-1])
    options: BootstrapOptions = model_options(config, ConditionConfig(n_objects=n_objects))
    agent = options.build(config.agent, body, stream(config.seed, "agent", seed))
    times, successes = [], []
    trial = EnvTrial(env, seed=seed)
    while agent.learning_time_steps < config.experiment.n_steps:
        # the trial loop itself, each step an env.step: the agent sees only obs and info
        result = run_trial(trial, agent, trial.observation["face"])
        times.append(result.learning_time)
        successes.append(trial.reward)
        trial = EnvTrial(env)
    env.close()
    return np.array(times), np.array(successes)


def tail_success(times, success, n_steps: int, tail_steps: int) -> float:
    return float(np.mean(success[np.asarray(times) >= n_steps - tail_steps]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--config", default="quick", help="preset or TOML file (default: quick)")
    parser.add_argument("--n-objects", type=int, default=3, help="objects per scene (default 3)")
    parser.add_argument("--seeds", type=int, default=3, help="seeds through the env (default 3)")
    parser.add_argument("--runner-seeds", type=int, default=10,
                        help="seeds through the runner (default 10)")
    parser.add_argument("--poses", type=int, default=125,
                        help="caregiver poses the env draws from, as the runner's 125 data sets "
                             "(default 125; 0: a new pose every episode)")
    parser.add_argument("--mode", choices=("image", "face"), default="image",
                        help="the environment's observation mode: image (rendered, default) or "
                             "face (no rendering: the runner's own fast world)")
    parser.add_argument("--n-steps", type=int, help="learning time (default: the config's)")
    parser.add_argument("--tail-steps", type=int, default=10_000,
                        help="success is measured over this much final learning time")
    args = parser.parse_args()
    config = load_config(args.config)
    if args.n_steps:
        config = dataclasses.replace(
            config, experiment=dataclasses.replace(config.experiment, n_steps=args.n_steps))
    n, tail = config.experiment.n_steps, args.tail_steps
    condition = ConditionConfig(name=f"n{args.n_objects}", n_objects=args.n_objects)
    runner = np.array([tail_success(r["learning_time"], r["success"], n, tail)
                       for r in (run_cell(config, condition, s) for s in range(args.runner_seeds))])
    env = np.array([tail_success(*run_through_env(config, args.n_objects, s,
                                                  args.poses or None, args.mode), n, tail)
                    for s in range(args.seeds)])
    for name, x in (("runner", runner), ("env", env)):
        mean, lo, hi = (float(v[0]) for v in mean_interval(x[:, None]))
        print(f"{name:<6} {len(x):>2} seeds: success over the last {tail} steps {mean:.3f} "
              f"(95% interval {lo:.3f} to {hi:.3f}); seeds " + " ".join(f"{v:.3f}" for v in x))
    diff = env.mean() - runner.mean()
    se = np.sqrt(env.var(ddof=1) / len(env) + runner.var(ddof=1) / len(runner))
    t = T975[min(len(env), len(runner)) - 2]
    print(f"env - runner: {diff:+.3f} (95% interval {diff - t * se:+.3f} to {diff + t * se:+.3f})")

if __name__ == "__main__":
    main()
