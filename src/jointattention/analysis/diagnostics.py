"""Why a run learns as it does: per learning-time bin, what the robot learned from and how.

For each condition and bin (means over seeds):
- ``on_target``: the fraction of the evaluator's firings on the caregiver's target, i.e. of
  the robot's learning situations, the share that teaches the right direction;
- ``fired``, ``step_limit``, ``joint_limit``: how trials ended (fractions of trials);
- ``lm_steps``, ``vf_steps``, ``random_steps``: which module drove the head (fractions of
  steps);
- ``lm_error_deg``: the learning module's median angle error over the data sets' faces at
  the bin's end (the cell's ``lm_error_deg``), and its horizontal and vertical parts
  (``lm_pan_error_deg``, ``lm_tilt_error_deg``), and ``lm_bias``, how alike its directions
  are over those faces (1: the same direction for every face; NaN for cells written before
  they were measured).

:func:`seed_diagnostics` keeps every seed apart, with its final success, so that a failing
seed can be told from one that learns (``diagnostics_seeds.csv``, ``diagnostics_seeds.png``).
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from ..config import Config, ExperimentConfig
from ..experiment.results import Cells, cell_records
from ..experiment.trial import END_FIRED, END_LIMIT, END_STEPS
from .claim_record import finals_of
from .curves import Curves, condition_curves
from .metrics import bin_index
from .tables import Table

__all__ = ["METRICS", "SeedDiagnostics", "condition_diagnostics", "diagnostics_table",
           "seed_diagnostics", "seeds_table"]

METRICS = {
    "on_target": "fraction of the evaluator's firings on the caregiver's target",
    "fired": "fraction of trials ended by the evaluator",
    "step_limit": "fraction of trials ended at the step limit",
    "joint_limit": "fraction of trials ended at a joint limit",
    "lm_steps": "fraction of steps moved by the learning module",
    "vf_steps": "fraction of steps moved by the visual controller (the reinforcement "
                "learner's: spent looking at the caregiver)",
    "random_steps": "fraction of steps that were random (nothing in view)",
    "lm_error_deg": "learning module's median angle error at the data sets' faces (deg)",
    "lm_pan_error_deg": "its median horizontal error: where a turn along it ends (deg)",
    "lm_tilt_error_deg": "its median vertical error (deg)",
    "lm_bias": "how alike its directions are over those faces: the length of the mean of its "
               "unit outputs (1: one direction for every face, whatever the caregiver looks at)",
}

Diagnostics = dict[str, tuple[np.ndarray, dict[str, np.ndarray]]]


def _ratio(num: np.ndarray, den: np.ndarray) -> np.ndarray:
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(den > 0, num / np.maximum(den, 1), np.nan)


def _cell_metrics(rec: dict[str, np.ndarray], exp: ExperimentConfig) -> np.ndarray:
    """(metrics, bins) for one cell, in the order of :data:`METRICS`."""
    n_bins = len(exp.bin_ends_steps())
    idx = bin_index(rec["learning_time"], exp.bin_steps, exp.n_steps)

    def per_bin(values) -> np.ndarray:
        return np.bincount(idx, weights=np.asarray(values, float), minlength=n_bins)

    trials, steps = per_bin(np.ones(len(idx))), per_bin(rec["n_steps"])
    fired = rec["end"] == END_FIRED
    lm, rand = per_bin(rec["n_lm_steps"]), per_bin(rec["n_random_steps"])
    errors = [np.pad(e[:n_bins], (0, n_bins - len(e[:n_bins])), constant_values=np.nan)
              for e in (rec.get(k, np.full(n_bins, np.nan)) for k in
                        ("lm_error_deg", "lm_pan_error_deg", "lm_tilt_error_deg",
                         "lm_bias"))]
    return np.array([
        _ratio(per_bin(fired & rec["success"]), per_bin(fired)),
        _ratio(per_bin(fired), trials),
        _ratio(per_bin(rec["end"] == END_STEPS), trials),
        _ratio(per_bin(rec["end"] == END_LIMIT), trials),
        _ratio(lm, steps), _ratio(steps - lm - rand, steps), _ratio(rand, steps),
        *errors])


# {condition: (bin ends, (seeds, metrics, bins) in the order of METRICS, final success per seed)}
SeedDiagnostics = dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]


def seed_diagnostics(out: Path, config: Config, curves: Curves | None = None,
                     cells: Cells | None = None) -> SeedDiagnostics:
    """Every seed's metrics per bin and its final success, from a run folder's cells.

    The final success is the claims' and tables' (:func:`~.claim.finals_of` of the success
    curves, ``curves`` as from :func:`~.curves.condition_curves`: read from the cells if None).
    ``cells``: the cells' records if already loaded.
    """
    exp = config.experiment
    curves = condition_curves(out, config, cells) if curves is None else curves
    result = {}
    for c in exp.conditions:
        records = [cell_records(out, c.name, i, cells) for i in range(exp.n_seeds)]
        result[c.name] = (exp.bin_ends_steps(), np.array([_cell_metrics(r, exp) for r in records]),
                          finals_of(curves[c.name][1]))
    return result


def condition_diagnostics(out: Path, config: Config,
                          seeds: SeedDiagnostics | None = None) -> Diagnostics:
    """{condition: (bin ends, {metric: mean over seeds per bin})} from a run folder's cells."""
    seeds = seed_diagnostics(out, config) if seeds is None else seeds
    result = {}
    for name, (ends, per_seed, _) in seeds.items():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # a bin no seed has data for: NaN
            means = np.nanmean(per_seed, axis=0)
        result[name] = (ends, dict(zip(METRICS, means, strict=True)))
    return result


def diagnostics_table(diagnostics: Diagnostics) -> Table:
    """One row per condition and bin: the bin's end and every metric (3 decimals)."""
    rows = []
    for name, (ends, metrics) in diagnostics.items():
        for k, end in enumerate(ends):
            rows.append((name, int(end), *(round(float(metrics[m][k]), 3) for m in METRICS)))
    return Table(("condition", "bin_end_steps", *METRICS), rows)


def seeds_table(seeds: SeedDiagnostics) -> Table:
    """One row per condition, seed and bin: the seed's final success and every metric."""
    rows = []
    for name, (ends, per_seed, finals) in seeds.items():
        for i, (metrics, final) in enumerate(zip(per_seed, finals, strict=True)):
            rows += [(name, i, round(float(final), 3), int(end),
                      *(round(float(v), 3) for v in metrics[:, k]))
                     for k, end in enumerate(ends)]
    return Table(("condition", "seed", "final_success", "bin_end_steps", *METRICS), rows)
