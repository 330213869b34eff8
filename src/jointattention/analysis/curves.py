"""Success curves of a run folder's conditions, and the table of their final success."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..config import Config
from ..experiment.results import cell_path, load_cell
from .metrics import final_success, mean_interval, success_by_bin, time_to_fraction
from .tables import Table

__all__ = ["condition_axis_errors", "condition_curves", "final_table"]

Curves = dict[str, tuple[np.ndarray, np.ndarray]]


def condition_curves(out: Path, config: Config) -> Curves:
    """{condition: (bin ends, per-seed success curves (seeds, bins))} from the saved cells."""
    exp = config.experiment
    ends = exp.bin_ends_steps()
    curves = {}
    for c in exp.conditions:
        per_seed = []
        for i in range(exp.n_seeds):
            rec = load_cell(cell_path(out, c.name, i))
            per_seed.append(success_by_bin(rec["learning_time"], rec["success"],
                                           exp.bin_steps, exp.n_steps))
        curves[c.name] = (ends, np.array(per_seed))
    return curves


def condition_axis_errors(out: Path, config: Config) -> dict:
    """{condition: (horizontal, vertical) errors (seeds, bins)} of the learning module.

    For the conditions whose cells hold them (``lm_pan_error_deg``, ``lm_tilt_error_deg``) and
    measured them (a model with a learning module).
    """
    exp, errors = config.experiment, {}
    for c in exp.conditions:
        cells = [load_cell(cell_path(out, c.name, i)) for i in range(exp.n_seeds)]
        if all("lm_pan_error_deg" in r for r in cells):
            pan, tilt = (np.array([r[k] for r in cells]) for k in
                         ("lm_pan_error_deg", "lm_tilt_error_deg"))
            if np.isfinite(pan).all() and np.isfinite(tilt).all():
                errors[c.name] = (pan, tilt)
    return errors


def final_table(config: Config, curves: Curves, ceilings: dict[str, float]) -> Table:
    """The table of final success, one row per condition.

    Chance, the oracle ceiling, final success (mean of the last 10% of bins; s.d. over seeds), its
    fraction of the ceiling and the time to 90% of it.
    """
    columns = ("condition", "n_objects", "chance", "ceiling", "final_success",
               "final_sd_over_seeds", "fraction_of_ceiling", "steps_to_90pct_of_final")
    rows = []
    for c in config.experiment.conditions:
        per_seed = curves[c.name][1]
        mean = mean_interval(per_seed)[0]
        final = final_success(mean)
        finals = [final_success(s) for s in per_seed]
        ceiling = ceilings.get(str(c.n_objects), float("nan"))
        sd = float(np.std(finals, ddof=1)) if len(finals) > 1 else 0.0
        rows.append((c.name, c.n_objects, round(1 / c.n_objects, 3), round(ceiling, 3),
                     round(final, 3), round(sd, 3), round(final / ceiling, 3),
                     time_to_fraction(mean, config.experiment.bin_steps)))
    return Table(columns, rows)
