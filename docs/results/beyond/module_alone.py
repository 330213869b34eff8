"""How fast each learning module learns, apart from the gate that hands it control.

Issue 31 asks for 90% of the final success within 3x10^4 steps. The live success is a mix of
visual attention (chance) and the module, in the proportion the gate chooses, so it cannot be
near its final before the module it has learned so far is. This script measures how fast a
module learns from visual attention's trials alone. It learns cells of the beyond preset's
world (125 data sets, the sigmoid gate: visual attention drives until about 10^5 steps) and, at
each 10^4 steps up to 10^5, freezes a copy of the agent, sets its learning time past the
sigmoid (the gate's rate 1: the module drives every step) and measures its success on 1,000
trials of the training data sets, as a fraction of the oracle's (4,000 trials): what the module
would do if the gate handed it everything then.

Modules: the paper's network, the episodic memory (64 neighbours, the default, and 32, as in
the preset's fastest cell) and the population code (``learner = "population"``, which the
beyond preset does not run), at 5 and 10 objects, seeds 0-2.

Run from the repository: ``python docs/results/beyond/module_alone.py`` (about 100 s on one
core); it writes ``docs/results/beyond/module_alone.md`` (``--out``). ``--quick``: checkpoints at
1,000 and 2,000 steps, seed 0, 5 objects, 50 trials a measure (the tests' run).
"""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

import numpy as np

from jointattention import load_config
from jointattention.experiment.cells import datasets_of, run_cell
from jointattention.experiment.evaluate import freeze, frozen_success, oracle_success

CHECKPOINTS = tuple(range(10_000, 100_001, 10_000))
SEEDS, N_TRIALS, N_CEILING_TRIALS = (0, 1, 2), 1000, 4000
SWEEP = {"vf_fallback": "sweep"}
MODELS = {"paper": {}, "memory": {"learner": "memory", **SWEEP},
          "memory, 32 neighbours": {"learner": "memory", **SWEEP, "memory": {"k_nearest": 32}},
          "population": {"learner": "population", **SWEEP}}


def module_alone(agent, config, ds, n_objects: int, n_trials: int = N_TRIALS) -> float:
    """The frozen ``agent``'s success with the gate's rate at 1 (its learning time past it)."""
    frozen = freeze(agent)
    frozen.learning_time_steps = 100 * CHECKPOINTS[-1]  # past the sigmoid, however short the run
    assert frozen.gate_rate() > 0.999, "expected the sigmoid gate, handed over by then"
    return frozen_success(frozen, ds, config, n_objects, n_trials, config.seed)


def curve(config, model: dict, n_objects: int, seed: int, ds, checkpoints=CHECKPOINTS,
          n_trials: int = N_TRIALS) -> list[float]:
    """The module alone's success at each checkpoint of one cell (not yet over the ceiling)."""
    condition = dataclasses.replace(config.experiment.conditions[0], name="module-alone",
                                    n_objects=n_objects, model=model)
    found: dict[int, float] = {}

    def measure(t: int, agent) -> None:
        found[t] = module_alone(agent, config, ds, n_objects, n_trials)

    run_cell(config, condition, seed, checkpoints=checkpoints, on_checkpoint=measure)
    return [found[t] for t in checkpoints]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path(__file__).with_name("module_alone.md"))
    parser.add_argument("--quick", action="store_true", help="a few thousand steps, one seed")
    args = parser.parse_args()
    checkpoints, seeds, objects = CHECKPOINTS, SEEDS, (5, 10)
    n_trials, n_ceiling_trials = N_TRIALS, N_CEILING_TRIALS
    if args.quick:
        checkpoints, seeds, objects = (1_000, 2_000), (0,), (5,)
        n_trials, n_ceiling_trials = 50, 100
    beyond = load_config("beyond")
    config = dataclasses.replace(beyond, experiment=dataclasses.replace(
        beyond.experiment, n_steps=checkpoints[-1]))
    ds = datasets_of(config)
    head = " | ".join(f"{t / 10_000:g}" for t in checkpoints)
    rows = [f"| module | objects | {head} |", "|---|---|" + "---|" * len(checkpoints)]
    for n_objects in objects:
        ceiling = oracle_success(ds, config, n_objects, n_ceiling_trials, config.seed)
        for name, model in MODELS.items():
            runs = np.array([curve(config, model, n_objects, s, ds, checkpoints, n_trials)
                             for s in seeds]) / ceiling
            cells = " | ".join(f"{m:.2f} ({lo:.2f}-{hi:.2f})" for m, lo, hi in
                               zip(runs.mean(0), runs.min(0), runs.max(0), strict=True))
            rows.append(f"| {name} | {n_objects} | {cells} |")
            print(rows[-1], flush=True)
    out = args.out
    out.write_text(
        "Each learning module alone (the frozen agent with the gate's rate at 1), learned in "
        "the beyond preset's world under the sigmoid gate: its success on the training data "
        "sets as a fraction of the oracle's, at each learning time (columns, in 10^4 steps); "
        f"mean over seeds {seeds[0]}-{seeds[-1]} (lowest-highest); written by "
        "`python docs/results/beyond/module_alone.py`.\n\n" + "\n".join(rows) + "\n")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
