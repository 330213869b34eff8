"""A prototype for 10 objects: a recalled place that holds no object is not recalled again.

A data set's target is always at the same place, so when the head reaches the place the
memory recalled for a face (within a step of it) and no object is near the view's centre
(within the voting radius), that place is not the face's target. This prototype keeps such
places per face code and leaves them out of that face's recalls from then on (the place that
agrees most among the others is recalled instead; none if every one is out), and visual
attention takes the rest of that trial. Everything it uses is the robot's own: its recall,
its head angle and its detections.

It is not in the package yet: it runs the python engine, with ``MemoryModule.begin`` and
``BootstrapAgent.act`` replaced in this process, on the beyond preset's memory conditions with
the evidence gate: ``memory-evidence-floor2-n10`` and ``memory-evidence-k32-n5``, seeds 0-9,
3x10^5 steps. It prints the preset's cells of the same conditions beside
(``docs/beyond/learning_speed.csv``). With nothing left out the replaced recall is the
package's (``--check`` compares the place and the evidence at every trial's start, to 1e-9;
numpy's vectorised sums and exponentials may round otherwise than the compiled kernel's).

Run from the repository: ``python docs/beyond/eliminate.py`` (about 15 min on 2 cores); it
writes ``docs/beyond/eliminate.md``.
"""

from __future__ import annotations

import csv
import dataclasses
import json
import math
import multiprocessing
import sys
from pathlib import Path

import numpy as np

from jointattention import load_config
from jointattention.agent._recall import CODE_OF, near_slots, votes_into, weighted_kth
from jointattention.agent.memory import _cell_of, code_distances_into
from jointattention.analysis.metrics import final_success, success_by_bin, time_to_fraction
from jointattention.experiment.cells import run_cell
from jointattention.models import bootstrap, memory

HERE = Path(__file__).parent
# each condition: the preset's condition it is, and what of its gate it changes (None: as is)
CONDITIONS = {"memory-evidence-floor2-n10": ("memory-evidence-floor2-n10", None),
              "memory-evidence-k32-n5": ("memory-evidence-k32-n5", None),
              "memory-evidence-floor2-half0.1-n10": ("memory-evidence-floor2-n10",
                                                     {"half_trials": 0.1})}
SEEDS = range(10)
CHECK = "--check" in sys.argv


def recall_leaving_out(mem, code, left_out):
    """``memory_recall``'s place, support and evidence, the places near ``left_out`` left out."""
    codes, counts, links, aims, base, n_stored, n_codes = mem.kept_arrays()
    n = min(n_stored, len(aims))
    if n == 0:
        return None, -1.0, 0.0
    d2 = np.empty((1, n_codes))
    code_distances_into(code.reshape(1, -1), codes, n_codes, d2)
    d2_k = weighted_kth(d2[0], counts[:n_codes], min(mem.options.k_nearest, n))
    near = near_slots(links, counts, d2[0], d2_k, n_codes)
    weight = np.exp(-d2[0][links[CODE_OF, near]] / max(d2_k, 1e-300))
    votes = np.empty(len(near))
    votes_into(near, weight, aims, mem.radius_rad, votes)
    places, r2 = aims[near], mem.radius_rad**2
    rate = np.array([base[_cell_of(p[0], p[1], mem.lo_rad, mem.cell_rad, base.shape)]
                     for p in places])
    excess = votes - weight.sum() * rate / n
    for p in left_out:
        excess[((places - p) ** 2).sum(axis=1) < r2] = -np.inf
    if not np.isfinite(excess).any():
        return None, -1.0, 0.0
    best = int(np.argmax(excess))  # the first of equal votes, as the kernel
    agree = ((places - places[best]) ** 2).sum(axis=1) < r2
    aim = (weight[agree, None] * places[agree]).sum(axis=0) / weight[agree].sum()
    return aim, excess[best] / weight.sum(), excess[best]


def begin(self, face, theta_rad) -> None:
    """MemoryModule.begin, leaving out the face's places that held no object."""
    self._face_code = self.memory.code(face)
    left_out = self.__dict__.setdefault("left_out", {}).get(self._face_code.tobytes(), [])
    self._aim_rad, self.support_, self.evidence_ = recall_leaving_out(
        self.memory, self._face_code, left_out)
    if CHECK and not left_out:
        aim, _, evidence = self.memory.recall_evidence(self._face_code)
        assert (aim is None) == (self._aim_rad is None) and abs(evidence - self.evidence_) < 1e-9


