"""What the models carry over: the held-out measures of a run folder's cells (pure functions).

Each cell keeps its frozen model's success and errors on three kinds of data set (the
training sets, new poses of the training caregivers, unseen caregivers) at a few learning
times (:mod:`jointattention.experiment.held_out`). Here they become a table, the curves over
learning time and a claim per condition.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..config import Config
from ..experiment.results import Cells, cell_records
from .claim_record import Claim, reading_of
from .tables import Table

__all__ = ["AIM", "KINDS", "frozen_fractions", "held_out_claims", "held_out_curves",
           "held_out_table"]

KINDS = ("training", "new poses", "unseen caregivers")
# the aim for a model that follows people it never saw (docs/generalisation.md)
AIM = {"fraction_of_ceiling": 0.9, "median_error_deg": 4.0, "share_over_10deg": 0.05}

HeldOut = dict[str, tuple[np.ndarray, dict[str, np.ndarray]]]


def held_out_curves(out: Path, config: Config, cells: Cells | None = None) -> HeldOut:
    """{condition: (learning times, {measure: (seeds, kinds, times)})} of the measured cells.

    Conditions whose cells were not measured are left out. Measures are named without their
    ``held_out_`` prefix.
    """
    exp, curves = config.experiment, {}
    for c in exp.conditions:
        records = [cell_records(out, c.name, i, cells) for i in range(exp.n_seeds)]
        if not all("held_out_steps" in r for r in records):
            continue
        names = [k for k in records[0] if k.startswith("held_out_") and k != "held_out_steps"]
        curves[c.name] = (records[0]["held_out_steps"],
                          {k.removeprefix("held_out_"): np.array([r[k] for r in records])
                           for k in names})
    return curves


def _fraction(success: np.ndarray, ceiling: float) -> np.ndarray:
    return success / ceiling if ceiling > 0 else np.full_like(success, np.nan)


def frozen_fractions(measured: dict, ceilings: dict, n_objects: int) -> list[np.ndarray]:
    """Per kind (:data:`KINDS`), each seed's last frozen success over that set's ceiling.

    ``measured``: one condition's measures, as in :func:`held_out_curves`; ``ceilings``:
    {kind: {str(n_objects): ceiling}}. NaN where the ceiling is not known.
    """
    return [_fraction(measured["success"][:, j, -1],
                      ceilings.get(kind, {}).get(str(n_objects), np.nan))
            for j, kind in enumerate(KINDS)]


def held_out_table(config: Config, curves: HeldOut, ceilings: dict,
                   novelty: dict | None = None) -> Table:
    """One row per measured condition: the three kinds side by side, at the end of learning.

    Success as a fraction of each set's ceiling (``ceilings`` {kind: {str(n): ceiling}}; mean
    over seeds, and the worst seed on unseen caregivers), the median angle error at the faces,
    the share of unseen identities whose median error is above 10°, and the controls on the
    unseen faces (:mod:`jointattention.experiment.controls`): the share of mirrored faces whose
    horizontal command flips, and the spread of the directions for a blank face. ``novelty``
    ({kind: each identity's novelty}, :func:`~jointattention.experiment.held_out.
    held_out_novelty`): how new the unseen caregivers are to the training ones, the median and
    the largest over them (NaN where not known).
    """
    columns = ("condition", "n_objects", "training_fraction", "new_poses_fraction",
               "unseen_fraction", "unseen_worst_seed_fraction", "training_median_deg",
               "new_poses_median_deg", "unseen_median_deg", "unseen_p90_deg",
               "unseen_share_over_10deg", "unseen_mirror_flip_share", "unseen_blank_spread_deg",
               "unseen_novelty_median", "unseen_novelty_max")
    new = np.asarray((novelty or {}).get("unseen caregivers", []), float)
    new = new[np.isfinite(new)]
    new = (round(float(np.median(new)), 2), round(float(new.max()), 2)) if len(new) else (
        float("nan"), float("nan"))
    rows = []
    for c in config.experiment.conditions:
        if c.name not in curves:
            continue
        m = curves[c.name][1]
        fractions = frozen_fractions(m, ceilings, c.n_objects)
        median = np.nanmean(m["median_error_deg"][:, :, -1], axis=0) if np.isfinite(
            m["median_error_deg"][:, :, -1]).any() else np.full(3, np.nan)
        rows.append((c.name, c.n_objects, *(round(float(f.mean()), 3) for f in fractions),
                     round(float(fractions[2].min()), 3),
                     *(round(float(v), 1) for v in median),
                     round(float(np.mean(m["p90_error_deg"][:, 2, -1])), 1),
                     round(float(np.mean(m["share_over_10deg"][:, 2, -1])), 3),
                     round(float(np.mean(m["mirror_flip_share"][:, 2, -1])), 3),
                     round(float(np.mean(m["blank_spread_deg"][:, 2, -1])), 1), *new))
    return Table(columns, rows)


def held_out_claims(config: Config, curves: HeldOut, ceilings: dict) -> list[Claim]:
    """Per measured condition: does it follow people it never saw?

    Shuffled-faces controls and models that cannot be frozen (not measured) get no claim.
    The rule (:data:`AIM`): on unseen caregivers, frozen success at least 0.9 of that set's
    ceiling, a median angle error at most 4° and at most 5% of identities above 10°, as means
    over seeds.
    """
    claims = []
    table = held_out_table(config, curves, ceilings)
    rows = {r[0]: dict(zip(table.columns, r, strict=True)) for r in table.rows}
    for c in config.experiment.conditions:
        if c.name not in rows or c.shuffle_faces:
            continue
        r = rows[c.name]
        if not np.isfinite(r["unseen_fraction"]):  # a model that cannot be frozen
            continue
        holds = (r["unseen_fraction"] >= AIM["fraction_of_ceiling"]
                 and r["unseen_median_deg"] <= AIM["median_error_deg"]
                 and r["unseen_share_over_10deg"] <= AIM["share_over_10deg"])
        claims.append(Claim(
            reading_of(c, config), f"{c.n_objects} object{'s' * (c.n_objects != 1)} ({c.name}): "
            "follows caregivers it never saw", bool(holds),
            f"unseen caregivers {r['unseen_fraction']:.2f} of the ceiling (worst seed "
            f"{r['unseen_worst_seed_fraction']:.2f}), median error {r['unseen_median_deg']}°, "
            f"identities above 10° {r['unseen_share_over_10deg']:.2f}; training sets "
            f"{r['training_fraction']:.2f}, new poses {r['new_poses_fraction']:.2f}",
            f"unseen caregivers: mean frozen success >= {AIM['fraction_of_ceiling']} x ceiling, "
            f"median error <= {AIM['median_error_deg']}°, identities above 10° <= "
            f"{AIM['share_over_10deg']}", "project"))
    return claims
