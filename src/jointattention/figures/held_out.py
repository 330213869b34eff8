"""The generalisation figure: the frozen model on its training sets, new poses and new people."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..analysis.held_out import KINDS, HeldOut
from ..config import Config
from ._save import new_figure, save_figure

__all__ = ["held_out_figure"]

_STYLES = {"training": ("k", "-"), "new poses": ("tab:blue", "--"),
           "unseen caregivers": ("tab:red", "-")}


def held_out_figure(config: Config, curves: HeldOut, ceilings: dict, path: Path,
                    learning: dict | None = None,
                    learning_ceilings: dict[str, float] | None = None) -> Path:
    """One panel per measured condition: success / ceiling against learning time, per kind.

    Means over seeds, with the range of the seeds shaded; the dotted line is 0.9 of the
    ceiling. With ``learning`` ({condition: (bin ends, per-seed curves)},
    :func:`~jointattention.analysis.curves.condition_curves`) and its ``learning_ceilings``
    ({str(n_objects): oracle success}), a grey line beside them: the success of the trials
    while it learned, its gate choosing, over the training sets' ceiling.
    """
    names = [c for c in (c.name for c in config.experiment.conditions) if c in curves]
    n_objects = {c.name: c.n_objects for c in config.experiment.conditions}
    cols = min(4, max(len(names), 1))
    rows = max(math.ceil(len(names) / cols), 1)
    fig = new_figure(3.2 * cols, 2.6 * rows + 0.4)
    axes = np.atleast_1d(fig.subplots(rows, cols, squeeze=False)).ravel()
    for ax, name in zip(axes, names, strict=False):
        steps, m = curves[name]
        for j, kind in enumerate(KINDS):
            ceiling = ceilings.get(kind, {}).get(str(n_objects[name]), math.nan)
            frac = m["success"][:, j, :] / ceiling
            colour, style = _STYLES[kind]
            ax.plot(steps, frac.mean(axis=0), style, color=colour, label=kind)
            ax.fill_between(steps, frac.min(axis=0), frac.max(axis=0), color=colour, alpha=0.12)
        if learning is not None and name in learning:
            ends, per_seed = learning[name]
            ceiling = (learning_ceilings or {}).get(str(n_objects[name]), math.nan)
            ax.plot(ends, np.nanmean(per_seed, axis=0) / ceiling, color="0.6", linewidth=1,
                    label="while learning")
        ax.axhline(0.9, color="grey", linestyle=":", linewidth=0.8)
        ax.set_title(name, fontsize=9)
        ax.set_ylim(0, 1.1)
        ax.set_xlabel("learning time [steps]", fontsize=8)
        ax.set_ylabel("success / ceiling (frozen)", fontsize=8)
    for ax in axes[len(names):]:
        ax.set_visible(False)
    if names:
        axes[0].legend(fontsize=7, loc="lower right")
    fig.suptitle("the frozen model on its training sets, new poses of its caregivers and "
                 "caregivers it never saw", fontsize=10)
    return save_figure(fig, path)
