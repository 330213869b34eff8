"""What each choice buys in the people world: one row per run, each one change from another.

Usage::

    python docs/results/people/ladder.py [--out docs/results/people/ladder.md]

Reads the held-out table (``held_out.md``) each run of the people world kept in
docs/results/people/ and its config's steps and seeds, and writes, per run, the unseen
caregivers' fraction of the ceiling (the mean of the seeds, and the worst seed), median error
and share of identities above 10°, with 5 and with 10 objects. Each row names the row it
changes and what it changes, and how new its unseen caregivers are (novelty). Nothing is
run: the figures are the runs' own.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from jointattention._files import write_text
from jointattention._readers import read_text

HERE = Path(__file__).resolve().parent

# (run: its folder under docs/results/people/, "" for the preset's own; its config; the run it
# changes; what it changes)
RUNS = (
    ("", "preset people", "", "the people preset: the face window only"),
    ("face_belief", "face_belief.toml", "people", "each place taught weighted by the "
     "network's belief"),
    ("window", "window.toml", "people", "a face window of 60x50 pixels"),
    ("eyes", "eyes.toml", "people", "an eye window through the fovea, placed at the eyeballs"),
    ("belief", "belief.toml", "eyes", "each place taught weighted by the network's belief"),
    ("unfound", "unfound.toml", "belief", "a line that finds nothing teaches too"),
    ("unfound_long", "unfound_long.toml", "unfound", "2x10^6 steps"),
    ("sockets", "sockets.toml", "eyes", "the window placed with an eye finder's error, "
     "patches cut at the sockets the drawn-eye bank finds"),
    ("sockets_belief", "sockets_belief.toml", "sockets", "each place taught weighted by the "
     "network's belief"),
    ("sockets_unfound", "sockets_unfound.toml", "sockets_belief", "a line that finds nothing "
     "teaches too"),
    ("sockets_unfound_long", "sockets_unfound_long.toml", "sockets_unfound", "2x10^6 steps"),
    ("sockets_net", "sockets_net.toml", "sockets_unfound_long", "the sockets found by the "
     "robot's own network"),
    ("sockets_net_h256", "sockets_net_h256.toml", "sockets_net", "256 hidden units, not 128"),
)
COLUMNS = ("unseen_fraction", "unseen_worst_seed_fraction", "unseen_median_deg",
           "unseen_share_over_10deg")


def held_out_rows(path: Path) -> dict[int, dict[str, str]]:
    """The population rows of a run's held_out.md, by object count."""
    lines = [line.strip().strip("|").split("|") for line in read_text(path, "held-out table")
             .splitlines() if line.startswith("|")]
    header = [cell.strip() for cell in lines[0]]
    rows = [dict(zip(header, (cell.strip() for cell in line), strict=True)) for line in lines[2:]]
    return {int(r["n_objects"]): r for r in rows if r["condition"].startswith("population")}


def config_of(config: str) -> tuple[int, int]:
    """A run's steps and seeds, from its config (or the preset's)."""
    from jointattention.config import load_config

    name = config.removeprefix("preset ")
    experiment = load_config(name if name != config else str(HERE / config)).experiment
    return experiment.n_steps, experiment.n_seeds


def cells(row: dict[str, str] | None) -> list[str]:
    """One object count's cells: fraction (worst seed), median error, share above 10°."""
    if row is None:
        return ["-", "-", "-"]
    return [f"{row['unseen_fraction']} ({row['unseen_worst_seed_fraction']})",
            f"{row['unseen_median_deg']}°", row["unseen_share_over_10deg"]]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="docs/results/people/ladder.md")
    args = parser.parse_args()
    rows = ["| run | changes | what | steps, seeds | 5 objects: fraction of the ceiling (worst "
            "seed) | median error | share above 10° | 10 objects: fraction of the ceiling "
            "(worst seed) | median error | share above 10° | novelty: median, max |",
            "|---|---|---|---|---|---|---|---|---|---|---|"]
    for folder, config, base, what in RUNS:
        table = held_out_rows(HERE / folder / "held_out.md")
        steps, seeds = config_of(config)
        name, some = folder or "people", next(iter(table.values()))
        novelty = f"{some['unseen_novelty_median']}, {some['unseen_novelty_max']}"
        rows.append(f"| `{name}` | {f'`{base}`' if base else '-'} | {what} | {steps / 1e6:g}x10^6, "
                    f"{seeds} | " + " | ".join(cells(table.get(5)) + cells(table.get(10)))
                    + f" | {novelty} |")
    text = "\n".join([
        *rows, "",
        "Unseen caregivers of the people world (16 from the run's held-out stream), frozen; "
        "novelty: each one's distance to the nearest training caregiver, in spacings among "
        "those (docs/generalisation.md). Each run's held_out.md is in docs/results/people/ "
        "(the people preset's: held_out.md there), and its config beside it; `python "
        "docs/results/people/ladder.py` gathers them."]) + "\n"
    print(write_text(args.out, text))
    print(text)


if __name__ == "__main__":
    main()
