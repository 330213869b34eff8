"""Why a squared-error learner cannot follow gaze among 10 objects, and what can.

The robot learns only from the trials its evaluator ends; with n objects the caregiver's
target is one place among those. This script lets the visual controller alone run 3x10^5 steps
(constant gate 0, the paper preset's world), keeping every self-evaluated trial in an episodic
memory of ample capacity. Then, per data set (face), it compares the two best answers the
trials allow, at the caregiver's face:

- the mean of the taught unit directions: what a squared-error learner converges to, however
  good its optimiser (the paper's learning module is one);
- the mode of the places found: where the trials agree.

Run from the repository: ``python docs/results/beyond/mean_vs_mode.py`` (15 s); it writes
``docs/results/beyond/mean_vs_mode.md`` and ``mean_vs_mode.png`` (the errors per data set; ``--out
FILE.md`` writes them elsewhere). ``--quick``: 3,000 steps (the tests' run).
"""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

import numpy as np

from jointattention import load_config, run_cell
from jointattention.experiment.cells import datasets_of
from jointattention.experiment.probes import angle_deg
from jointattention.figures._save import new_figure, save_figure

STEPS, RADIUS_RAD = 300_000, np.radians(2.0)


def memory_of(n_objects: int, steps: int = STEPS):
    """The memory of a visual-controller-only cell: every trial the evaluator ended."""
    config = load_config("paper")
    model = {"learner": "memory", "gate": {"kind": "constant", "rate": 0.0},
             "memory": {"capacity": 200_000, "keep": "attended"}}
    condition = dataclasses.replace(config.experiment.conditions[0], n_objects=n_objects,
                                    name=f"n{n_objects}", model=model)
    config = dataclasses.replace(config, experiment=dataclasses.replace(
        config.experiment, n_steps=steps, conditions=(condition,)))
    kept = {}
    run_cell(config, condition, 0, checkpoints=[steps - 1],
             on_checkpoint=lambda t, agent: kept.setdefault("memory", agent.module.memory))
    return config, kept["memory"]


def errors(n_objects: int, steps: int = STEPS) -> tuple[int, float, np.ndarray, np.ndarray]:
    """Trials kept, share on target, per data set the error of the mean and of the mode (deg)."""
    config, memory = memory_of(n_objects, steps)
    ds = datasets_of(config)
    n = memory.n_stored_
    codes, places = memory.codes_[:, memory.links_[0, :n]].T, memory.aims_[:n]  # per trial
    targets = ds.theta_face_rad + ds.command_rad
    mean_err, mode_err, on_target = [], [], 0
    for k in range(len(ds)):
        mine = places[np.all(codes == memory.code(ds.face[k]), axis=1)]
        if len(mine) == 0:
            continue
        on_target += int((np.linalg.norm(mine - targets[k], axis=1) < RADIUS_RAD).sum())
        steps = mine - ds.theta_face_rad[k]
        units = steps / np.linalg.norm(steps, axis=1, keepdims=True)
        mean_err.append(angle_deg(units.mean(axis=0), ds.command_rad[k]))
        near = np.linalg.norm(mine[:, None] - mine[None], axis=2) < RADIUS_RAD
        mode = mine[near[np.argmax(near.sum(axis=1))]].mean(axis=0)
        mode_err.append(angle_deg(mode - ds.theta_face_rad[k], ds.command_rad[k]))
    return n, on_target / n, np.array(mean_err), np.array(mode_err)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path(__file__).with_suffix(".md"),
                        help="the table (.md); the figure goes beside it (.png)")
    parser.add_argument("--quick", action="store_true", help="3,000 steps (the tests' run)")
    args = parser.parse_args()
    steps = 3_000 if args.quick else STEPS
    rows = ["| objects | trials kept | on the target | mean of the taught directions | "
            "mode of the places found |", "|---|---|---|---|---|"]
    fig = new_figure(12.0, 3.4)
    for ax, n_objects in zip(fig.subplots(1, 3), (3, 5, 10), strict=True):
        n, share, mean, mode = errors(n_objects, steps)
        rows.append(f"| {n_objects} | {n:,} | {share:.2f} | {np.median(mean):.1f}° | "
                    f"{np.median(mode):.1f}° |")
        print(rows[-1], flush=True)
        bins = np.linspace(0, 180, 37)
        ax.hist(mean, bins, alpha=0.6, label="mean of the taught directions (squared error)")
        ax.hist(mode, bins, alpha=0.6, label="mode of the places found")
        ax.set_title(f"{n_objects} objects: {share:.2f} of the trials on the target", fontsize=9)
        ax.set_xlabel("angle error at the caregiver's face [deg]")
        ax.set_ylabel("data sets")
    ax.legend(fontsize=7)
    save_figure(fig, args.out.with_suffix(".png"))
    args.out.write_text("Median angle error at the caregiver's face over the 125 data sets, "
                        f"after {steps:,} steps of the visual controller alone (seed 0); "
                        "written by `python docs/results/beyond/mean_vs_mode.py`.\n\n"
                        + "\n".join(rows) + "\n")


if __name__ == "__main__":
    main()
