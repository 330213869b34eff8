"""How fast each seed learns, and how well: steps to 90% of its final success, and that final.

The paper's future work asks for a robot that learns faster. A learner that hands control to
its module early may learn fast and end lower, so both are reported per seed, side by side
(``learning_speed.csv``/``.md``; the figure is
:func:`jointattention.figures.learning_speed.learning_speed_figure`). The target, for a
learner that judges itself: 90% of its final success within 3x10^4 steps
(:data:`TARGET_STEPS`), and a learner measured on caregivers it never saw, frozen, at least
0.9 of that set's ceiling (:data:`UNSEEN_TARGET_FRACTION`, the held-out aim's:
docs/learn-fast.md); one not measured so, a final success of at least 0.95 of the ceiling
(:data:`TARGET_FRACTION`: docs/beyond-the-paper.md).
"""

from __future__ import annotations

import numpy as np

from ..config import Config
from .held_out import AIM, KINDS, HeldOut, frozen_fractions
from .metrics import final_success, time_to_fraction
from .tables import Table

__all__ = ["TARGET_FRACTION", "TARGET_STEPS", "UNSEEN_TARGET_FRACTION", "learning_speed_table",
           "speed_points"]

TARGET_STEPS = 30_000  # steps to 90% of the final success, at most
TARGET_FRACTION = 0.95  # final success over the ceiling, at least (no strangers measured)
UNSEEN_TARGET_FRACTION = AIM["fraction_of_ceiling"]  # frozen, on unseen caregivers, at least


def learning_speed_table(config: Config, curves: dict, ceilings: dict[str, float],
                         held: HeldOut | None = None, held_ceilings: dict | None = None
                         ) -> Table:
    """One row per condition and seed: its final success, and how fast it got there.

    The final success (also as a fraction of the ceiling) and the learning time at which the
    seed's own curve first reaches 90% of it (NaN if never), also in minutes of a real head
    making ``experiment.head_moves_per_s`` moves a second; the seed's frozen success on
    unseen caregivers at the last checkpoint over that set's ceiling (NaN where not measured);
    ``meets_target``: both within the targets above (on the unseen caregivers where measured,
    else on the final success).

    ``curves``: {condition: (bin ends, per-seed curves)}
    (:func:`~.curves.condition_curves`); ``ceilings``: {str(n_objects): oracle success};
    ``held``, ``held_ceilings``: :func:`~.held_out.held_out_curves` and the held-out sets'
    ceilings ({kind: {str(n_objects): ceiling}}), if measured.
    """
    columns = ("condition", "n_objects", "seed", "final_success", "fraction_of_ceiling",
               "steps_to_90pct_of_final", "real_head_minutes_to_90pct",
               "unseen_caregivers_fraction", "meets_target")
    moves_per_min = 60 * config.experiment.head_moves_per_s
    unseen = KINDS.index("unseen caregivers")
    rows = []
    for c in config.experiment.conditions:
        ends, per_seed = curves[c.name]
        ceiling = ceilings.get(str(c.n_objects), float("nan"))
        measured = (held or {}).get(c.name)
        strangers = (frozen_fractions(measured[1], held_ceilings or {}, c.n_objects)[unseen]
                     if measured is not None else np.full(len(per_seed), np.nan))
        for seed, curve in enumerate(per_seed):
            final = final_success(curve)
            steps = time_to_fraction(curve, ends)
            fraction = final / ceiling
            stranger = float(strangers[seed])
            well = (stranger >= UNSEEN_TARGET_FRACTION if np.isfinite(stranger)
                    else fraction >= TARGET_FRACTION)
            rows.append((c.name, c.n_objects, seed, round(final, 3), round(fraction, 3), steps,
                         round(steps / moves_per_min, 1), round(stranger, 3),
                         bool(steps <= TARGET_STEPS and well)))
    return Table(columns, rows)


def speed_points(table: Table) -> dict[str, np.ndarray]:
    """{condition: (seeds, 2) of (steps to 90% of final, fraction of the ceiling)} of a table.

    The fraction is the one the target judges: on unseen caregivers, frozen, where measured;
    else the final success's.
    """
    points: dict[str, list] = {}
    i = {c: table.columns.index(c) for c in ("condition", "steps_to_90pct_of_final",
                                             "fraction_of_ceiling",
                                             "unseen_caregivers_fraction")}
    for row in table.rows:
        unseen = float(row[i["unseen_caregivers_fraction"]])
        points.setdefault(str(row[i["condition"]]), []).append(
            (float(row[i["steps_to_90pct_of_final"]]),
             unseen if np.isfinite(unseen) else float(row[i["fraction_of_ceiling"]])))
    return {name: np.array(p) for name, p in points.items()}
