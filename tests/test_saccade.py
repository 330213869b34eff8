"""Beyond the paper: the memory moves to its recalled place in one move (``memory.saccade``)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from jointattention import run_cell
from jointattention.agent.attention import largest_feedback_rad, visual_feedback_rad
from jointattention.agent.moves import place_step
from jointattention.config import ConditionConfig, Config, ExperimentConfig
from jointattention.models.bootstrap import BootstrapOptions
from jointattention.models.memory.options import MemoryOptions

ANGLE = st.floats(-2.0, 2.0)
MEMORY = {"learner": "memory", "vf_fallback": "sweep",
          "gate": {"kind": "evidence", "floor_trials": 1.5, "half_trials": 0.05},
          "memory": {"leave_out_empty": True, "pass_over_left_out": True, "recall_again": True}}
SACCADE = {**MEMORY, "memory": {**MEMORY["memory"], "saccade": True}}
CONFIG = Config(model=BootstrapOptions(), experiment=ExperimentConfig(
    n_steps=6_000, n_seeds=1, conditions=(
        ConditionConfig(name="steps", n_objects=10, model=MEMORY),
        ConditionConfig(name="saccade", n_objects=10, model=SACCADE))))


@settings(deadline=None)  # the first example compiles the kernel
@given(ANGLE, ANGLE, st.floats(0.01, 0.2), st.floats(0.05, 1.0))
def test_a_saccade_lands_on_the_place_within_reach_and_stops_at_its_reach_beyond(
        d_pan, d_tilt, step_rad, saccade_rad):
    """A saccade goes the whole way within reach, else reach-long toward the place."""
    move = np.array(place_step(d_pan, d_tilt, step_rad, saccade_rad))
    distance = math.hypot(d_pan, d_tilt)
    if distance <= saccade_rad:
        assert np.array_equal(move, [d_pan, d_tilt])
    else:
        assert np.hypot(*move) == pytest.approx(saccade_rad)
        assert move @ [d_pan, d_tilt] == pytest.approx(saccade_rad * distance)


@settings(deadline=None)
@given(ANGLE, ANGLE, st.floats(0.01, 0.2))
def test_without_a_saccade_the_move_is_one_step_toward_the_place(d_pan, d_tilt, step_rad):
    """saccade_rad 0: one step of step_rad toward the place, even past it."""
    assume(math.hypot(d_pan, d_tilt) > 1e-9)
    move = np.array(place_step(d_pan, d_tilt, step_rad, 0.0))
    assert np.hypot(*move) == pytest.approx(step_rad)
    assert move @ [d_pan, d_tilt] >= 0


def test_the_longest_saccade_is_visual_feedback_s_move_to_an_image_corner():
    """largest_feedback_rad is Eq. 2's move to an object at the image's corner pixel."""
    cx, cy = (320 - 1) / 2, (240 - 1) / 2
    assert largest_feedback_rad(320, 240, 0.0025) == pytest.approx(
        math.hypot(*visual_feedback_rad(0.0, 0.0, cx, cy, 0.0025)))


def _cells(engine):
    config = dataclasses.replace(CONFIG, experiment=dataclasses.replace(
        CONFIG.experiment, engine=engine))
    agents, cells = [], {}
    for condition in config.experiment.conditions:
        cells[condition.name] = run_cell(config, condition, 0, checkpoints=[6_000],
                                         on_checkpoint=lambda t, a: agents.append(a))
    return cells, agents[-1]


def test_both_engines_run_the_same_saccading_trials_which_are_shorter():
    """With saccade both engines' records agree bit for bit; its trials take fewer steps."""
    (compiled, _), (python, _) = _cells("compiled"), _cells("python")
    for key in compiled["saccade"]:
        assert np.array_equal(compiled["saccade"][key], python["saccade"][key],
                              equal_nan=True), key
    steps, saccade = compiled["steps"], compiled["saccade"]
    assert saccade["n_steps"].mean() < 0.7 * steps["n_steps"].mean()


def test_the_saccading_memory_commands_the_whole_way_to_a_place_within_reach():
    """The commands (follow's) move from each head angle onto the recalled place, or reach-long."""
    _, agent = _cells("compiled")
    module, memory = agent.module, agent.module.memory
    assert isinstance(memory.options, MemoryOptions) and memory.options.saccade
    rng = np.random.default_rng(0)
    faces = rng.uniform(0, 255, (40, memory.projection.shape[0]))
    thetas = rng.uniform(-0.5, 0.5, (40, 2))
    moves = module.commands(faces, thetas)
    for face, theta, move in zip(faces, thetas, moves, strict=True):
        aim, _ = memory.recall(memory.code(face))
        assert aim is not None
        want = np.array(place_step(*(aim - theta), agent.step_rad, module.saccade_rad))
        assert np.array_equal(move, want)
    reach = np.hypot(*moves.T)
    assert reach.max() <= module.saccade_rad + 1e-12 and reach.max() > 3 * agent.step_rad