_act = bootstrap.BootstrapAgent.act


def act(self, det, theta_rad):
    """BootstrapAgent.act; first, a recalled place reached with no object near is left out."""
    m = self.module
    aim = getattr(m, "_aim_rad", None)
    if self.learning and aim is not None and math.dist(aim, theta_rad) < self.step_rad:
        w, h = det.image_size_px
        off = np.hypot(*(det.centre_px - ((w - 1) / 2, (h - 1) / 2)).T)
        if not (off < m.memory.radius_rad / self.mechanisms.vf_gain_rad_per_px).any():
            m.left_out.setdefault(m._face_code.tobytes(), []).append(np.array(aim))
            m._aim_rad, m.support_, m.evidence_ = None, -1.0, 0.0  # the gate: rate 0
    return _act(self, det, theta_rad)


memory.MemoryModule.begin, bootstrap.BootstrapAgent.act = begin, act


def cell(job: tuple[str, int, str]) -> tuple[str, int, str, float, float]:
    """One cell: (condition, seed, engine, steps to 90%, final / ceiling).

    The python engine runs it with the elimination; the compiled engine, which does not call
    the replaced methods, without.
    """
    label, seed, engine = job
    name, gate = CONDITIONS[label]
    config = load_config("beyond")
    exp = dataclasses.replace(config.experiment, engine=engine)
    condition = next(c for c in exp.conditions if c.name == name)
    if gate is not None:
        model = condition.model
        condition = dataclasses.replace(condition, name=label,
                                        model={**model, "gate": {**model["gate"], **gate}})
    records = run_cell(dataclasses.replace(config, experiment=exp), condition, seed)
    curve = success_by_bin(records["learning_time"], records["success"], exp.bin_steps,
                           exp.n_steps)
    ends = np.arange(exp.bin_steps, exp.n_steps + 1, exp.bin_steps)
    ceiling = json.loads((HERE / "ceilings.json").read_text())[str(condition.n_objects)]
    return label, seed, engine, float(time_to_fraction(curve, ends)), final_success(curve) / ceiling


def main() -> None:
    """Run the cells on 2 processes and write the table beside the preset's."""
    jobs = [(label, seed, "python") for label in CONDITIONS for seed in SEEDS]
    jobs += [(label, seed, "compiled") for label, (_, gate) in CONDITIONS.items()
             if gate is not None for seed in SEEDS]  # the preset has no such cells
    with multiprocessing.get_context("fork").Pool(2) as pool:
        found = pool.map(cell, jobs, chunksize=1)
    with open(HERE / "learning_speed.csv", newline="") as f:
        preset = [r for r in csv.DictReader(f) if r["condition"] in CONDITIONS]
    lines = ["How the beyond preset's evidence-gate conditions learn with a recalled place "
             "that held no object left out (a prototype: `python docs/beyond/eliminate.py`), "
             "beside the same conditions without it (the preset's cells, "
             "`learning_speed.csv`, or the compiled engine's); seeds 0-9.", "",
             "| condition | elimination | steps to 90% of final (per seed, x10^4) | "
             "final / ceiling (per seed) | seeds meeting both |", "|---|---|---|---|---|"]
    for label, (_, gate) in CONDITIONS.items():
        without = ([(s, f) for n, _, e, s, f in found if n == label and e == "compiled"]
                   if gate is not None else
                   [(float(r["steps_to_90pct_of_final"]), float(r["fraction_of_ceiling"]))
                    for r in preset if r["condition"] == label])
        with_it = [(s, f) for n, _, e, s, f in found if n == label and e == "python"]
        for mark, rows in (("no", without), ("yes", with_it)):
            steps = ", ".join(f"{s / 1e4:g}" for s, _ in rows)
            finals = ", ".join(f"{f:.3f}" for _, f in rows)
            meet = sum(s <= 30_000 and f >= 0.95 for s, f in rows)
            lines.append(f"| {label} | {mark} | {steps} | {finals} | {meet} |")
    (HERE / "eliminate.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
