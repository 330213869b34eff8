"""The diagnostics figure: why a run learns as it does, per learning-time bin."""

from __future__ import annotations

from pathlib import Path

import matplotlib

from ..analysis.diagnostics import Diagnostics
from ._save import new_figure, save_figure

__all__ = ["diagnostics_figure"]

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
