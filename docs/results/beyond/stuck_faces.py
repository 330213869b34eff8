"""Faces whose target the memory never finds with 10 objects, with and without passing over.

With a place found empty left out (``memory.leave_out_empty``), most 10-object cells of the
beyond preset end near the ceiling, but a few faces stay wrong to the end. This script learns
the preset's ``memory-evidence-quick-leave-n10`` and ``memory-evidence-quick-pass-n10`` cells
(3x10^5 steps) for each seed given, and lists, per cell, the data sets whose final recall is
farther than the voting radius (2 degrees) from their target: how many places the memory kept
for the face, how many of them lie within the radius of the target, and how many places it
left out of the face's recalls. A face with no kept place near its target was never followed
there: visual attention always found a distractor first.

Run from the repository: ``python docs/results/beyond/stuck_faces.py [seeds...]`` (default: 7 and 2;
about 10 s a cell); it writes ``docs/results/beyond/stuck_faces.md`` (``--out``). ``--quick``: 3,000
steps a cell (the tests' run).
"""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

import numpy as np

from jointattention import load_config
from jointattention.experiment.cells import datasets_of, run_cell
from jointattention.models.memory._recall import CODE_OF

CONDITIONS = ("memory-evidence-quick-leave-n10", "memory-evidence-quick-pass-n10")


def stuck_faces(config, name: str, seed: int) -> list[tuple[int, float, int, int, int]]:
    """(data set, recall's error in degrees, places kept, of them near the target, left out)."""
    condition = next(c for c in config.experiment.conditions if c.name == name)
    ended = []
    run_cell(config, condition, seed, checkpoints=[config.experiment.n_steps],
             on_checkpoint=lambda t, agent: ended.append(agent))
    memory, ds = ended[-1].module.memory, datasets_of(config)
    faces, targets = ds.face.reshape(len(ds), -1).astype(float), ds.theta_face_rad + ds.command_rad
    n_kept = min(memory.n_stored_, len(memory.aims_))
    codes, out = memory.codes_[:, : memory.n_codes_], []
    for k in range(len(ds)):
        code = memory.code(faces[k])
        aim, _ = memory.recall(code)
        error = np.inf if aim is None else float(np.hypot(*(aim - targets[k])))
        if error < memory.radius_rad:
            continue
        own = int(np.argmin(((codes - code[:, None]) ** 2).sum(axis=0)))  # the face's code
        places = memory.aims_[:n_kept][memory.links_[CODE_OF, :n_kept] == own]
        near = int((np.hypot(*(places - targets[k]).T) < memory.radius_rad).sum())
        out.append((k, float(np.degrees(error)), len(places), near, len(memory.left_out(code))))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("seeds", nargs="*", type=int, default=[7, 2])
    parser.add_argument("--out", type=Path, default=Path(__file__).with_name("stuck_faces.md"))
    parser.add_argument("--quick", action="store_true", help="3,000 steps (the tests' run)")
    args = parser.parse_args()
    seeds, config = args.seeds, load_config("beyond")
    if args.quick:
        config = dataclasses.replace(config, experiment=dataclasses.replace(
            config.experiment, n_steps=3_000))
    lines = ["| condition | seed | data set | recall's error (deg) | places kept for the face "
             "| near its target | places left out |", "|---|---|---|---|---|---|---|"]
    for seed in seeds:
        for name in CONDITIONS:
            rows = stuck_faces(config, name, seed)
            lines += [f"| {name} | {seed} | {k} | {e:.1f} | {n} | {near} | {left} |"
                      for k, e, n, near, left in rows] or [f"| {name} | {seed} | none | | | | |"]
            print(name, seed, len(rows), "faces", flush=True)
    args.out.write_text("\n".join(lines) + "\n")
    print("wrote", args.out)


if __name__ == "__main__":
    main()
