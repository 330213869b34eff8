"""Steps and trials to 90% of the final: the saccading memory against the stepping one.

Reads the trials of ``jointattention sweep docs/results/beyond/saccade.toml --out
runs/beyond-saccade`` (then ``jointattention reproduce --config
runs/beyond-saccade/seed=0/config.toml --out runs/beyond-saccade/seed=0 --trials-csv``, which
writes ``trials.csv``) and prints, per condition, the trials a trial takes in steps over the
first 3x10^4 steps, how many trials fit in them, and the trials to 90% of the final: the first
window of 500 trials (windows every 250) whose success reaches 90% of that of the seed's last
3,000 trials. Means over the seeds, and the range.

Run from the repository: ``python docs/results/beyond/saccade_trials.py [trials.csv]`` (a few
seconds).
"""

from __future__ import annotations

import csv
import sys
from collections import defaultdict

EARLY_STEPS, WINDOW, STRIDE, FINAL = 30_000, 500, 250, 3_000


def _trials_to_90(success: list[int]) -> int:
    final = sum(success[-FINAL:]) / len(success[-FINAL:])
    for start in range(0, len(success), STRIDE):
        window = success[start:start + WINDOW]
        if sum(window) / len(window) >= 0.9 * final:
            return start + WINDOW
    return len(success)


def main(path: str = "runs/beyond-saccade/seed=0/trials.csv") -> None:
    cells = defaultdict(list)
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            cells[row["condition"], int(row["seed"])].append(row)
    by = defaultdict(list)
    for (condition, _), rows in cells.items():
        early = [r for r in rows if int(r["learning_time"]) < EARLY_STEPS]
        steps = sum(int(r["n_steps"]) for r in early) / len(early)
        by[condition].append((steps, len(early), _trials_to_90([int(r["success"]) for r in rows])))
    print("| condition | steps a trial (first 3x10^4 steps) | trials in them | "
          "trials to 90% of the final (mean; range) |")
    print("|---|---|---|---|")
    for condition, seeds in sorted(by.items()):
        n, to_90 = len(seeds), [s[2] for s in seeds]
        print(f"| {condition} | {sum(s[0] for s in seeds) / n:.2f} | "
              f"{sum(s[1] for s in seeds) / n:,.0f} | "
              f"{sum(to_90) / n:,.0f}; {min(to_90):,}-{max(to_90):,} |")


if __name__ == "__main__":
    main(*sys.argv[1:])
