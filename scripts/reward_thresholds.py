"""The oracle's ceilings that set every registered environment's ``reward_threshold``.

Usage::

    python scripts/reward_thresholds.py [--trials 100000]

Measures, for each object count of the registered ids (1, 3, 5, 10; 5 is the count of the ids
that name none), the mean return of the oracle gaze-line follower in the fast world of the
default configuration (``jointattention.experiment.cells.measure_ceiling``), for both rewards:
``external``, the share of trials it ends on the caregiver's target, and ``intrinsic``, the
share it ends on any object. Writes them to ``src/jointattention/env/reward_thresholds.json``,
which ``import jointattention.env`` reads: a spec's ``reward_threshold`` is ``fraction`` (0.9)
times its ceiling. ``tests/test_env_modes.py`` measures the ceilings again with fewer trials
and checks the file against them.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from jointattention.config import Config
from jointattention.experiment.cells import measure_ceiling

OUT = Path(__file__).resolve().parent.parent / "src/jointattention/env/reward_thresholds.json"
COUNTS = (1, 3, 5, 10)
FRACTION = 0.9  # "solved": 0.9 of what the oracle reaches


def ceilings(n_trials: int) -> dict[str, dict[str, float]]:
    """{reward: {object count: the oracle's mean return}} over ``n_trials`` trials each."""
    config = Config()
    return {reward: {str(n): round(measure_ceiling(config, n, n_trials, reward), 4)
                     for n in COUNTS} for reward in ("external", "intrinsic")}


def main() -> None:
    """Measure the ceilings and write them."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--trials", type=int, default=100_000,
                        help="oracle trials per object count and reward (default 1e5)")
    args = parser.parse_args()
    data = {"command": f"python scripts/reward_thresholds.py --trials {args.trials}",
            "n_trials": args.trials, "fraction": FRACTION, "ceiling": ceilings(args.trials)}
    OUT.write_text(json.dumps(data, indent=1) + "\n")
    print(OUT, json.dumps(data["ceiling"]))


if __name__ == "__main__":
    main()
