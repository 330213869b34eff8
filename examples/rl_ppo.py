"""PPO (Stable-Baselines3) learns joint attention in the face mode, against the bootstrap model.

The RL agent gets the external reward: 1 when the object it centres is the caregiver's target.
That is the answer the bootstrap model must find by itself (its evaluator fires on any object).
Both see the same fast world: a data set's face window and head angle, random distractors.
PPO learns by the first recipe of docs/reinforcement-learning.md: ``JointAttentionFace-N{n}-v2``
(observations already scaled near [-1, 1]), 8 environments, ``MultiInputPolicy`` and SB3's
defaults (``--smoke``: shorter rollouts, so that a few hundred steps make one).

    pip install "jointattention[rl]"
    python examples/rl_ppo.py --n-objects 1 3 --steps 300000 --out runs/rl

writes ``curves.csv`` and ``curves.png`` (success per episode against environment steps for PPO,
the bootstrap model's learning time, and a uniform-random policy's level) and ``curves.md``, the
table it prints: final success (the last bin), and the steps each needs to reach 0.9 of the
lower final.
``--smoke`` runs a few hundred steps (the test suite runs it).
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
from pathlib import Path

import gymnasium as gym
import numpy as np

import jointattention.env  # noqa: F401  (registers the environments)
from jointattention import ConditionConfig, load_config, run_cell


def train_ppo(n_objects: int, steps: int, seed: int,
              smoke: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """PPO's training episodes: (environment steps at the episode's end, success).

    SB3's ``MultiInputPolicy`` takes v2's dict of scaled observations as it is (it flattens
    and joins the face and the head angle): no wrapper.
    """
    from stable_baselines3 import PPO
    from stable_baselines3.common.env_util import make_vec_env

    from jointattention.env.sb3 import EpisodeLog

    log = EpisodeLog()
    envs = make_vec_env(f"JointAttentionFace-N{n_objects}-v2", n_envs=8, seed=seed)
    # --smoke: 64-step rollouts, else PPO's 2,048 x 8 would be one rollout of 16,384 steps
    short = {"n_steps": 64} if smoke else {}
    model = PPO("MultiInputPolicy", envs, seed=seed, device="cpu", verbose=0, **short)
    model.learn(steps, callback=log)
    envs.close()
    return np.array(log.ends), np.array(log.wins, dtype=float)


def random_level(n_objects: int, episodes: int, seed: int) -> float:
    """The success of uniform-random actions, per episode."""
    from jointattention.env.sb3 import success_rate

    return success_rate(None, gym.make(f"JointAttentionFace-N{n_objects}-v2"), episodes, seed)


def bootstrap(n_objects: int, steps: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """The bootstrap model (the paper's preset) learning for ``steps``: (time, success)."""
    config = load_config("paper")
    config = dataclasses.replace(config, experiment=dataclasses.replace(config.experiment,
                                                                        n_steps=steps))
    rec = run_cell(config, ConditionConfig(name=f"n{n_objects}", n_objects=n_objects), seed)
    return rec["learning_time"].astype(float), rec["success"].astype(float)


def curve(times: np.ndarray, success: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Mean success of the episodes in each bin of ``edges`` (NaN where none)."""
    which = np.digitize(times, edges[1:-1])
    return np.array([success[which == b].mean() if np.any(which == b) else np.nan
                     for b in range(len(edges) - 1)])


def steps_to(level: float, mids: np.ndarray, values: np.ndarray) -> float:
    """The first bin's middle where ``values`` reach ``level`` (NaN if never)."""
    hit = np.flatnonzero(values >= level)
    return float(mids[hit[0]]) if len(hit) else float("nan")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n-objects", type=int, nargs="+", default=[1, 3],
                        help="object counts (default: 1 3)")
    parser.add_argument("--steps", type=int, default=300_000,
                        help="environment steps of learning (default: 3e5, the paper's)")
    parser.add_argument("--bins", type=int, default=15, help="learning-curve bins (default 15)")
    parser.add_argument("--seed", type=int, default=0, help="seed (default 0)")
    parser.add_argument("--out", default="runs/rl", help="output folder (default runs/rl)")
    parser.add_argument("--smoke", action="store_true", help="a few hundred steps only")
    args = parser.parse_args()
    steps = 512 if args.smoke else args.steps
    bins = 2 if args.smoke else args.bins
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    edges = np.linspace(0, steps, bins + 1)
    mids = (edges[:-1] + edges[1:]) / 2
    rows, table = [], []
    for n in args.n_objects:
        chance = random_level(n, 50 if args.smoke else 2000, args.seed)
        ppo = curve(*train_ppo(n, steps, args.seed, args.smoke), edges)
        boot = curve(*bootstrap(n, steps, args.seed), edges)
        rows += [(n, "ppo", m, v) for m, v in zip(mids, ppo, strict=True)]
        rows += [(n, "bootstrap", m, v) for m, v in zip(mids, boot, strict=True)]
        rows += [(n, "random", m, chance) for m in mids]
        level = 0.9 * min(ppo[-1], boot[-1])  # a success both reach
        table.append((n, chance, ppo[-1], boot[-1], level, steps_to(level, mids, ppo),
                      steps_to(level, mids, boot)))
    with open(out / "curves.csv", "w", newline="") as f:
        csv.writer(f).writerows([("n_objects", "model", "steps", "success"), *rows])
    _figure(rows, args.n_objects, out / "curves.png")
    lines = ["| objects | random | PPO final | bootstrap final | level: 0.9 x the lower final | "
             "PPO steps to it | bootstrap steps to it |", "|---|---|---|---|---|---|---|"]
    lines += [f"| {n} | {chance:.3f} | {p:.3f} | {b:.3f} | {level:.3f} | {sp:,.0f} | {sb:,.0f} |"
              for n, chance, p, b, level, sp, sb in table]
    (out / "curves.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    print(out / "curves.csv", out / "curves.png", out / "curves.md")


def _figure(rows, counts, path: Path) -> None:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(4 * len(counts), 3.2), layout="tight")
    for i, n in enumerate(counts):
        ax = fig.add_subplot(1, len(counts), i + 1)
        for model, style in (("ppo", "-"), ("bootstrap", "--"), ("random", ":")):
            pts = [(s, v) for c, m, s, v in rows if c == n and m == model]
            ax.plot(*zip(*pts, strict=True), style, label=model)
        ax.set(title=f"{n} object{'s' * (n > 1)}", xlabel="environment steps (learning time)",
               ylabel="success per episode", ylim=(0, 1.02))
        ax.ticklabel_format(axis="x", style="sci", scilimits=(0, 0))
        ax.legend()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main()
