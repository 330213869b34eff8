"""Success curves of a run folder's conditions, and the table of their final success."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..config import Config
from ..experiment.results import Cells, cell_records
from .metrics import final_success, mean_interval, success_by_bin, time_to_fraction
from .tables import Table

__all__ = ["condition_axis_errors", "condition_curves", "final_table"]

Curves = dict[str, tuple[np.ndarray, np.ndarray]]


def condition_curves(out: Path, config: Config, cells: Cells | None = None) -> Curves:
    """{condition: (bin ends, per-seed success curves (seeds, bins))} from the saved cells.

    ``cells``: the cells' records if already loaded ({(condition, seed): records}).
    """
    exp = config.experiment
    ends = exp.bin_ends_steps()
    curves = {}
    for c in exp.conditions:
        per_seed = []
        for i in range(exp.n_seeds):
            rec = cell_records(out, c.name, i, cells)
            per_seed.append(success_by_bin(rec["learning_time"], rec["success"],
                                           exp.bin_steps, exp.n_steps))
        curves[c.name] = (ends, np.array(per_seed))
    return curves


def condition_axis_errors(out: Path, config: Config, cells: Cells | None = None) -> dict:
    """{condition: (horizontal, vertical) errors (seeds, bins)} of the learning module.

    For the conditions whose cells hold them (``lm_pan_error_deg``, ``lm_tilt_error_deg``) and
    measured them (a model with a learning module). ``cells`` as :func:`condition_curves`'s.
    """
    exp, errors = config.experiment, {}
    for c in exp.conditions:
        records = [cell_records(out, c.name, i, cells) for i in range(exp.n_seeds)]
        if all("lm_pan_error_deg" in r for r in records):
            pan, tilt = (np.array([r[k] for r in records]) for k in
                         ("lm_pan_error_deg", "lm_tilt_error_deg"))
            if np.isfinite(pan).all() and np.isfinite(tilt).all():
                errors[c.name] = (pan, tilt)
    return errors


def final_table(config: Config, curves: Curves, ceilings: dict[str, float],
                held_out: dict | None = None, held_out_ceilings: dict | None = None) -> Table:
    """The table of final success, one row per condition.

    Chance, the oracle ceiling, final success (mean of the last 10% of bins; s.d. over seeds), its
    fraction of the ceiling and the time to 90% of it. With ``held_out`` (as from
    :func:`~.held_out.held_out_curves`) and its ceilings, two more columns: the frozen model's
    success on new poses and on unseen caregivers at the end, as fractions of their ceilings
    (empty for a condition not measured).
    """
    columns = ("condition", "n_objects", "chance", "ceiling", "final_success",
               "final_sd_over_seeds", "fraction_of_ceiling", "steps_to_90pct_of_final")
    if held_out:
        columns += ("new_poses_fraction", "unseen_caregivers_fraction")
    rows = []
    for c in config.experiment.conditions:
        per_seed = curves[c.name][1]
        mean = mean_interval(per_seed)[0]
        final = final_success(mean)
        finals = [final_success(s) for s in per_seed]
        ceiling = ceilings.get(str(c.n_objects), float("nan"))
        sd = float(np.std(finals, ddof=1)) if len(finals) > 1 else 0.0
        row = (c.name, c.n_objects, round(1 / c.n_objects, 3), round(ceiling, 3),
               round(final, 3), round(sd, 3), round(final / ceiling, 3),
               time_to_fraction(mean, config.experiment.bin_ends_steps()))
        if held_out:
            row += _held_out_fractions(held_out.get(c.name), held_out_ceilings, c.n_objects)
        rows.append(row)
    return Table(columns, rows)


def _held_out_fractions(held, ceilings: dict, n_objects: int) -> tuple:
    """Final frozen success on new poses and unseen caregivers over their ceilings."""
    if held is None:
        return "", ""
    success = held[1]["success"][:, :, -1].mean(axis=0)  # per kind, mean over seeds
    return tuple(round(float(success[j]) / ceilings.get(kind, {}).get(str(n_objects), np.nan), 3)
                 for j, kind in ((1, "new poses"), (2, "unseen caregivers")))
