"""Saved population models on caregivers recorded from held-out seeds nothing else uses.

Usage::

    python docs/results/generalise/fresh.py [--models runs/trained]
        [--out docs/results/generalise/fresh.md] [--objects 5 10] [--training-seeds 3]
        [--held-out-seeds 2026 77 4242] [--files population-n{n}-s{i}.npz]
        [--world PRESET|FILE.toml] [--quick]

Reads the models ``population-n5-s{0,1,2}.npz`` and ``population-n10-s{0,1,2}.npz`` that
``jointattention train --preset generalise --condition population-nN --seed-index I --out
runs/trained/population-nN-sI.npz`` wrote (the preset's 64 training caregivers, world seed 1),
records 32 caregivers x 25 poses from each of three held-out seeds (2026, 77, 4242: no file
or test of the repository uses them), and measures each model frozen on each set with its own
object count (:func:`jointattention.evaluate`, 10,000 trials of the model and of the oracle).
Writes one row per model and set, then the mean and the worst over them, and the command that
wrote them. Other models (e.g. the people world's, docs/results/people/sockets_net_n10.md) take
``--files`` (``{n}``: the object count, ``{i}``: the seed index) and seeds of their own
(``--held-out-seeds``). ``--world`` records the caregivers of another world instead, with
the model's own robot (:meth:`~jointattention.config.WorldConfig.with_people_of`: e.g. a
people-world model among the default world's caregivers, ``--world generalise``).
``--quick`` (the tests' run): one held-out seed, 2 caregivers x 2 poses, 50 trials.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

import jointattention as ja
from jointattention._files import write_text
from jointattention.config import load_config
from jointattention.errors import ConfigError
from jointattention.experiment.held_out import held_out_datasets

SEEDS = (2026, 77, 4242)
N_CAREGIVERS, N_POSES, N_TRIALS = 32, 25, 10_000


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--models", default="runs/trained", type=Path)
    parser.add_argument("--out", default="docs/results/generalise/fresh.md")
    parser.add_argument("--objects", nargs="+", type=int, default=[5, 10],
                        help="the models' object counts (default 5 10)")
    parser.add_argument("--training-seeds", type=int, default=3,
                        help="models per object count: seed indices 0 to this - 1 (default 3)")
    parser.add_argument("--held-out-seeds", nargs="+", type=int, default=list(SEEDS),
                        help="world seeds of the held-out sets (default 2026 77 4242: no other "
                        "file or test uses them)")
    parser.add_argument("--files", default="population-n{n}-s{i}.npz",
                        help="the models' file names in --models ({n}: objects, {i}: seed index)")
    parser.add_argument("--world", metavar="PRESET|FILE.toml",
                        help="record the caregivers, light, room and sensor of this "
                        "configuration's world, with the model's own camera and windows "
                        "(default: the model's own world)")
    parser.add_argument("--quick", action="store_true", help="small sets (the tests' run)")
    args = parser.parse_args()
    try:  # before any recording: a bad name is one line, not a traceback
        people = None if args.world is None else load_config(args.world).world
    except ConfigError as e:
        parser.error(f"--world: {e}")
    seeds, n_caregivers, n_poses, n_trials = (tuple(args.held_out_seeds), N_CAREGIVERS,
                                              N_POSES, N_TRIALS)
    if args.quick:
        seeds, n_caregivers, n_poses, n_trials = seeds[:1], 2, 2, 50
    command = " ".join(["python docs/results/generalise/fresh.py", *sys.argv[1:]])
    start = time.perf_counter()
    rows = ["| model | objects | training seed | held-out seed | success | ceiling | fraction "
            "of the ceiling | median error | 90th percentile | identities above 10° | novelty: "
            "median, max |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    summary = []
    for n in args.objects:
        fractions, medians, shares = [], [], []
        for i in range(args.training_seeds):
            model = ja.load_model(args.models / args.files.format(n=n, i=i))
            world = model.config.world
            world = world if people is None else world.with_people_of(people)
            for seed in seeds:
                ds = held_out_datasets(world, n_caregivers, n_poses, seed)
                e = ja.evaluate(model, ds, n_objects=n, n_trials=n_trials, seed=seed)
                fractions.append(e.fraction_of_ceiling)
                medians.append(e.median_error_deg)
                shares.append(e.share_identities_over_10deg)
                rows.append(f"| population-n{n} | {n} | {i} | {seed} | {e.success:.3f} | "
                            f"{e.ceiling:.3f} | {e.fraction_of_ceiling:.3f} | "
                            f"{e.median_error_deg:.1f}° | {e.p90_error_deg:.1f}° | "
                            f"{e.share_identities_over_10deg:.2f} | {e.novelty_median:.2f}, "
                            f"{e.novelty_max:.2f} |")
        summary.append(f"| population-n{n} | {np.mean(fractions):.3f} | {min(fractions):.3f} | "
                       f"{np.mean(medians):.1f}° | {max(medians):.1f}° | {max(shares):.2f} |")
    text = "\n".join(
        [*rows, "", "| model | fraction of the ceiling, mean | worst | median error, mean | "
         "worst | identities above 10°, worst |", "|---|---|---|---|---|---|", *summary,
         "", f"{args.training_seeds} training seeds x {len(seeds)} sets of {n_caregivers} "
         f"caregivers x {n_poses} poses, {n_trials:,} trials each; "
         f"`{command}` ({(time.perf_counter() - start) / 60:.1f} min). Novelty: each unseen "
         "caregiver's distance to the nearest training caregiver in the world's parameter "
         "space, in spacings among the training caregivers (docs/generalisation.md)."]) + "\n"
    print(write_text(args.out, text))
    print(text)


if __name__ == "__main__":
    main()
