"""Is the episodic memory a lookup? Where it steers for faces it never saw.

Usage::

    python docs/results/generalise/lookup.py [--out docs/results/generalise/lookup.md] [--quick]

Learns the beyond preset's 10-object memory cell (``memory-n10``, seed 0: 3x10^5 steps on the
125 shipped data sets of one caregiver), then recalls a place for every face of the shipped
held-out sets (new poses of that caregiver, 16 caregivers it never saw) and counts the recalled
places that lie within 2 degrees of one of the 125 training targets' places, against the share
of the held-out sets' own targets that do. A memory that recalls where it found objects for
faces like these, and nowhere else, recalls training places only: a lookup. ``--quick``:
3,000 steps (the tests' run); a face the memory recalls no place for counts as not near.
"""

from __future__ import annotations

import argparse
import dataclasses
import time

import numpy as np

from jointattention._files import write_text
from jointattention.config import condition_named, load_config
from jointattention.datasets import default_datasets
from jointattention.experiment.cells import run_cell
from jointattention.experiment.held_out import shipped_held_out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="docs/results/generalise/lookup.md")
    parser.add_argument("--quick", action="store_true", help="3,000 steps (the tests' run)")
    args = parser.parse_args()
    start = time.perf_counter()
    config = load_config("beyond")
    if args.quick:
        config = dataclasses.replace(config, experiment=dataclasses.replace(
            config.experiment, n_steps=3_000))
    learned = []
    run_cell(config, condition_named(config, "memory-n10"), 0,
             checkpoints=[config.experiment.n_steps],
             on_checkpoint=lambda t, agent: learned.append(agent))
    memory, train = learned[-1].module.memory, default_datasets()
    places = train.theta_face_rad + train.command_rad  # the training targets' places
    rows = ["| faces | data sets | recalled places within 2° of a training place | their own "
            "targets within 2° of a training place |", "|---|---|---|---|"]
    for name, ds in (("training", train), ("new poses", shipped_held_out("new poses")),
                     ("unseen caregivers", shipped_held_out("unseen caregivers"))):
        recalled = np.array([np.full(2, np.nan) if aim is None else aim for aim in
                             (memory.recall(memory.code(f))[0] for f in ds.face)])
        own = ds.theta_face_rad + ds.command_rad

        def near(p):
            d = np.linalg.norm(p[:, None] - places[None], axis=2).min(axis=1)
            return float(np.mean(np.rad2deg(d) <= 2.0))

        rows.append(f"| {name} | {len(ds)} | {near(recalled):.2f} | {near(own):.2f} |")
    text = "\n".join(rows) + (f"\n\n`python docs/results/generalise/lookup.py` "
                              f"({(time.perf_counter() - start) / 60:.1f} min).\n")
    print(write_text(args.out, text))
    print(text)


if __name__ == "__main__":
    main()
