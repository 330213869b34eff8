"""Learning speed per condition: the beyond preset's per-seed table, summed up.

Reads ``docs/results/beyond/learning_speed.csv`` (a row per condition and seed, written by
``jointattention reproduce --preset beyond``) and writes, for the conditions that *Beyond the
paper* compares, the range and mean over the seeds of the steps to 90% of the seed's own final
success and of that final as a fraction of the ceiling, and how many seeds meet each half of
the issue's target (90% of the final within ``TARGET_STEPS`` steps, a final of at least
``TARGET_FRACTION`` of the ceiling) and both. One table per group of conditions, each between
snippet markers (``--8<-- [start:group]``) so that the page includes it where it belongs.

Run from the repository: ``python docs/results/beyond/speed_summary.py`` (under a second); it
writes ``docs/results/beyond/speed_summary.md`` (``--out``; ``--csv`` for another run's table).
"""

from __future__ import annotations

import argparse
import csv
import math
from pathlib import Path

from jointattention.analysis.learning_speed import TARGET_FRACTION, TARGET_STEPS

HERE = Path(__file__).parent
# {group: conditions}, in the order the page compares them.
GROUPS = {
    "gates": ("memory-n5", "memory-perf-n5", "memory-perf-w1000-n5", "memory-evidence-n5",
              "memory-evidence-k32-n5", "memory-n10", "memory-perf-n10", "memory-perf-w1000-n10",
              "memory-evidence-n10", "memory-evidence-floor2-n10"),
    "leave": ("memory-evidence-quick-n5", "memory-evidence-quick-leave-n5",
              "memory-evidence-quick-n10", "memory-evidence-quick-leave-n10"),
    "pass": ("memory-evidence-quick-leave-n5", "memory-evidence-quick-pass-n5",
             "memory-evidence-quick-leave-n10", "memory-evidence-quick-pass-n10"),
    "saccade": ("memory-evidence-quick-pass-n5", "memory-evidence-quick-saccade-n5",
                "memory-evidence-quick-pass-n10", "memory-evidence-quick-saccade-n10"),
}


def _range(values: list[float], ends: str, mean: str) -> str:
    """'low-high (mean)' of the values that are numbers, or the one value if all are equal."""
    finite = [v for v in values if not math.isnan(v)]
    if not finite:
        return "never"
    low, high, average = min(finite), max(finite), sum(finite) / len(finite)
    text = (format(low, ends) if low == high
            else f"{low:{ends}}-{high:{ends}} ({average:{mean}})")
    never = len(values) - len(finite)
    return text + (f"; never: {never}" if never else "")


def summary_rows(rows: list[dict], conditions: tuple[str, ...]) -> list[str]:
    """A Markdown row per condition: seeds, steps to 90%, final / ceiling, seeds meeting."""
    out = []
    for name in conditions:
        seeds = [r for r in rows if r["condition"] == name]
        if not seeds:
            raise SystemExit(f"no seeds of {name} in the table")
        steps = [float(r["steps_to_90pct_of_final"]) for r in seeds]
        fraction = [float(r["fraction_of_ceiling"]) for r in seeds]
        fast = [s <= TARGET_STEPS for s in steps]  # NaN (never) compares False
        well = [f >= TARGET_FRACTION for f in fraction]
        both = sum(a and b for a, b in zip(fast, well, strict=True))
        out.append(f"| {name} | {len(seeds)} | {_range([s / 1e4 for s in steps], 'g', '.1f')} | "
                   f"{_range(fraction, '.3f', '.3f')} | {sum(fast)} | {sum(well)} | {both} |")
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--csv", type=Path, default=HERE / "learning_speed.csv")
    parser.add_argument("--out", type=Path, default=HERE / "speed_summary.md")
    args = parser.parse_args()
    with open(args.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    header = ("| condition | seeds | steps to 90% of final, x10^4: range (mean) "
              "| final / ceiling: range (mean) "
              f"| seeds at 90% by {TARGET_STEPS / 1e4:g}x10^4 "
              f"| seeds at {TARGET_FRACTION:g} of the ceiling | seeds meeting both |")
    lines = []
    for group, conditions in GROUPS.items():
        lines += [f"<!-- --8<-- [start:{group}] -->", header, "|---|---|---|---|---|---|---|",
                  *summary_rows(rows, conditions), f"<!-- --8<-- [end:{group}] -->", ""]
    args.out.write_text("\n".join(lines).rstrip() + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
