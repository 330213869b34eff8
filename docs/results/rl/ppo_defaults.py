"""Stable-Baselines3's PPO with its defaults on the v2 environments, beside v1 and our own RL model.

The recipe a new user tries first: ``PPO("MultiInputPolicy", make_vec_env(id, 8))``, nothing
tuned. On v1 (raw observations: uint8 grey levels) it does not learn; on v2 (the same
environment with ``scaled_obs=True``) it does. Beside it: PPO through the native vector
environment (``jointattention.env.sb3.NativeVecEnv``, 64 environments in one compiled step),
the project's own reinforcement learner (``kind = "rl"``, Triesch et al. 2006: SARSA over gaze
shifts with interest and habituation, learning from its own evaluator, not from the external
reward PPO gets), a uniform-random policy, and the ceiling (the oracle gaze-line follower).

Success is measured where the model learned (the 125 shipped data sets, new distractors) and,
frozen, on data sets no training set uses: new poses of the same caregiver and unseen
caregivers (the shipped held-out sets, recorded with their own world seeds).

    make test-rl                                   # the rl extra, CPU PyTorch where it can
    .venv-rl/bin/python docs/results/rl/ppo_defaults.py --out docs/results/rl

writes ``ppo_defaults.md`` (the table), ``ppo_defaults.csv`` and ``ppo_defaults.png``
(success per episode against environment steps). ``--quick`` (the tests' run): 2,048 steps a
run, PPO's rollouts cut to 1,024 steps, one seed, 20 episodes a frozen measure.
"""

from __future__ import annotations

import argparse
import csv
import json
import time
from importlib import resources
from pathlib import Path

import gymnasium as gym
import numpy as np

import jointattention.env  # noqa: F401  (registers the environments)
from jointattention import ConditionConfig, load_config, measure_ceiling
from jointattention.experiment.held_out import SHIPPED, final_held_out, run_cell_measured

STEPS, BIN = 250_000, 25_000
QUICK = False  # --quick: main() sets STEPS, BIN and this; PPO then rolls out 1,024 steps


def ppo(env_id: str, seed: int, native: bool = False):
    """PPO with SB3's defaults: (episode end steps, success), the model, wall seconds."""
    from stable_baselines3 import PPO
    from stable_baselines3.common.env_util import make_vec_env

    from jointattention.env.sb3 import EpisodeLog, NativeVecEnv

    log = EpisodeLog()
    t = time.perf_counter()
    if native:  # 64 environments: a shorter rollout per environment, the rest the defaults
        env = NativeVecEnv(env_id, num_envs=64, seed=seed)
        model = PPO("MultiInputPolicy", env, n_steps=16 if QUICK else 256, seed=seed,
                    device="cpu")
    else:
        env = make_vec_env(env_id, 8, seed=seed)
        model = PPO("MultiInputPolicy", env, seed=seed, device="cpu",
                    **({"n_steps": 128} if QUICK else {}))
    model.learn(STEPS, callback=log)
    env.close()
    return np.array(log.ends), np.array(log.wins, float), model, time.perf_counter() - t


def frozen_success(model, env_id: str, datasets: str | None, episodes: int, seed: int,
                   deterministic: bool = False) -> float:
    """The learned policy's success on ``datasets`` (None: training).

    Actions are drawn from the policy, as in learning; ``deterministic``: its mean action.
    """
    from jointattention.env.sb3 import success_rate

    config = load_config({} if datasets is None else {"datasets": datasets})
    return success_rate(model, gym.make(env_id, config=config), episodes, seed, deterministic)


def random_level(env_id: str, episodes: int, seed: int) -> float:
    """The success of uniform-random actions."""
    from jointattention.env.sb3 import success_rate

    return success_rate(None, gym.make(env_id), episodes, seed)


