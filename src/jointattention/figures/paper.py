"""The paper's Fig. 4(a), Fig. 4(b) and Fig. 5 from a run's success curves.

And a figure of the models side by side when a run's conditions use more than one model.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np

from ..analysis.metrics import mean_interval
from ..config import ConditionConfig, Config, model_options
from ._save import new_figure, save_figure

__all__ = ["is_plain", "write_figures"]

_NOTE = "dotted: chance 1/n; dashed: oracle gaze-line ceiling; bands: 95% interval over seeds"


def is_plain(condition: ConditionConfig, config: Config) -> bool:
    """Whether a condition belongs in the paper's own figures.

    It has the run's model and readings, and faces not shuffled (other gates are allowed).
    """
    options, run = model_options(config, condition), config.model
    return (not condition.shuffle_faces and type(options) is type(run)
            and all(getattr(options, k) == getattr(run, k) for k in run.readings))


def _plot_conditions(ax, curves, names, conditions, ceilings, labels) -> None:
    colours = matplotlib.rcParams["axes.prop_cycle"].by_key()["color"]
    shown_n = []
    for k, name in enumerate(names):
        ends, per_seed = curves[name]
        mean, lo, hi = mean_interval(per_seed)
        col = colours[k % len(colours)]
        ax.plot(ends, mean, color=col, label=labels[name])
        ax.fill_between(ends, lo, hi, color=col, alpha=0.2, linewidth=0)
        n = conditions[name].n_objects
        if n not in shown_n:
            shown_n.append(n)
            ax.axhline(1 / n, color=col, linestyle=":", linewidth=1)
            if str(n) in ceilings:
                ax.axhline(ceilings[str(n)], color=col, linestyle="--", linewidth=1)
    ax.set_xlabel("learning time [steps]")
    ax.set_ylabel("success rate of joint attention")
    ax.set_ylim(0, 1.02)
    if names:
        ax.legend(fontsize=8, loc="upper left")


def _gates_figure(config: Config, options: dict, path: Path) -> Path:
    """Fig. 4(b): each gate the conditions' model ``options`` use, against learning time.

    Gates whose rate is not a function of learning time (the performance gate) are left out;
    the diagnostics show the share of steps each module drove.
    """
    fig = new_figure(6.4, 3.2)
    ax = fig.subplots()
    t = np.linspace(0, config.experiment.n_steps, 400)
    gates = {}
    for o in options.values():
        gate = getattr(o, "gate", None)
        if gate is not None:
            gates.setdefault(gate.label, gate)
    for label, gate in gates.items():
        rate = gate.rate_at(t)
        if not np.isnan(rate).all():  # a performance gate's rate is not a function of time
            ax.plot(t, rate, label=label)
    ax.set_xlabel("learning time [steps]")
    ax.set_ylabel("rate of choosing LM Δθ")
    ax.set_ylim(-0.02, 1.02)
    if len(gates) > 1:
        ax.legend(fontsize=8)
    ax.set_title("Fig. 4(b): gating function", fontsize=9)
    return save_figure(fig, path)


def write_figures(out: Path, config: Config, curves: dict, ceilings: dict) -> list[Path]:
    """Write the paper's figures into ``out``; returns their paths.

    fig4a_success.png, fig4b_gate.png, fig5_gates.png, and models.png if the conditions use more
    than one model (or learning module, or a performance gate).
    """
    out = Path(out)
    conds = {c.name: c for c in config.experiment.conditions}
    options = {n: model_options(config, c) for n, c in conds.items()}
    plain = [n for n, c in conds.items() if is_plain(c, config)]
    written = []

    sigmoid = [n for n in plain
               if getattr(getattr(options[n], "gate", None), "claims_role", None) == "sigmoid"]
    fig = new_figure(6.4, 4.4)
    ax = fig.subplots()
    _plot_conditions(ax, curves, sigmoid, conds, ceilings,
                     {n: f"{conds[n].n_objects} objects" for n in sigmoid})
    ax.set_title("Fig. 4(a): success against learning time (sigmoid gate)\n" + _NOTE, fontsize=8)
    written.append(save_figure(fig, out / "fig4a_success.png"))
    written.append(_gates_figure(config, options, out / "fig4b_gate.png"))

    five = [n for n in plain if conds[n].n_objects == 5]
    fig = new_figure(6.4, 4.4)
    ax = fig.subplots()
    labels = {n: getattr(options[n], "gate", None) for n in five}
    _plot_conditions(ax, curves, five, conds, ceilings,
                     {n: g.label if g is not None else n for n, g in labels.items()})
    ax.set_title("Fig. 5: 5 objects, sigmoid gate against constant rates\n" + _NOTE, fontsize=8)
    written.append(save_figure(fig, out / "fig5_gates.png"))

    model = config.model.label.split(", ")[0]  # the model's name (and learner), not its gate
    others = {n for n, o in options.items() if o.label.split(", ")[0] != model
              or getattr(getattr(o, "gate", None), "measured", False)}
    if others:
        shown = [n for n, c in conds.items()
                 if n in plain or (n in others and not c.shuffle_faces)]
        written.append(_models_figure(out / "models.png", curves, conds, options, shown,
                                      ceilings))
    return written


def _models_figure(path: Path, curves, conds, options, shown, ceilings) -> Path:
    """One panel per object count (two per row): the conditions ``shown``, labelled by name."""
    counts = sorted({conds[n].n_objects for n in shown})
    cols = min(2, len(counts))
    rows = -(-len(counts) // cols)
    fig = new_figure(6.4 * cols, 4.4 * rows)
    axes = np.atleast_1d(fig.subplots(rows, cols)).ravel()
    for ax in axes[len(counts):]:
        ax.set_visible(False)
    for ax, n in zip(axes, counts, strict=False):
        names = [m for m in shown if conds[m].n_objects == n]
        _plot_conditions(ax, curves, names, conds, ceilings, {m: m for m in names})
        ax.set_title(f"{n} objects: the models side by side\n" + _NOTE, fontsize=8)
    return save_figure(fig, path)
