"""The compiled engine against the step-by-step (python) engine on whole paper-scale runs.

Run first (the python engine takes about 20 min on 2 cores, the compiled one 1 min):
    jointattention reproduce --preset paper --out runs/paper
    jointattention config --config paper | sed 's/^engine = .*/engine = "python"/' > paper-py.toml
    jointattention reproduce --config paper-py.toml --out runs/paper-python
then:
    python docs/results/engines/compare_engines.py runs/paper runs/paper-python

Writes engines.md here (``--out``: elsewhere): per condition, each engine's final success with
its 95% interval over seeds, whether each lies inside the other's interval, and how many cells
are byte-identical.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from jointattention import load_config
from jointattention.analysis.curves import condition_curves
from jointattention.analysis.metrics import final_success, mean_interval
from jointattention.analysis.tables import Table
from jointattention.experiment.results import cell_path

HERE = Path(__file__).parent


def _final(per_seed: np.ndarray) -> tuple[float, float, float]:
    """Mean final success over seeds and its 95% t interval."""
    mean, lo, hi = mean_interval(np.array([[final_success(s)] for s in per_seed]))
    return float(mean[0]), float(lo[0]), float(hi[0])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("compiled", type=Path)
    ap.add_argument("python", type=Path)
    ap.add_argument("--out", type=Path, default=HERE / "engines.md")
    args = ap.parse_args()
    configs = {name: load_config(path / "config.toml")
               for name, path in (("compiled", args.compiled), ("python", args.python))}
    exp = configs["compiled"].experiment
    curves = {name: condition_curves(path, configs[name])
              for name, path in (("compiled", args.compiled), ("python", args.python))}
    rows, same = [], 0
    for c in exp.conditions:
        for i in range(exp.n_seeds):
            a, b = (cell_path(p, c.name, i).read_bytes() for p in (args.compiled, args.python))
            same += a == b
        (cm, clo, chi), (pm, plo, phi) = (_final(curves[e][c.name][1])
                                          for e in ("compiled", "python"))
        rows.append((c.name, f"{pm:.3f} ({plo:.3f}-{phi:.3f})", f"{cm:.3f} ({clo:.3f}-{chi:.3f})",
                     "yes" if plo <= cm <= phi else "NO", "yes" if clo <= pm <= chi else "NO"))
    table = Table(("condition", "python engine: final (95% interval)",
                   "compiled engine: final (95% interval)", "compiled inside python's",
                   "python inside compiled's"), rows)
    n_cells = len(exp.conditions) * exp.n_seeds
    text = (f"{table.to_markdown()}\n\n{same} of {n_cells} cells are byte-identical "
            "(the `.npz` files).\n")
    args.out.write_text(text)
    print(text)


if __name__ == "__main__":
    main()
