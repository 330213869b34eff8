"""The bench's bounds: the loops it times alone do the learning modules' own arithmetic."""

from __future__ import annotations

import copy
import dataclasses
import math

import numpy as np
import pytest

from jointattention.config import load_config
from jointattention.datasets import default_datasets
from jointattention.experiment.cells import run_cell
from jointattention.jobs.bounds import _memory_starts, _population_trials, learner_cell_rows


def _condition(config, condition: dict | str):
    """The preset's condition of that name, or its first with ``condition`` as the model."""
    conditions = config.experiment.conditions
    if isinstance(condition, str):
        return next(c for c in conditions if c.name == condition)
    return dataclasses.replace(conditions[0], model=condition)


def _learned(preset: str, condition: dict | str, n_steps: int):
    """The agent of a cell of ``preset`` after ``n_steps`` of learning."""
    config = load_config(preset)
    config = dataclasses.replace(
        config, experiment=dataclasses.replace(config.experiment, n_steps=n_steps))
    ended = []
    run_cell(config, _condition(config, condition), 0, checkpoints=[n_steps],
             on_checkpoint=lambda t, a: ended.append(a))
    return ended[-1]


def test_the_memory_bound_recalls_what_the_memory_recalls():
    """The timed start loop's recalls are the module's: the same supports, face by face."""
    agent = _learned("beyond", "memory-n5", 4000)
    memory, ds = agent.module.memory, default_datasets()
    faces = np.ascontiguousarray(ds.face.reshape(len(ds), -1)[:20], dtype=float)
    assert memory.n_stored_ > 0
    expected = sum(memory.recall(memory.code(f))[1] for f in faces)
    total = _memory_starts(faces, memory.projection, *memory.kept_arrays(), memory.lo_rad,
                           memory.cell_rad, memory.options.k_nearest, memory.radius_rad,
                           *memory.left_arrays())
    assert total == pytest.approx(expected, rel=1e-12) and expected > 0


def test_the_population_bound_reads_out_what_the_module_reads_out():
    """The timed loop's directions are the module's own, for each face (nothing skipped)."""
    model = {"learner": "population", "vf_fallback": "sweep"}
    agent = _learned("quick", model, 3000)
    ds = default_datasets()
    faces = np.ascontiguousarray(ds.face.reshape(len(ds), -1)[:10], dtype=float)
    thetas = np.ascontiguousarray(ds.theta_face_rad[:10], dtype=float)
    module = copy.deepcopy(agent.module)
    agent.learning = False
    expected = 0.0
    for face, theta in zip(faces, thetas, strict=True):
        agent.module.begin(face, theta)
        expected += agent.module.direction_rad_
    total = _population_trials(module.arrays(), faces, thetas, thetas, np.random.default_rng(0),
                               False)
    assert total == pytest.approx(expected, rel=1e-12) and math.isfinite(total)


@pytest.mark.parametrize(("preset", "condition"), [
    ("beyond", "memory-n5"), ("quick", {"learner": "population", "vf_fallback": "sweep"}),
    ("models", "rl-n5")])
def test_the_bench_prints_each_learner_s_bound_and_its_share_of_the_cell(preset, condition):
    """Each learner's rows: a start and an end in microseconds, and a share of the cell's time."""
    config = load_config(preset)
    rate, rows = learner_cell_rows(config, _condition(config, condition), 3000)
    assert rate > 0 and [unit for _, _, unit in rows] == ["us", "us", "x"]
    assert all(math.isfinite(v) and v > 0 for _, v, _ in rows)
