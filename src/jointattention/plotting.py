"""Figures and tables from a saved run folder, never from a live simulation."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np

from . import io
from .agent.gate import sigmoid_rate
from .claims import check_claims, claims_markdown
from .config import READINGS, Config, agent_config, load_config
from .metrics import final_success, mean_interval, success_by_bin, time_to_fraction

__all__ = ["condition_curves", "save_figure", "write_figures", "write_table"]


def condition_curves(out: Path, config: Config) -> dict[str, tuple]:
    """{condition: (bin ends, per-seed curves (seeds, bins))} from the saved cells."""
    exp = config.experiment
    ends = np.minimum(np.arange(1, int(np.ceil(exp.n_steps / exp.bin_steps)) + 1)
                      * exp.bin_steps, exp.n_steps)
    curves = {}
    for c in exp.conditions:
        per_seed = []
        for i in range(exp.n_seeds):
            rec = io.load_cell(io.cell_path(out, c.name, i))
            per_seed.append(success_by_bin(rec["learning_time"], rec["success"],
                                           exp.bin_steps, exp.n_steps))
        curves[c.name] = (ends, np.array(per_seed))
    return curves


def _is_plain(c, config: Config) -> bool:
    """A condition of the paper's own figures: the default reading, faces not shuffled."""
    agent = agent_config(config, c)
    return not c.shuffle_faces and all(getattr(agent, k) == getattr(config.agent, k)
                                       for k in READINGS)


def _plot_conditions(ax, curves, names, config, ceilings, labels):
    import matplotlib.pyplot as plt

    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    n_of = {c.name: c.n_objects for c in config.experiment.conditions}
    shown_n = []
    for k, name in enumerate(names):
        ends, per_seed = curves[name]
        mean, lo, hi = mean_interval(per_seed)
        col = colours[k % len(colours)]
        ax.plot(ends, mean, color=col, label=labels.get(name, name))
        ax.fill_between(ends, lo, hi, color=col, alpha=0.2, linewidth=0)
        n = n_of[name]
        if n not in shown_n:
            shown_n.append(n)
            ax.axhline(1 / n, color=col, linestyle=":", linewidth=1)
            if str(n) in ceilings:
                ax.axhline(ceilings[str(n)], color=col, linestyle="--", linewidth=1)
    ax.set_xlabel("learning time [steps]")
    ax.set_ylabel("success rate of joint attention")
    ax.set_ylim(0, 1.02)
    ax.legend(fontsize=8, loc="upper left")


def write_figures(out: Path) -> list[Path]:
    """Fig. 4(a), Fig. 4(b), Fig. 5, the table and the checked claims from the run folder
    ``out``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(out)
    config = load_config(out / "config.toml")
    ceilings = json.loads((out / "ceilings.json").read_text())
    curves = condition_curves(out, config)
    conds = {c.name: c for c in config.experiment.conditions}
    written = []
    note = "dotted: chance 1/n; dashed: oracle gaze-line ceiling; bands: 95% interval over seeds"

    fig4a = [n for n, c in conds.items()
             if _is_plain(c, config) and agent_config(config, c).gate == "sigmoid"]
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    _plot_conditions(ax, curves, fig4a, config, ceilings,
                     {n: f"{conds[n].n_objects} objects" for n in fig4a})
    ax.set_title("Fig. 4(a): success against learning time (sigmoid gate)\n" + note, fontsize=8)
    written.append(save_figure(fig, out / "fig4a_success.png"))

    fig, ax = plt.subplots(figsize=(6.4, 3.2))
    t = np.linspace(0, config.experiment.n_steps, 400)
    a = config.agent
    ax.plot(t, sigmoid_rate(t, a.gate_midpoint_steps, a.gate_width_steps))
    ax.set_xlabel("learning time [steps]")
    ax.set_ylabel("rate of choosing LM Δθ")
    ax.set_ylim(-0.02, 1.02)
    ax.set_title("Fig. 4(b): gating function (sigmoid)", fontsize=9)
    written.append(save_figure(fig, out / "fig4b_gate.png"))

    fig5 = [n for n, c in conds.items() if _is_plain(c, config) and c.n_objects == 5]
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    agents = {n: agent_config(config, conds[n]) for n in fig5}
    labels = {n: ("sigmoid" if agents[n].gate == "sigmoid" else f"constant {agents[n].gate_rate}")
              for n in fig5}
    _plot_conditions(ax, curves, fig5, config, ceilings, labels)
    ax.set_title("Fig. 5: 5 objects, sigmoid gate against constant rates\n" + note, fontsize=8)
    written.append(save_figure(fig, out / "fig5_gates.png"))
    written += write_table(out, config, curves, ceilings)
    claims_path = out / "claims.md"
    with io.atomic_path(claims_path) as tmp:
        tmp.write_text(claims_markdown(check_claims(config, curves, ceilings)))
    return [*written, claims_path]


def write_table(out: Path, config: Config, curves, ceilings) -> list[Path]:
    """Final success per condition, as a fraction of the ceiling, and the time to 90%."""
    rows = []
    for c in config.experiment.conditions:
        per_seed = curves[c.name][1]
        mean = mean_interval(per_seed)[0]
        final = final_success(mean)
        finals = [final_success(s) for s in per_seed]
        ceiling = ceilings.get(str(c.n_objects), float("nan"))
        rows.append({
            "condition": c.name, "n_objects": c.n_objects, "chance": round(1 / c.n_objects, 3),
            "ceiling": round(ceiling, 3), "final_success": round(final, 3),
            "final_sd_over_seeds": round(float(np.std(finals, ddof=1)) if len(finals) > 1
                                         else 0.0, 3),
            "fraction_of_ceiling": round(final / ceiling, 3),
            "steps_to_90pct_of_final": time_to_fraction(mean, config.experiment.bin_steps),
        })
    csv_path = out / "table.csv"
    with io.atomic_path(csv_path) as tmp, open(tmp, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    md = ["| " + " | ".join(rows[0]) + " |", "|" + "---|" * len(rows[0])]
    md += ["| " + " | ".join(str(v) for v in r.values()) + " |" for r in rows]
    md_path = out / "table.md"
    with io.atomic_path(md_path) as tmp:
        tmp.write_text("\n".join(md) + "\n")
    return [csv_path, md_path]


def save_figure(fig, path: Path, dpi: int = 110) -> Path:
    """Lay out ``fig``, write it to ``path`` (format from its suffix) atomically, close it."""
    import matplotlib.pyplot as plt

    fig.tight_layout()
    with io.atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=dpi, format=path.suffix[1:])
    plt.close(fig)
    return path
