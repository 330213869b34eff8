"""The learning modules' error over learning time, horizontal against vertical, from a run.

Reads a ``models`` run folder's ``diagnostics.csv`` (means over seeds per 10,000-step bin: the
learning module's median angle error at the data sets' faces and its horizontal and vertical
parts, ``experiment.probes.axis_errors_deg``) and writes ``docs/results/models/errors.md``: for each
condition with a learning module, the three errors at a few learning times, and the area under
the angle error (its mean over the bins: lower is faster).

Run from the repository after ``jointattention reproduce --preset models --out runs/models``:
``python docs/results/models/errors.py runs/models`` (a second). ``--out`` writes the table
elsewhere; ``--times`` names other learning times (the tests' short run).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from jointattention.analysis.tables import read_csv

TIMES = (30_000, 60_000, 120_000, 150_000, 300_000)
OUT = Path(__file__).parent


def main(run: Path, out: Path = OUT / "errors.md", times: tuple[int, ...] = TIMES) -> None:
    """Write errors.md from ``run``'s diagnostics."""
    table = read_csv(run / "diagnostics.csv")
    col = {name: i for i, name in enumerate(table.columns)}
    by_condition: dict[str, list] = {}
    for row in table.rows:
        by_condition.setdefault(row[col["condition"]], []).append(row)
    head = ", ".join(f"{t // 1000}k" for t in times)
    rows = [f"| condition | mean angle error over learning time | angle error at {head} | "
            f"horizontal at {head} | vertical at {head} |", "|---|---|---|---|---|"]
    for name, cond_rows in by_condition.items():
        ends = np.array([float(r[col["bin_end_steps"]]) for r in cond_rows])

        def series(metric, cond_rows=cond_rows):
            return np.array([float(r[col[metric]]) for r in cond_rows])

        error = series("lm_error_deg")
        if "shuffled" in name or not np.isfinite(error).all():
            continue
        at = [int(np.searchsorted(ends, t)) for t in times]

        def cells(values, at=at):
            return ", ".join(f"{values[i]:.1f}" for i in at)

        rows.append(f"| {name} | {error.mean():.1f}° | {cells(error)} | "
                    f"{cells(series('lm_pan_error_deg'))} | "
                    f"{cells(series('lm_tilt_error_deg'))} |")
    text = "\n".join(rows) + (f"\n\n`python docs/results/models/errors.py {run}`: degrees, "
                              "means over seeds of each bin's median over the 125 data sets.\n")
    out.write_text(text)
    print(text, end="")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", nargs="?", type=Path, default=Path("runs/models"))
    parser.add_argument("--out", type=Path, default=OUT / "errors.md")
    parser.add_argument("--times", type=int, nargs="+", default=list(TIMES),
                        help="learning times of the columns, in steps (default: "
                             f"{' '.join(map(str, TIMES))})")
    args = parser.parse_args()
    main(args.run, args.out, tuple(args.times))
