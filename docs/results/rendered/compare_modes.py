"""Rendered mode against fast mode on a short run: writes modes.png and modes.md here.

Run first (about 4 min on 2 cores):
    jointattention reproduce --preset rendered --out runs/rendered
then:
    python docs/results/rendered/compare_modes.py [runs/rendered] [--fast-seeds 10] [--out FILE.md]

It runs the same preset in the fast mode (compiled engine) with --fast-seeds seeds (seconds) into
runs/rendered-fast, and checks, bin by bin, whether the rendered mode's mean success lies
inside the fast mode's 95% interval (t interval of the mean over seeds). ``--out``: the table
elsewhere, and the figure beside it (.png).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from jointattention import load_config, run_experiment
from jointattention.analysis.curves import condition_curves
from jointattention.analysis.metrics import mean_interval
from jointattention.world.gl import suggested_backend

# A program chooses its process's OpenGL backend (the library only reads MUJOCO_GL).
os.environ.setdefault("MUJOCO_GL", suggested_backend())

HERE = Path(__file__).parent


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run", nargs="?", default="runs/rendered")
    ap.add_argument("--fast-seeds", type=int, default=10)
    ap.add_argument("--out", type=Path, default=HERE / "modes.md",
                    help="the table (.md); the figure goes beside it (.png)")
    args = ap.parse_args()
    run = Path(args.run)
    rendered_cfg = load_config(run / "config.toml")
    exp = dataclasses.replace(rendered_cfg.experiment, perception="fast", engine="compiled",
                              n_seeds=args.fast_seeds)
    fast_cfg = dataclasses.replace(rendered_cfg, experiment=exp)
    fast_run = run.parent / f"{run.name}-fast"
    run_experiment(fast_cfg, fast_run, workers=2)
    rendered, fast = condition_curves(run, rendered_cfg), condition_curves(fast_run, fast_cfg)
    timing = json.loads((run / "timing.json").read_text())
    steps = rendered_cfg.experiment.n_steps * len(rendered) * rendered_cfg.experiment.n_seeds
    lines = [f"Rendered mode: `{run}` ({rendered_cfg.experiment.n_seeds} seeds); fast mode: "
             f"`{fast_run}` ({args.fast_seeds} seeds). Rendered run: {steps:,} agent steps in "
             f"{timing['wall_min']:.1f} min on {timing['workers']} workers "
             f"({rendered_cfg.experiment.n_steps:,} steps per cell: every step renders with "
             "MuJoCo and detects with OpenCV, so the preset cuts the learning time, not the "
             "seeds, to run in about 5 min on 2 cores).", "",
             "| condition | bins inside the fast 95% interval | rendered final | fast final "
             "(95% interval) |", "|---|---|---|---|"]
    fig, axes = plt.subplots(1, len(rendered), figsize=(5 * len(rendered), 3.6), squeeze=False)
    for ax, name in zip(axes[0], rendered, strict=True):
        ends, per_seed = fast[name]
        f_mean, f_lo, f_hi = mean_interval(per_seed)
        r_mean = np.nanmean(rendered[name][1], axis=0)
        inside = (r_mean >= f_lo) & (r_mean <= f_hi)
        x = ends / 1e4
        ax.fill_between(x, f_lo, f_hi, alpha=0.3, label=f"fast, 95% interval ({args.fast_seeds} "
                                                        "seeds)")
        ax.plot(x, f_mean, color="tab:blue")
        ax.plot(x, r_mean, "o-", color="tab:red",
                label=f"rendered + OpenCV ({rendered_cfg.experiment.n_seeds} seeds)")
        ax.set_title(name)
        ax.set_xlabel("learning time (x 10^4 steps)")
        ax.set_ylabel("success of joint attention")
        ax.set_ylim(0, 1)
        ax.legend(fontsize=8)
        lines.append(f"| {name} | {int(inside.sum())} of {len(inside)} | {r_mean[-1]:.3f} | "
                     f"{f_mean[-1]:.3f} ({f_lo[-1]:.3f}-{f_hi[-1]:.3f}) |")
    fig.tight_layout()
    fig.savefig(args.out.with_suffix(".png"), dpi=120)
    args.out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
