"""The diagnostics figure: why a run learns as it does, per learning-time bin."""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np

from ..analysis.diagnostics import METRICS, Diagnostics, SeedDiagnostics
from ._save import new_figure, save_figure

__all__ = ["MAX_SEED_ROWS", "diagnostics_figure", "seeds_figure"]

_PANELS = [  # (title, [(metric, line style)], y limits)
    ("learning situations on the caregiver's target\n(fraction of firings)",
     [("on_target", "-")], (0, 1.02)),
    ("learning module's median angle error\nat the data sets' faces (deg)",
     [("lm_error_deg", "-")], (0, 130)),
    ("who moved the head (fraction of steps)\nsolid: learning module; dashed: random",
     [("lm_steps", "-"), ("random_steps", "--")], (0, 1.02)),
    ("how trials ended (fraction of trials)\nsolid: joint limit; dashed: step limit",
     [("joint_limit", "-"), ("step_limit", "--")], (0, 1.02)),
]


def diagnostics_figure(diagnostics: Diagnostics, path: Path) -> Path:
    """Four panels against learning time, one colour per condition (means over seeds)."""
    colours = matplotlib.rcParams["axes.prop_cycle"].by_key()["color"]
    fig = new_figure(12.8, 7.6)
    axes = fig.subplots(2, 2).ravel()
    for ax, (title, lines, ylim) in zip(axes, _PANELS, strict=True):
        for k, (name, (ends, metrics)) in enumerate(diagnostics.items()):
            for j, (metric, style) in enumerate(lines):
                ax.plot(ends, metrics[metric], style, color=colours[k % len(colours)],
                        label=name if j == 0 else None)
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("learning time [steps]")
        ax.set_ylim(*ylim)
    axes[0].legend(fontsize=7, loc="best")
    return save_figure(fig, path)


_SEED_PANELS = [  # (metric, column title, y limits)
    ("on_target", "learning situations on the target\n(fraction of firings)", (0, 1.02)),
    ("lm_error_deg", "module's median error at the faces (deg)", (0, 130)),
    ("lm_bias", "module's bias: how alike its directions\nare over the faces (1: one for all)",
     (0, 1.02)),
]


MAX_SEED_ROWS = 16  # conditions drawn at most: those whose seeds disagree most


def seeds_figure(seeds: SeedDiagnostics, path: Path) -> Path:
    """One row per condition, one line per seed coloured by its final success (why a seed fails).

    Columns: the share of learning situations on the target, the module's error at the faces,
    and its bias. A seed whose module keeps one direction for every face (bias near 1) before
    the hand-over learns from its own bias after it. With more than :data:`MAX_SEED_ROWS`
    conditions, those with the widest spread of final success over seeds are drawn (the csv
    has them all).
    """
    if len(seeds) > MAX_SEED_ROWS:
        spread = {name: float(np.ptp(v[2])) for name, v in seeds.items()}
        keep = set(sorted(spread, key=spread.get, reverse=True)[:MAX_SEED_ROWS])
        seeds = {name: v for name, v in seeds.items() if name in keep}
    cmap = matplotlib.colormaps["viridis"]
    fig = new_figure(12.8, 1.9 * len(seeds) + 0.6)
    axes = np.atleast_2d(fig.subplots(len(seeds), len(_SEED_PANELS), squeeze=False))
    index = {m: i for i, m in enumerate(METRICS)}
    for row, (name, (ends, per_seed, finals)) in zip(axes, seeds.items(), strict=True):
        for ax, (metric, title, ylim) in zip(row, _SEED_PANELS, strict=True):
            for metrics, final in zip(per_seed, finals, strict=True):
                ax.plot(ends, metrics[index[metric]], color=cmap(float(np.clip(final, 0, 1))),
                        lw=1)
            ax.set_ylim(*ylim)
            ax.set_title(f"{name}: {title}" if metric == "on_target" else title, fontsize=8)
            ax.tick_params(labelsize=7)
        row[0].set_ylabel(f"finals {finals.min():.2f}-{finals.max():.2f}", fontsize=7)
    for ax in axes[-1]:
        ax.set_xlabel("learning time [steps]", fontsize=8)
    axes[-1, 1].set_xlabel("learning time [steps]\none line per seed, coloured by its final "
                           "success (dark: 0, yellow: 1)", fontsize=8)
    return save_figure(fig, path)
