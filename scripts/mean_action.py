"""Why PPO's mean action stops short: measure its deterministic and sampled episodes.

Trains Stable-Baselines3's PPO with its defaults (the first recipe) on
``JointAttentionFace-N1-v2`` and on its discrete twin ``JointAttentionFace-N1-Discrete-v2``,
then runs the frozen policy, mean (``deterministic=True``) and sampled, on the same new
episodes. For every episode it records how it ended (joint attention, another object, a
joint limit, the 40-step limit) and, for the continuous id, the size of the last actions and
where the head stopped: how far from the target in degrees, along the line from the face to
the target (short of it or past it) and across it. It also records the policy's own spread,
the Gaussian's standard deviation, in degrees of head turn.

    .venv-rl/bin/python scripts/mean_action.py --out docs/results/rl

writes ``mean_action.md`` (the table docs/reinforcement-learning.md includes) and
``mean_action.json``; ``--quick`` trains 2,048 steps and runs 20 episodes (the tests run it).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import gymnasium as gym
import numpy as np

import jointattention.env  # noqa: F401  (registers the environments)

BOX, DISCRETE = "JointAttentionFace-N1-v2", "JointAttentionFace-N1-Discrete-v2"
ENDS = ("joint attention", "another object", "joint limit", "step limit")


def train(env_id: str, steps: int, seed: int, quick: bool):
    """PPO, SB3's defaults (``MultiInputPolicy``, 8 environments); ``quick``: short rollouts."""
    from stable_baselines3 import PPO
    from stable_baselines3.common.env_util import make_vec_env

    envs = make_vec_env(env_id, 8, seed=seed)
    model = PPO("MultiInputPolicy", envs, seed=seed, device="cpu",
                **({"n_steps": 64} if quick else {}))
    return model.learn(steps)


def episodes(model, env_id: str, n: int, seed: int, deterministic: bool) -> list[dict]:
    """``n`` frozen episodes: how each ended, its last actions and where the head stopped."""
    env = gym.make(env_id)
    inner = env.unwrapped
    kin = inner.kinematics
    out = []
    obs, _ = env.reset(seed=seed)
    for _ in range(n):
        trial = inner._trial
        start = trial.theta_rad.copy()
        goal = np.asarray(kin.centring_angles(trial.target_pos_m)).ravel()
        norms, done = [], False
        while not done:
            action = model.predict(obs, deterministic=deterministic)[0]
            if np.ndim(action):
                norms.append(float(np.abs(action).max()))
            obs, reward, terminated, truncated, info = env.step(action)
            done = terminated or truncated
        end = (ENDS[0] if reward > 0 else ENDS[1] if info["fired"] else
               ENDS[2] if info["limit_hit"] else ENDS[3])
        line = np.rad2deg(goal[:2] - start)
        miss = np.rad2deg(inner._trial.theta_rad - goal[:2])
        unit = line / np.linalg.norm(line)
        out.append({"end": end, "steps": int(inner._trial.n_steps),
                    "last_action": norms[-1] if norms else None,
                    "least_of_last_5": min(norms[-5:]) if norms else None,
                    "miss_deg": float(np.linalg.norm(miss)),
                    "miss_along_deg": float(miss @ unit),  # < 0: short of the target
                    "miss_across_deg": float(abs(miss[0] * unit[1] - miss[1] * unit[0])),
                    "start_to_target_deg": float(np.linalg.norm(line))})
        obs, _ = env.reset()
    return out


def policy_spread_deg(model, env_id: str) -> list[float] | None:
    """The Gaussian's standard deviation in degrees of (pan, tilt) head turn (None: discrete)."""
    log_std = getattr(model.policy, "log_std", None)
    if log_std is None:
        return None
    scale = np.rad2deg(gym.make(env_id).unwrapped.max_step_rad)
    return (np.exp(log_std.detach().cpu().numpy()) * scale).round(2).tolist()


