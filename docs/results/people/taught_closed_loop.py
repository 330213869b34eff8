"""What the eye windows allow in closed loop when the true places are taught, beside the runs.

Usage::

    python docs/results/people/taught_closed_loop.py [--passes 3]
        [--out docs/results/people/taught_closed_loop.md]

The learners of ``belief.toml`` (the eye window placed exactly, where only the experimenter
knows the eyes are) and ``sockets_belief.toml`` (patches around the sockets the robot finds in
a window misplaced by 0.1 eye distances) teach themselves from their evaluator. Here each
condition's learner (its seed 0, untrained) is taught the true place of every training face's
target instead, through its own teaching step (the population module's ``learn_places``, with
its replay), ``passes`` times over the run's training sets in a random order. With its gate
at the run's end it is then frozen and measured as the run measures its models
(:func:`~jointattention.experiment.held_out.measure_held_out`: the run's held-out sets and
trials), each success divided by that set's ceiling (the oracle's, over the run's
``n_ceiling_trials``). Beside it, the run's own result (its ``held_out.md``: the mean of its
seeds, learned with no teacher). The taught columns are what the eye reading allows; the gap
to the run's is what the teaching by the evaluator loses.
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from pathlib import Path

import numpy as np

from jointattention._files import write_text
from jointattention.config import load_config
from jointattention.experiment.cells import datasets_of, make_agent
from jointattention.experiment.evaluate import oracle_success
from jointattention.experiment.held_out import KINDS, held_out_sets, measure_held_out

HERE = Path(__file__).parent
RUNS = {  # the eye window, as the table names it: the run's configuration
    "placed exactly": "belief",
    "socket patches the robot finds": "sockets_belief",
}


def small(config, caregivers: int):
    """``config`` with ``caregivers`` training caregivers of 4 poses and tiny held-out sets."""
    held = dataclasses.replace(config.experiment.held_out, n_trials=20, n_poses=4,
                               n_caregivers=2, poses_per_caregiver=2)
    return dataclasses.replace(
        config, recording=dataclasses.replace(config.recording, caregivers=caregivers,
                                              poses_per_caregiver=4),
        experiment=dataclasses.replace(config.experiment, held_out=held, n_ceiling_trials=50))


def taught(config, condition, passes: int):
    """The condition's untrained learner of seed 0, taught each training face's true place."""
    ds = datasets_of(config)
    agent = make_agent(config, condition, 0, ds)
    views, places = ds.views, ds.theta_face_rad + ds.command_rad
    order = np.random.default_rng(0)
    for _ in range(passes):
        for k in order.permutation(len(ds)):
            agent.begin_trial(views[k], ds.theta_face_rad[k])
            agent.module.learn_places(places[k][None])
    agent.learning_time_steps = config.experiment.n_steps  # its gate as at the run's end
    return agent


def run_rows(name: str) -> dict[str, dict[str, str]]:
    """The run's own held-out table (``name/held_out.md``), by condition; {} if it is absent."""
    path = HERE / name / "held_out.md"
    if not path.exists():
        return {}
    lines = [r for r in path.read_text().splitlines() if r.startswith("| ")]
    head = [c.strip() for c in lines[0].strip("|").split("|")]
    return {cells[0]: dict(zip(head, cells, strict=True))
            for cells in ([c.strip() for c in r.strip("|").split("|")] for r in lines[1:])}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--passes", type=int, default=3,
                        help="passes of teaching over the training sets")
    parser.add_argument("--train-caregivers", type=int, default=0,
                        help="record this many training caregivers instead of the run's (a "
                             "small run: the tests')")
    parser.add_argument("--out", default=str(HERE / "taught_closed_loop.md"))
    args = parser.parse_args()
    start = time.perf_counter()
    rows = ["| eye window | objects | taught: training | taught: new poses | "
            "taught: unseen caregivers | taught: median error, unseen | run (self-taught): "
            "unseen caregivers | run: median error, unseen |", "|---|---|---|---|---|---|---|---|"]
    for window, name in RUNS.items():
        config = load_config(str(HERE / f"{name}.toml"))
        if args.train_caregivers:
            config = small(config, args.train_caregivers)
        sets, run = held_out_sets(config), run_rows(name)
        for condition in config.experiment.conditions:
            n = condition.n_objects
            measured = measure_held_out(taught(config, condition, args.passes), config, n)
            fractions = [measured[0, j] / oracle_success(sets[kind], config, n,
                                                         config.experiment.n_ceiling_trials,
                                                         config.seed)
                         for j, kind in enumerate(KINDS)]
            own = run.get(condition.name)
            theirs = (f"{own['unseen_fraction']} | {own['unseen_median_deg']}°" if own
                      else "- | -")
            rows.append(f"| {window} | {n} | " + " | ".join(f"{f:.3f}" for f in fractions)
                        + f" | {measured[1, 2]:.1f}° | {theirs} |")
    text = "\n".join([
        *rows, "",
        f"Success as a fraction of each set's ceiling. Taught: each condition's learner taught "
        f"the true places, {args.passes} passes; run: `docs/results/people/<run>/held_out.md` "
        f"(the mean of its seeds, no teacher). `python docs/results/people/"
        f"taught_closed_loop.py` ({(time.perf_counter() - start) / 60:.1f} min)."]) + "\n"
    print(write_text(args.out, text))
    print(text)


if __name__ == "__main__":
    main()
