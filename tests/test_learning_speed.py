"""Each seed's learning speed beside its final success: the table, the target, the figure."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from jointattention.analysis.learning_speed import learning_speed_table, speed_points
from jointattention.config import ConditionConfig, Config, ExperimentConfig

CONFIG = Config(experiment=ExperimentConfig(
    n_steps=100_000, n_seeds=2, bin_steps=10_000, conditions=(
        ConditionConfig(name="fast", n_objects=5), ConditionConfig(name="flat", n_objects=5))))
ENDS = CONFIG.experiment.bin_ends_steps()


def _curves():
    fast = np.array([[0.2, 0.85, *[0.9] * 8], [0.2, 0.5, 0.6, 0.7, 0.8, 0.85, *[0.9] * 4]])
    flat = np.zeros((2, 10))  # never above 0: its "90% of final" is reached at once
    flat[1, 3] = np.nan  # a bin without trials is skipped, not fatal
    return {"fast": (ENDS, fast), "flat": (ENDS, flat)}


def test_each_seed_gets_its_own_steps_to_90pct_and_final():
    """Per seed: the first bin end at 90% of that seed's final, and the final over the ceiling."""
    table = learning_speed_table(CONFIG, _curves(), {"5": 0.9})
    rows = {(r[0], r[2]): r for r in table.rows}
    assert rows[("fast", 0)][5] == 20_000 and rows[("fast", 1)][5] == 60_000
    assert rows[("fast", 0)][4] == 1.0 and rows[("flat", 0)][4] == 0.0
    assert math.isnan(rows[("fast", 0)][7])  # no held-out measure
    assert rows[("fast", 0)][8] is True  # 2x10^4 steps and the whole ceiling
    assert rows[("fast", 1)][8] is False  # 6x10^4 steps: too slow
    assert rows[("flat", 0)][8] is False  # fast to nothing: below 0.95 of the ceiling


def _held(unseen_success: list[float]) -> dict:
    """Held-out curves of the fast condition: 2 seeds x 3 kinds x 1 checkpoint."""
    success = np.full((2, 3, 1), 0.5)
    success[:, 2, 0] = unseen_success
    return {"fast": (np.array([100_000]), {"success": success})}


def test_the_target_judges_the_frozen_model_on_unseen_caregivers():
    """Where measured, the unseen caregivers' fraction is shown and judged at 0.9, not the final."""
    ceilings = {"unseen caregivers": {"5": 0.8}}
    table = learning_speed_table(CONFIG, _curves(), {"5": 0.9}, _held([0.6, 0.76]), ceilings)
    rows = {(r[0], r[2]): r for r in table.rows}
    assert rows[("fast", 0)][7] == 0.75 and rows[("fast", 1)][7] == 0.95
    assert rows[("fast", 0)][8] is False  # fast, the whole ceiling in training, 0.75 on strangers
    table = learning_speed_table(CONFIG, _curves(), {"5": 0.9}, _held([0.74, 0.76]), ceilings)
    assert table.rows[0][7] == 0.925 and table.rows[0][8] is True  # 0.925: above 0.9
    assert math.isnan(rows[("flat", 0)][7])  # not measured: its final stands in
    assert np.array_equal(speed_points(table)["fast"], [[20_000, 0.925], [60_000, 0.95]])


def test_steps_are_also_given_in_minutes_of_a_real_head():
    """The minutes column is the steps at ``experiment.head_moves_per_s`` moves a second."""
    slow = dataclasses.replace(CONFIG, experiment=dataclasses.replace(CONFIG.experiment,
                                                                      head_moves_per_s=2.0))
    for config, moves_per_s in ((CONFIG, 5.0), (slow, 2.0)):
        rows = {(r[0], r[2]): r for r in learning_speed_table(config, _curves(),
                                                              {"5": 0.9}).rows}
        assert rows[("fast", 1)][6] == round(60_000 / moves_per_s / 60, 1)


def test_the_figures_points_are_the_tables_rows(tmp_path):
    """speed_points reads the table back per condition; the figure is written."""
    from jointattention.figures.learning_speed import learning_speed_figure

    table = learning_speed_table(CONFIG, _curves(), {"5": 0.9})
    points = speed_points(table)
    assert sorted(points) == ["fast", "flat"]
    assert np.array_equal(points["fast"], [[20_000, 1.0], [60_000, 1.0]])
    path = learning_speed_figure(table, tmp_path / "speed.png")
    assert path.stat().st_size > 1000
    assert not math.isnan(points["flat"][0, 0])