def own_rl(n_objects: int, seed: int):
    """The project's reinforcement learner in the same fast world: (times, success, held-out)."""
    config = load_config({"model": {"kind": "rl"}, "experiment": {
        "n_steps": STEPS, "bin_steps": BIN, "engine": "python",
        "held_out": {"n_trials": 50 if QUICK else 2000, "n_checkpoints": 1}}})
    rec = run_cell_measured(config, ConditionConfig(name=f"rl-n{n_objects}",
                                                    n_objects=n_objects), seed)
    held = final_held_out(rec)
    return (rec["learning_time"].astype(float), rec["success"].astype(float),
            {k: held[k]["success"] for k in held})


def curve(times: np.ndarray, success: np.ndarray) -> np.ndarray:
    """Mean success of the episodes ending in each bin of BIN steps."""
    which = np.minimum(times // BIN, STEPS // BIN - 1).astype(int)
    return np.array([success[which == b].mean() if np.any(which == b) else np.nan
                     for b in range(STEPS // BIN)])


def steps_to(level: float, values: np.ndarray) -> float:
    """The end of the first bin whose mean reaches ``level`` (NaN if none)."""
    hit = np.flatnonzero(values >= level)
    return float((hit[0] + 1) * BIN) if len(hit) else float("nan")


def ppo_record(env_id: str, native: bool, seed: int, held: dict, episodes: int) -> dict:
    """One PPO run: its learning curve, frozen successes and wall time."""
    ends, wins, model, seconds = ppo(env_id, seed, native)
    frozen = {"training": frozen_success(model, env_id, None, episodes, 10_000 + seed)}
    for kind, path in held.items():
        frozen[kind] = frozen_success(model, env_id, path, episodes, 10_000 + seed)
    frozen["mean"] = frozen_success(model, env_id, None, episodes, 10_000 + seed,
                                    deterministic=True)
    return {"curve": curve(ends, wins).tolist(), "frozen": frozen, "seconds": seconds}


def own_record(n_objects: int, seed: int) -> dict:
    """One run of the project's RL model: its learning curve, frozen successes, wall time."""
    t = time.perf_counter()
    times, success, frozen = own_rl(n_objects, seed)
    return {"curve": curve(times, success).tolist(), "frozen": {**frozen, "mean": None},
            "seconds": time.perf_counter() - t}


def main() -> None:
    global STEPS, BIN, QUICK
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=3, help="seeds per row (default 3)")
    parser.add_argument("--episodes", type=int, default=1000,
                        help="episodes per frozen measure (default 1000)")
    parser.add_argument("--out", default="docs/results/rl",
                        help="output folder (default docs/results/rl)")
    parser.add_argument("--quick", action="store_true",
                        help="2,048 steps a run, one seed, 20 episodes (the tests' run)")
    args = parser.parse_args()
    if args.quick:
        STEPS, BIN, QUICK, args.seeds, args.episodes = 2_048, 1_024, True, 1, 20
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    held = {kind: str(resources.files("jointattention.data") / name)
            for kind, name in SHIPPED.items()}
    own = "own RL model (kind rl), its own evaluator"
    runs = [("PPO, SB3 defaults, 8 envs", "JointAttentionFace-N1-v1", 1),
            ("PPO, SB3 defaults, 8 envs", "JointAttentionFace-N1-v2", 1),
            ("PPO, SB3 defaults, 8 envs", "JointAttentionFace-N5-v2", 5),
            ("PPO, NativeVecEnv x64 (n_steps=256)", "JointAttentionFace-N1-v2", 1),
            ("PPO, NativeVecEnv x64 (n_steps=256)", "JointAttentionFace-N5-v2", 5),
            (own, "runner, 1 object", 1), (own, "runner, 5 objects", 5)]
    done_path = out / "ppo_defaults_runs.json"  # each finished run: a re-run resumes
    done = json.loads(done_path.read_text()) if done_path.exists() else {}
    rows = []
    for label, env, n in runs:
        ceiling = measure_ceiling(load_config(None), n)
        records = []
        for seed in range(args.seeds):
            key = f"{label} | {env} | {seed} | {args.episodes}" + (" | quick" if QUICK else "")
            if key not in done:
                done[key] = (own_record(n, seed) if label == own else
                             ppo_record(env, "Native" in label, seed, held, args.episodes))
                tmp = done_path.with_suffix(".tmp")
                tmp.write_text(json.dumps(done, indent=1))
                tmp.replace(done_path)
            records.append(done[key])
            print(label, env, seed, f"final {done[key]['curve'][-1]:.3f}", flush=True)
        chance = float("nan") if label == own else random_level(env, args.episodes if QUICK
                                                                 else 2000, 0)
        rows.append((label, env, n, ceiling, chance, records))
    _write(rows, out, args)


def _fmt(values) -> str:
    values = np.asarray(values, float)
    if np.all(np.isnan(values)):
        return "never"
    text = f"{np.nanmean(values):.3f}"
    return text if len(values) == 1 else f"{text} ({np.nanmin(values):.2f}-{np.nanmax(values):.2f})"


def _steps(values) -> str:
    values = np.asarray(values, float)
    reached = values[np.isfinite(values)]
    if len(reached) == 0:
        return "never"
    return f"{np.mean(reached):,.0f}" + ("" if len(reached) == len(values) else
                                         f" ({len(reached)} of {len(values)} seeds)")


def _write(rows, out: Path, args) -> None:
    lines = ["| learner | environment | objects | ceiling | random | final, learning (last "
             f"{BIN:,} steps) | steps to 0.9 x ceiling | frozen: training sets | frozen: "
             "new poses | frozen: unseen caregivers | frozen, mean action: training sets | "
             "minutes per seed |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    curves = {}
    for label, env, n, ceiling, chance, records in rows:
        finals = [r["curve"][-1] for r in records]
        to = [steps_to(0.9 * ceiling, np.array(r["curve"], float)) for r in records]
        frozen = {k: [np.nan if r["frozen"][k] is None else r["frozen"][k] for r in records]
                  for k in records[0]["frozen"]}
        curves[(label, env)] = np.array([r["curve"] for r in records], float)
        lines.append(f"| {label} | {env} | {n} | {ceiling:.3f} | "
                     f"{'-' if np.isnan(chance) else f'{chance:.3f}'} | {_fmt(finals)} | "
                     f"{_steps(to)} | {_fmt(frozen['training'])} | {_fmt(frozen['new poses'])} | "
                     f"{_fmt(frozen['unseen caregivers'])} | "
                     f"{'-' if np.all(np.isnan(frozen['mean'])) else _fmt(frozen['mean'])} | "
                     f"{np.mean([r['seconds'] for r in records]) / 60:.1f} |")
    lines.append("")
    lines.append(f"({args.seeds} seeds each: mean (lowest-highest); {STEPS:,} environment steps; "
                 f"frozen measures: {args.episodes} episodes from world seed 10,000 + seed, "
                 "actions drawn from the learned policy (PPO's Gaussian; the RL model's softmax), "
                 "and, for PPO, its mean action. Command: "
                 "`.venv-rl/bin/python docs/results/rl/ppo_defaults.py`.)")
    (out / "ppo_defaults.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    with open(out / "ppo_defaults.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["learner", "environment", "seed", "bin_end_steps", "success"])
        for (label, env), runs in curves.items():
            for seed, c in enumerate(runs):
                w.writerows([label, env, seed, (b + 1) * BIN, f"{v:.4f}"]
                            for b, v in enumerate(c))
    _figure(curves, out / "ppo_defaults.png")


def _figure(curves, path: Path) -> None:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.5, 4), layout="tight")
    ax = fig.add_subplot()
    x = (np.arange(STEPS // BIN) + 1) * BIN
    for (label, env), runs in curves.items():
        ax.plot(x, np.nanmean(runs, axis=0), marker="o", ms=3, label=f"{label}: {env}")
    ax.set(xlabel="environment steps", ylabel="success per episode (mean over seeds)",
           ylim=(0, 1.02))
    ax.legend(fontsize=6.5)
    fig.savefig(path, dpi=120)


if __name__ == "__main__":
    main()
