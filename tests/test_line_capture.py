"""Beyond the paper: a line followed lands on the first object along it (``line_capture_deg``)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from jointattention import run_cell
from jointattention.agent.attention import visual_feedback_rad
from jointattention.agent.moves import line_capture
from jointattention.agent.options import AgentConfig
from jointattention.config import ConditionConfig, Config, ExperimentConfig
from jointattention.errors import ConfigError
from jointattention.models.bootstrap import BootstrapOptions

GAIN, CX, CY = 0.0025, 159.5, 119.5
POPULATION = {"learner": "population", "vf_fallback": "sweep",
              "gate": {"kind": "constant", "rate": 0.8},
              "population": {"replay_capacity": 500, "unfound": True}}


def _config(capture_deg: float, engine: str = "compiled", n_steps: int = 3_000) -> Config:
    return Config(agent=AgentConfig(lm_step_deg=10.0, line_capture_deg=capture_deg),
                  model=BootstrapOptions(), experiment=ExperimentConfig(
                      n_steps=n_steps, n_seeds=1, engine=engine, conditions=(
                          ConditionConfig(name="n10", n_objects=10, model=POPULATION),)))


def _place(x_px, y_px, pan, tilt):
    v = visual_feedback_rad(x_px, y_px, CX, CY, GAIN)
    return pan + v[0], tilt + v[1]


PIXELS = st.lists(st.tuples(st.floats(0, 319), st.floats(0, 239)), min_size=0, max_size=8)


@settings(deadline=None)  # the first example compiles the kernel
@given(PIXELS, st.floats(-0.3, 0.3), st.floats(-0.3, 0.3), st.floats(0, 2 * math.pi),
       st.floats(0.01, 0.3))
def test_the_capture_is_the_nearest_along_the_line_of_the_objects_near_it(
        pixels, d_pan, d_tilt, psi, capture_rad):
    """The object picked lies ahead within reach of the line, and none such lies nearer along it."""
    centre = np.array(pixels, dtype=float).reshape(-1, 2)
    pan, tilt, u = 0.1 + d_pan, -0.05 + d_tilt, (math.cos(psi), math.sin(psi))
    i = line_capture(centre, CX, CY, GAIN, pan, tilt, 0.1, -0.05, 3 * u[0], 3 * u[1],
                     capture_rad)

    def along_across(j):
        p = np.subtract(_place(*centre[j], pan, tilt), (0.1, -0.05))
        return p @ u, abs(p[0] * u[1] - p[1] * u[0])

    near = [j for j in range(len(centre))
            if along_across(j)[0] > 0 and along_across(j)[1] <= capture_rad]
    if not near:
        assert i == -1
    else:
        assert i in near
        assert along_across(i)[0] == min(along_across(j)[0] for j in near)


def test_no_direction_captures_nothing():
    """A line of no direction has nothing along it."""
    assert line_capture(np.array([[CX, CY]]), CX, CY, GAIN, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
                        1.0) == -1


def test_the_capture_is_refused_outside_its_range():
    """A negative or a half-turn capture distance is a configuration error."""
    for bad in (-1.0, 91.0):
        with pytest.raises(ConfigError, match="line_capture_deg"):
            AgentConfig(line_capture_deg=bad)


def test_both_engines_run_the_same_capturing_trials():
    """With a capture both engines' records agree bit for bit, and differ from the line's."""
    cells = {}
    for engine in ("compiled", "python"):
        for capture in (0.0, 5.0):
            config = _config(capture, engine)
            cells[engine, capture] = run_cell(config, config.experiment.conditions[0], 0)
    for key in cells["compiled", 5.0]:
        assert np.array_equal(cells["compiled", 5.0][key], cells["python", 5.0][key],
                              equal_nan=True), key
    steps, captured = cells["compiled", 0.0], cells["compiled", 5.0]
    assert not np.array_equal(captured["n_steps"], steps["n_steps"][:len(captured["n_steps"])])


def _oracle_trials(capture_deg: float, n_trials: int = 200):
    """OracleAgent's wins and steps over the ceiling's trials, and the compiled loop's wins."""
    from jointattention.datasets import default_datasets
    from jointattention.experiment.cells import evaluator, oracle_wins, random_scene
    from jointattention.experiment.oracle import OracleAgent
    from jointattention.experiment.trial import SceneTrial, run_trial
    from jointattention.rng import stream
    from jointattention.world.kinematics import HeadKinematics

    ds, config = default_datasets(), _config(capture_deg)
    kin, step = HeadKinematics.from_config(config.world), np.deg2rad(config.agent.lm_step_deg)
    rng, wins, steps = stream(3, "ceiling", 10), 0, 0
    for _ in range(n_trials):
        k, scene, _ = random_scene(config, ds, kin, 10, rng)
        trial = SceneTrial(scene, ds.theta_face_rad[k], kinematics=kin,
                           max_steps=config.agent.max_steps, evaluate=evaluator(config))
        oracle = OracleAgent(ds.theta_face_rad[k] + ds.command_rad[k], step,
                             np.deg2rad(capture_deg), config.agent.vf_gain_rad_per_px)
        wins += run_trial(trial, oracle, ds.face[k]).success
        steps += oracle.learning_time_steps
    compiled = stream(3, "ceiling", 10)
    compiled_wins = oracle_wins(ds, config, 10, n_trials, compiled)
    assert compiled.random() == rng.random()  # the same draws, to the last
    return wins, steps, compiled_wins


def test_the_ceiling_follows_the_capture_too():
    """The oracle's compiled trials and OracleAgent's agree with a capture, which shortens them."""
    wins, steps, compiled_wins = _oracle_trials(5.0)
    _, line_steps, _ = _oracle_trials(0.0)
    assert compiled_wins == wins and 0 < wins <= 200
    assert steps < line_steps