def summary(runs: list[dict]) -> dict:
    """Shares of each end, and, over the step-limit ends, medians of the stop measures."""
    shares = {e: sum(r["end"] == e for r in runs) / len(runs) for e in ENDS}
    stuck = [r for r in runs if r["end"] == ENDS[3]]

    def median(key):
        values = [r[key] for r in stuck if r[key] is not None]
        return float(np.median(values)) if values else None

    return {"episodes": len(runs), "shares": shares, "timeouts": len(stuck),
            **{f"timeouts_median_{k}": median(k) for k in
               ("last_action", "least_of_last_5", "miss_deg", "miss_along_deg",
                "miss_across_deg")}}


def main() -> None:
    """Train, run the frozen episodes, write the table and the measures."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=float, default=250_000, help="PPO steps (2.5e5)")
    parser.add_argument("--episodes", type=int, default=1000, help="frozen episodes (1000)")
    parser.add_argument("--seed", type=int, default=0, help="seed (0)")
    parser.add_argument("--out", default="runs/mean_action", help="output folder")
    parser.add_argument("--quick", action="store_true", help="2,048 steps and 20 episodes")
    args = parser.parse_args()
    steps, n = (2048, 20) if args.quick else (int(args.steps), args.episodes)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    result = {"command": "python scripts/mean_action.py" + (" --quick" if args.quick else ""),
              "steps": steps, "seed": args.seed, "ids": {}}
    for env_id in (BOX, DISCRETE):
        t = time.perf_counter()
        model = train(env_id, steps, args.seed, args.quick)
        runs = {mode: episodes(model, env_id, n, 10_000 + args.seed, mode == "mean")
                for mode in ("mean", "sampled")}
        result["ids"][env_id] = {"policy_std_deg": policy_spread_deg(model, env_id),
                                 "minutes": round((time.perf_counter() - t) / 60, 2),
                                 **{mode: summary(r) for mode, r in runs.items()}}
    (out / "mean_action.json").write_text(json.dumps(result, indent=1) + "\n")
    lines = _table(result)
    (out / "mean_action.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


def _num(x, fmt: str = ".3f") -> str:
    return "-" if x is None else format(x, fmt)


def _table(result: dict) -> list[str]:
    lines = ["| environment | action | joint attention | another object | joint limit | "
             "step limit | timeouts: last action (median) | timeouts: head from target, ° "
             "(along, across the face-target line) |", "|---|---|---|---|---|---|---|---|"]
    for env_id, r in result["ids"].items():
        for mode in ("mean", "sampled"):
            s = r[mode]
            sh = s["shares"]
            miss = ("-" if s["timeouts"] == 0 else
                    f"{_num(s['timeouts_median_miss_deg'], '.1f')} "
                    f"({_num(s['timeouts_median_miss_along_deg'], '+.1f')}, "
                    f"{_num(s['timeouts_median_miss_across_deg'], '.1f')})")
            lines.append(f"| {env_id} | {mode} | {sh[ENDS[0]]:.3f} | {sh[ENDS[1]]:.3f} | "
                         f"{sh[ENDS[2]]:.3f} | {sh[ENDS[3]]:.3f} | "
                         f"{_num(s['timeouts_median_last_action'], '.1e')} | {miss} |")
    std = result["ids"][BOX]["policy_std_deg"]
    lines += ["", f"(PPO, SB3 defaults, 8 environments, {result['steps']:,} steps, seed "
              f"{result['seed']}; {result['ids'][BOX]['mean']['episodes']:,} frozen episodes "
              f"each from seed {10_000 + result['seed']}, the same for mean and sampled. "
              f"Last action: the largest of |pan|, |tilt| in [-1, 1] units. The Gaussian's "
              f"standard deviation of {BOX}: {std[0]:.1f}° of pan, {std[1]:.1f}° of tilt. "
              f"Command: `{result['command']}`.)"]
    return lines


if __name__ == "__main__":
    main()
