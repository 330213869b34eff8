"""How fast each seed learns, and how well: steps to 90% of its final success, and that final.

The paper's future work asks for a robot that learns faster. A learner that hands control to
its module early may learn fast and end lower, so both are reported per seed, side by side
(``learning_speed.csv``/``.md``; the figure is
:func:`jointattention.figures.learning_speed.learning_speed_figure`). The issue's target, for a
learner that judges itself: 90% of its final success within 3x10^4 steps, and a final success
of at least 0.95 of the ceiling (:data:`TARGET_STEPS`, :data:`TARGET_FRACTION`).
"""

from __future__ import annotations

import numpy as np

from ..config import Config
from .metrics import final_success, time_to_fraction
from .tables import Table

__all__ = ["TARGET_FRACTION", "TARGET_STEPS", "learning_speed_table", "speed_points"]

TARGET_STEPS = 30_000  # steps to 90% of the final success, at most
TARGET_FRACTION = 0.95  # final success over the ceiling, at least


def learning_speed_table(config: Config, curves: dict, ceilings: dict[str, float]) -> Table:
    """One row per condition and seed: its final success, and how fast it got there.

    The final success (also as a fraction of the ceiling) and the learning time at which the
    seed's own curve first reaches 90% of it (NaN if never), also in minutes of a real head
    making ``experiment.head_moves_per_s`` moves a second; ``meets_target``: both within the
    targets above.

    ``curves``: {condition: (bin ends, per-seed curves)}
    (:func:`~.curves.condition_curves`); ``ceilings``: {str(n_objects): oracle success}.
    """
    columns = ("condition", "n_objects", "seed", "final_success", "fraction_of_ceiling",
               "steps_to_90pct_of_final", "real_head_minutes_to_90pct", "meets_target")
    moves_per_min = 60 * config.experiment.head_moves_per_s
    rows = []
    for c in config.experiment.conditions:
        ends, per_seed = curves[c.name]
        ceiling = ceilings.get(str(c.n_objects), float("nan"))
        for seed, curve in enumerate(per_seed):
            final = final_success(curve)
            steps = time_to_fraction(curve, ends)
            fraction = final / ceiling
            rows.append((c.name, c.n_objects, seed, round(final, 3), round(fraction, 3), steps,
                         round(steps / moves_per_min, 1),
                         bool(steps <= TARGET_STEPS and fraction >= TARGET_FRACTION)))
    return Table(columns, rows)


def speed_points(table: Table) -> dict[str, np.ndarray]:
    """{condition: (seeds, 2) of (steps to 90% of final, fraction of the ceiling)} of a table."""
    points: dict[str, list] = {}
    i = {c: table.columns.index(c) for c in ("condition", "steps_to_90pct_of_final",
                                             "fraction_of_ceiling")}
    for row in table.rows:
        points.setdefault(str(row[i["condition"]]), []).append(
            (float(row[i["steps_to_90pct_of_final"]]), float(row[i["fraction_of_ceiling"]])))
    return {name: np.array(p) for name, p in points.items()}
