"""How fast and how well, per sweep point and condition: one table from a sweep's folders.

Usage::

    python docs/results/learn-fast/summarise.py SWEEP_FOLDER
        [--out docs/results/learn-fast/ablation.md] [--ceilings]

Reads each point of a sweep (``jointattention sweep``: one run folder per point), measures its
ceilings where the folder has none (the oracle on the training sets and on the held-out sets,
kept in the folder's ``ceilings.json`` and ``held_out_ceilings.json``), and writes per point and
condition:

- the learning time at which each seed's success first reaches 90% of its own final success
  (mean over seeds and the slowest seed), also in minutes of a real head making
  ``experiment.head_moves_per_s`` moves a second;
- the final success while learning, as a fraction of the training sets' ceiling;
- the frozen model at the end on caregivers it never saw: success as a fraction of their
  ceiling (mean and worst seed), median angle error, the share of those caregivers whose median
  error is above 10°, and how new they are (the median novelty of ``held_out.md``).

With ``--ceilings``, also the unseen caregivers' success itself and their ceiling: where the
points move differently (``agent.line_capture_deg``), the oracle moves so too, and each
point's ceiling is its own.
"""

from __future__ import annotations

import argparse
import math
import re
from pathlib import Path

import numpy as np

from jointattention._files import write_text
from jointattention.analysis.curves import condition_curves
from jointattention.analysis.held_out import held_out_curves, held_out_table
from jointattention.analysis.metrics import final_success, time_to_fraction
from jointattention.config import load_config
from jointattention.errors import JointAttentionError
from jointattention.experiment.held_out import held_out_novelty
from jointattention.jobs.reproduce import held_out_ceilings, run_ceilings

HEADER = ("| point | condition | objects | steps to 90% of final, mean (slowest seed) | minutes "
          "of a real head | final / ceiling | unseen caregivers / ceiling, mean (worst seed) | "
          "median error, unseen | unseen identities above 10° | novelty of the unseen |")


def _number(value) -> str:
    """A table cell: the value, or '-' where there is none (None or NaN)."""
    return "-" if value is None or (isinstance(value, float) and math.isnan(value)) else str(value)


def _natural(folder: Path) -> list:
    """Sort key of a point's folder name, its numbers as numbers (caregivers=4 before =16)."""
    return [float(t) if t[:1].isdigit() else t for t in re.split(r"(\d+(?:\.\d+)?)", folder.name)]


CEILING_COLUMNS = " unseen caregivers' success | their ceiling |"


def point_rows(folder: Path, ceilings_too: bool = False) -> list[str]:
    """The table's rows for one sweep point's run folder (``ceilings_too``: CEILING_COLUMNS)."""
    config = load_config(folder / "config.toml")
    ceilings = run_ceilings(config, folder / "ceilings.json")
    held_ceilings = held_out_ceilings(config, folder / "held_out_ceilings.json")
    held = held_out_table(config, held_out_curves(folder, config), held_ceilings,
                          held_out_novelty(config))
    unseen = {r[0]: dict(zip(held.columns, r, strict=True)) for r in held.rows}
    rows = []
    for name, (ends, per_seed) in condition_curves(folder, config).items():
        n = next(c.n_objects for c in config.experiment.conditions if c.name == name)
        steps = np.array([time_to_fraction(curve, ends) for curve in per_seed])
        final = np.mean([final_success(curve) for curve in per_seed]) / ceilings[str(n)]
        minutes = np.mean(steps) / config.experiment.head_moves_per_s / 60
        u = unseen.get(name, {})
        rows.append(f"| {folder.name} | {name} | {n} | {np.mean(steps):,.0f} ({np.max(steps):,.0f})"
                    f" | {minutes:.0f} | {final:.3f} | {u.get('unseen_fraction', '-')} "
                    f"({u.get('unseen_worst_seed_fraction', '-')}) | "
                    f"{u.get('unseen_median_deg', '-')}° | "
                    f"{u.get('unseen_share_over_10deg', '-')} | "
                    f"{_number(u.get('unseen_novelty_median'))} |"
                    + (_ceiling_cells(u, held_ceilings, n) if ceilings_too else ""))
    return rows


def _ceiling_cells(unseen: dict, held_ceilings: dict, n_objects: int) -> str:
    """The unseen caregivers' success (their fraction times their ceiling) and the ceiling."""
    ceiling = held_ceilings["unseen caregivers"][str(n_objects)]
    fraction = unseen.get("unseen_fraction")
    success = "-" if fraction is None else f"{float(fraction) * ceiling:.3f}"
    return f" {success} | {ceiling:.3f} |"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sweep", type=Path, help="the sweep's output folder")
    parser.add_argument("--out", default="docs/results/learn-fast/ablation.md")
    parser.add_argument("--ceilings", action="store_true",
                        help="add the unseen caregivers' success and their ceiling")
    args = parser.parse_args()
    folders = sorted((p.parent for p in args.sweep.glob("*/config.toml")), key=_natural)
    if not folders:
        parser.error(f"{args.sweep}: no sweep point (a folder with config.toml) in it; expected "
                     "the --out folder of `jointattention sweep`")
    config = load_config(folders[0] / "config.toml")
    lines = [HEADER + CEILING_COLUMNS * args.ceilings, "|---" * (10 + 2 * args.ceilings) + "|"]
    for folder in folders:
        try:
            lines += point_rows(folder, args.ceilings)
        except JointAttentionError as err:  # a point not finished, or not a run folder
            parser.error(f"{err} (`jointattention sweep` on its spec finishes a sweep that "
                         "stopped)")
    lines += ["", f"({config.experiment.n_seeds} seeds per point; bins of "
              f"{config.experiment.bin_steps:,} steps; minutes at "
              f"{config.experiment.head_moves_per_s:g} moves a second; novelty: the median "
              "distance of the unseen caregivers to the nearest training caregiver, in spacings "
              "of the training caregivers (-: one caregiver has no spacing). Written by `python "
              f"docs/results/learn-fast/summarise.py {args.sweep} --out {args.out}"
              f"{' --ceilings' * args.ceilings}`.)"]
    text = "\n".join(lines) + "\n"
    print(write_text(args.out, text))
    print(text)


if __name__ == "__main__":
    main()
