"""How new each preset's unseen caregivers are to the caregivers its models learn from.

Usage::

    python docs/results/people/novelty.py [--out docs/results/people/novelty.md] [PRESET ...]

For each preset (default: generalise, people), the run's held-out sets
(:func:`jointattention.experiment.held_out.held_out_novelty`, recorded once and kept in the
cache): each new-poses and unseen caregiver's distance to the nearest training caregiver,
over the spacing among those (:mod:`jointattention.world.novelty`; 0 for a caregiver it
learned from), the median and the largest.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from jointattention._files import write_text
from jointattention.config import load_config
from jointattention.experiment.held_out import held_out_novelty


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("presets", nargs="*", default=["generalise", "people"])
    parser.add_argument("--out", default="docs/results/people/novelty.md")
    args = parser.parse_args()
    start = time.perf_counter()
    rows = ["| preset | held-out sets | caregivers | novelty, median | largest |",
            "|---|---|---|---|---|"]
    for preset in args.presets:
        for kind, new in held_out_novelty(load_config(preset)).items():
            rows.append(f"| {preset} | {kind} | {len(new)} | {np.median(new):.2f} | "
                        f"{np.max(new):.2f} |")
    text = "\n".join([*rows, "", "`python docs/results/people/novelty.py "
                      f"{' '.join(args.presets)}` "
                      f"({(time.perf_counter() - start) / 60:.1f} min)."]) + "\n"
    print(write_text(args.out, text))
    print(text)


if __name__ == "__main__":
    main()
