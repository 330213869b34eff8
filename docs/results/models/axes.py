"""Horizontal against vertical: which does each model learn first?

Nagai, Asada, Hosoda (2006) report that their robot learned to follow gaze horizontally before
vertically. This script measures it for the models of the ``models`` preset at 5 objects: it
learns each cell with snapshots of the agent every 5,000 steps and measures, on the 125 data
sets, the median horizontal and vertical error of the learning module
(:func:`jointattention.experiment.probes.axis_errors_deg`). An axis is "learned" at the first
snapshot where its error is at most half its untrained value; "horizontal first" counts the
seeds where the horizontal error halves strictly earlier.

The run's own claim ("horizontal before vertical", ``claims.md``) compares the two errors at
each 10,000-step bin; this script looks at the first steps, from the untrained module, every
5,000 steps.

Run from the repository: ``python docs/results/models/axes.py`` (about 2 min); it writes
``docs/results/models/axes.md`` and ``axes.png`` (``--out FILE.md``: the figure goes beside it).
``--quick``: 2,000 steps, 1 seed, snapshots every 1,000 steps (the tests' run).
"""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

import numpy as np

from jointattention import load_config
from jointattention.experiment.cells import datasets_of
from jointattention.experiment.probes import axis_errors_deg
from jointattention.figures._save import new_figure, save_figure
from jointattention.jobs.learned import snapshots

CONDITIONS = ("paper-n5", "teacher-n5", "developmental-n5", "developmental-sharp-n5",
              "teacher-nogate-n5", "developmental-nogate-n5")
SEEDS, EVERY_STEPS = 10, 5_000
OUT = Path(__file__).parent


def _halved(errors: np.ndarray, steps: np.ndarray) -> float:
    """The first learning time at which the error is at most half its untrained value."""
    hit = np.flatnonzero(errors <= errors[0] / 2)
    return float(steps[hit[0]]) if len(hit) else np.nan


def main() -> None:
    """Measure, write axes.md and axes.png."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT / "axes.md",
                        help="the table (.md); the figure goes beside it (.png)")
    parser.add_argument("--quick", action="store_true", help="2,000 steps (the tests' run)")
    args = parser.parse_args()
    config, n_seeds, every = load_config("models"), SEEDS, EVERY_STEPS
    if args.quick:
        config = dataclasses.replace(config, experiment=dataclasses.replace(
            config.experiment, n_steps=2_000))
        n_seeds, every = 1, 1_000
    ds = datasets_of(config)
    steps = np.arange(0, config.experiment.n_steps + 1, every)
    errors = {}  # condition -> (seeds, snapshots, 2)
    for name in CONDITIONS:
        per_seed = []
        for seed in range(n_seeds):
            snaps = snapshots(config, name, seed, steps[1:])
            per_seed.append([axis_errors_deg(snaps[int(t)], ds) for t in steps])
        errors[name] = np.array(per_seed)
    rows = ["| condition | horizontal: untrained, final | vertical: untrained, final | "
            "halved at (median over seeds): horizontal, vertical | seeds: horizontal first, "
            "vertical first, same time |", "|---|---|---|---|---|"]
    cols = 3
    rows_n = -(-len(CONDITIONS) // cols)
    fig = new_figure(4.5 * cols, 3.6 * rows_n)
    for k, name in enumerate(CONDITIONS):
        e = errors[name]
        med = np.median(e, axis=0)
        halves = np.array([[_halved(e[s, :, a], steps) for a in (0, 1)] for s in range(n_seeds)])
        h_first = int(np.sum(halves[:, 0] < halves[:, 1]))
        v_first = int(np.sum(halves[:, 1] < halves[:, 0]))
        rows.append(f"| {name} | {med[0, 0]:.1f}°, {med[-1, 0]:.1f}° | {med[0, 1]:.1f}°, "
                    f"{med[-1, 1]:.1f}° | {np.nanmedian(halves[:, 0]):,.0f}, "
                    f"{np.nanmedian(halves[:, 1]):,.0f} | {h_first}, {v_first}, "
                    f"{n_seeds - h_first - v_first} |")
        ax = fig.add_subplot(rows_n, cols, k + 1)
        for a, label in ((0, "horizontal (pan)"), (1, "vertical (tilt)")):
            ax.plot(steps, med[:, a], label=label)
            ax.fill_between(steps, *np.percentile(e[:, :, a], [25, 75], axis=0), alpha=0.2)
        ax.set(title=f"{name}: median over {n_seeds} seeds\n(band: quartiles)",
               xlabel="learning time [steps]", ylabel="error at the target [deg]")
        ax.legend()
    text = "\n".join(rows) + (f"\n\n`python docs/results/models/axes.py`: preset `models`, "
                              f"{n_seeds} seeds, snapshots every {every:,} steps, the 125 data "
                              "sets.\n")
    args.out.write_text(text)
    save_figure(fig, args.out.with_suffix(".png"))
    print(text, end="")


if __name__ == "__main__":
    main()
