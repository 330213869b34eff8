"""The trade-off between learning fast and learning well, one point per seed."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..analysis.learning_speed import (
    TARGET_FRACTION,
    TARGET_STEPS,
    UNSEEN_TARGET_FRACTION,
    speed_points,
)
from ..analysis.tables import Table
from ._save import new_figure, save_figure

__all__ = ["learning_speed_figure"]


def learning_speed_figure(table: Table, path: Path) -> Path:
    """Success / ceiling against steps to 90% of the final, per seed (a learning-speed table).

    The success is the frozen model's on unseen caregivers where measured, else the final
    success (:func:`~jointattention.analysis.learning_speed.speed_points`).

    Each condition is one colour: its seeds as dots, their medians as a ringed point. The
    shaded corner is the target (:mod:`jointattention.analysis.learning_speed`). Seeds that
    never reach 90% of their final are left out.
    """
    points = speed_points(table)
    fig = new_figure(9.0, 5.0)
    ax = fig.subplots()
    colours = [f"C{i % 10}" for i in range(len(points))]
    markers = "ospD^v<>"
    for i, (name, p) in enumerate(points.items()):
        p = p[np.isfinite(p).all(axis=1)]
        if not len(p):
            continue
        style = {"color": colours[i], "marker": markers[(i // 10) % len(markers)]}
        ax.scatter(p[:, 0], p[:, 1], s=12, alpha=0.45, **style)
        ax.scatter(*np.median(p, axis=0), s=60, edgecolors="k", label=name, **style)
    right = max([TARGET_STEPS * 2] + [float(np.nanmax(p[:, 0])) for p in points.values()
                                      if np.isfinite(p[:, 0]).any()])
    i = table.columns.index("unseen_caregivers_fraction")
    unseen = np.isfinite(np.array([float(r[i]) for r in table.rows])).any()
    floor, what = ((UNSEEN_TARGET_FRACTION, "frozen, on unseen caregivers") if unseen
                   else (TARGET_FRACTION, "final"))
    ax.fill_between([0, TARGET_STEPS], floor, 1.1, color="tab:green", alpha=0.12,
                    label=f"target: <= {TARGET_STEPS:,} steps, >= {floor} of the ceiling "
                    f"({what})")
    ax.set_xlim(0, right * 1.05)
    ax.set_ylim(0, 1.1)
    ax.set_xlabel("learning time to 90% of the seed's final success [steps]")
    ax.set_ylabel("success / ceiling: frozen on unseen caregivers\n(where measured; else final)")
    ax.legend(fontsize=6, loc="center left", bbox_to_anchor=(1.01, 0.5), ncol=1 + len(points) // 16)
    ax.set_title("learning fast against learning well (one small dot per seed)", fontsize=10)
    return save_figure(fig, path)
