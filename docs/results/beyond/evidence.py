"""What holds 10 objects back from learning fast: the places the memory holds, or the gate?

The evidence gate (``gate = { kind = "evidence" }``) hands a face to the memory once the memory
has evidence for the face's place. Two things must go right early: the memory must hold the
right place for most faces, and the evidence must tell a right place from a wrong one. This
script learns cells of the beyond preset (its world, 3x10^5 steps) and, at 1, 2, 3 and 5x10^4
steps, recalls each of the 125 data sets' faces. Per checkpoint it prints:

- the share of faces whose recalled place lies within 3° of their target (right);
- how well the evidence ranks right places above wrong ones: the probability that a right
  face's evidence exceeds a wrong face's (the area under the ROC curve; 0.5 is chance).

The ``memory-n10`` cell (the sigmoid gate: visual attention drives until about 10^5 steps)
shows what the memory learns from visual attention's trials alone; the ``memory-evidence``
cells, what it learns when the evidence gate hands faces over.

Run from the repository: ``python docs/results/beyond/evidence.py`` (about 30 s); it writes
``docs/results/beyond/evidence.md`` (``--out``). ``--quick``: 3,000 steps, checkpoints at 1,000 and
2,000 (the tests' run).
"""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

import numpy as np

from jointattention import load_config
from jointattention.experiment.cells import datasets_of
from jointattention.jobs.learned import snapshots

CHECKPOINTS, RIGHT_DEG = (10_000, 20_000, 30_000, 50_000), 3.0
CELLS = (("memory-n10", 0), ("memory-evidence-n10", 0), ("memory-evidence-n10", 3),
         ("memory-evidence-k32-n5", 0))


def auc(right: np.ndarray, wrong: np.ndarray) -> float:
    """P(a right face's value > a wrong face's), ties counting half; NaN if either is empty."""
    if not len(right) or not len(wrong):
        return float("nan")
    above = right[:, None] > wrong[None, :]
    return float(np.mean(above) + 0.5 * np.mean(right[:, None] == wrong[None, :]))


def rows_of(config, name: str, seed: int, checkpoints=CHECKPOINTS) -> list[str]:
    """One table row per checkpoint of one cell."""
    ds = datasets_of(config)
    targets = ds.theta_face_rad + ds.command_rad
    rows = []
    for t, agent in sorted(snapshots(config, name, seed, checkpoints).items()):
        if t not in checkpoints:
            continue
        memory, error, evidence = agent.module.memory, [], []
        for face, target in zip(ds.face, targets, strict=True):
            aim, _, e = memory.recall_evidence(memory.code(face.ravel()))
            error.append(np.inf if aim is None else np.degrees(np.linalg.norm(aim - target)))
            evidence.append(e)
        error, evidence = np.array(error), np.array(evidence)
        right = error < RIGHT_DEG
        rows.append(f"| {name} | {seed} | {t:,} | {right.mean():.2f} | "
                    f"{auc(evidence[right], evidence[~right]):.2f} | "
                    f"{np.median(evidence[right]) if right.any() else np.nan:.1f} | "
                    f"{np.median(evidence[~right]) if (~right).any() else np.nan:.1f} |")
        print(rows[-1], flush=True)
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path(__file__).with_name("evidence.md"))
    parser.add_argument("--quick", action="store_true", help="3,000 steps (the tests' run)")
    args = parser.parse_args()
    config, checkpoints = load_config("beyond"), CHECKPOINTS
    if args.quick:
        config = dataclasses.replace(config, experiment=dataclasses.replace(
            config.experiment, n_steps=3_000))
        checkpoints = (1_000, 2_000)
    rows = ["| cell | seed | learning time (steps) | faces right | evidence AUC | "
            "evidence, right (median) | evidence, wrong (median) |",
            "|---|---|---|---|---|---|---|"]
    for name, seed in CELLS:
        rows += rows_of(config, name, seed, checkpoints)
    out = args.out
    out.write_text(
        "The memory's recalled place for each of the 125 data sets' faces (right: within "
        f"{RIGHT_DEG:.0f}° of the target) and how well its evidence ranks right places above "
        "wrong ones, in cells of the beyond preset; written by "
        "`python docs/results/beyond/evidence.py`.\n\n" + "\n".join(rows) + "\n")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
