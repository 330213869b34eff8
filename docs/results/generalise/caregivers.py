"""Generalisation against the number of training caregivers K: one table from the runs.

Usage::

    python docs/results/generalise/caregivers.py [--sweep runs/generalise-k]
        [--run runs/generalise-64 --run runs/generalise]
        [--out docs/results/generalise/caregivers.md]

Reads the sweep of ``docs/results/generalise/caregivers.toml`` (K = 1 and 16) and the generalise
preset's runs (K = 128; K = 64 is the preset as it was at commit 60325f6, run into
``runs/generalise-64``), measures each point's held-out ceilings where its folder has none (the
oracle on its training sets, new poses and unseen caregivers; kept in the folder's
``held_out_ceilings.json``), and writes, per model and K, the frozen success on each kind of
data set as a fraction of its ceiling and the median angle error on unseen caregivers (means
over seeds).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from jointattention._files import write_text
from jointattention.analysis.held_out import held_out_curves, held_out_table
from jointattention.config import load_config
from jointattention.jobs.reproduce import held_out_ceilings


def _rows(folder: Path) -> tuple[int, dict[str, dict]]:
    config = load_config(folder / "config.toml")
    ceilings = held_out_ceilings(config, folder / "held_out_ceilings.json")
    table = held_out_table(config, held_out_curves(folder, config), ceilings)
    return config.recording.caregivers, {r[0]: dict(zip(table.columns, r, strict=True))
                                          for r in table.rows}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sweep", default="runs/generalise-k", type=Path)
    parser.add_argument("--run", action="append", type=Path,
                        help="a generalise run folder (repeatable; default: runs/generalise-64 "
                             "and runs/generalise)")
    parser.add_argument("--out", default="docs/results/generalise/caregivers.md")
    args = parser.parse_args()
    runs = args.run or [Path("runs/generalise-64"), Path("runs/generalise")]
    folders = sorted(p.parent for p in args.sweep.glob("*/config.toml")) + runs
    by_k = dict(_rows(f) for f in folders)
    lines = ["| model | objects | K | training sets | new poses | unseen caregivers | error, "
             "unseen | identities above 10° |", "|---|---|---|---|---|---|---|---|"]
    names = list(by_k[min(by_k)])
    for name in names:
        for k in sorted(by_k):
            r = by_k[k].get(name)
            if r is None:
                continue
            lines.append(f"| {name} | {r['n_objects']} | {k} | {r['training_fraction']:.3f} | "
                         f"{r['new_poses_fraction']:.3f} | {r['unseen_fraction']:.3f} | "
                         f"{r['unseen_median_deg']}° | {r['unseen_share_over_10deg']:.2f} |")
    text = "\n".join(lines) + ("\n\nSuccess of the frozen model as a fraction of each set's "
                               "oracle ceiling, means over 3 seeds; `python "
                               "docs/results/generalise/caregivers.py`.\n")
    print(write_text(args.out, text))
    print(text)


if __name__ == "__main__":
    main()
