"""How long recording the people world's caregivers takes: the preset's training sets.

Usage::

    python docs/results/people/record.py [--caregivers 256] [--poses 64]
        [--out docs/results/people/recording.md]

Records ``caregivers`` x ``poses`` data sets of the ``people`` preset from world seed 1 (what
``jointattention datasets make --config people --n 16384 --caregivers 256 --seed 1`` records,
with its progress bar), and writes the wall time and the rate.
"""

from __future__ import annotations

import argparse
import os
import time

from tqdm import tqdm

from jointattention._files import write_text
from jointattention.config import load_config
from jointattention.world.recording import make_datasets


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--caregivers", type=int, default=256)
    parser.add_argument("--poses", type=int, default=64)
    parser.add_argument("--out", default="docs/results/people/recording.md")
    args = parser.parse_args()
    n, world = args.caregivers * args.poses, load_config("people").world
    start = time.perf_counter()
    with tqdm(total=n, desc="recording", unit="set") as bar:
        make_datasets(world, n, 1, lambda i: bar.update(1), caregivers=args.caregivers)
    minutes = (time.perf_counter() - start) / 60
    text = (f"it recorded {n:,} data sets of {args.caregivers} caregivers in {minutes:.1f} min "
            f"({n / minutes / 60:.0f} sets/s, {os.cpu_count()} cores; `python "
            "docs/results/people/record.py`).\n")
    print(write_text(args.out, text))
    print(text)


if __name__ == "__main__":
    main()
