"""The reinforcement-learning model (Triesch et al. 2006): it learns, is controlled, is checked."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from jointattention.agent.detections import Detections
from jointattention.agent.protocol import LM, Body, Outcome
from jointattention.analysis.metrics import final_success
from jointattention.config import load_config, model_options
from jointattention.errors import ConfigError
from jointattention.experiment.cells import datasets_of, make_agent, run_cell
from jointattention.models.rl import STAY, RLAgent, RLOptions

SHORT = {"seed": 0, "model": {"kind": "rl"},
         "experiment": {"engine": "python", "n_steps": 30000, "n_seeds": 2, "bin_steps": 3000,
                        "n_ceiling_trials": 50, "conditions": [
                            {"name": "rl-n1", "n_objects": 1},
                            {"name": "rl-n5-shuffled", "n_objects": 5,
                             "shuffle_faces": True}]}}
BODY = Body((320, 240), ((-1.0, 1.0), (-0.8, 0.6)), (30, 25))
DET = Detections(np.array([[100.0, 120.0]]), np.array([400.0]), np.zeros(1), np.zeros(1),
                 (320, 240))
FACE = np.full((25, 30), 100, np.uint8)


def _final(records: dict) -> float:
    """Success over the last fifth of the trials."""
    return final_success(records["success"].astype(float), 0.2)


def _agent(**options) -> RLAgent:
    config = load_config({"model": {"kind": "rl", **options},
                          "experiment": {"engine": "python"}})
    return model_options(config, config.experiment.conditions[0]).build(
        config.agent, BODY, np.random.default_rng(0))


def _shift(agent: RLAgent, n_moves: int = 3, face: np.ndarray = FACE) -> None:
    """Begin a trial and act until the agent has shifted its gaze and made ``n_moves`` moves."""
    agent.begin_trial(face, np.zeros(2))
    while agent.act(DET, np.zeros(2))[1] != LM:
        pass
    for _ in range(n_moves - 1):
        assert agent.act(DET, np.zeros(2))[1] == LM


def test_rl_learns_on_one_object():
    """With 1 object the RL model rises from about 0.1 to above 0.6 in 3x10^4 steps.

    Its greedy shift direction comes within 15 deg of the caregiver's target.
    """
    config = load_config(SHORT)
    records = run_cell(config, config.experiment.conditions[0], 0)
    assert records["success"][:50].mean() < 0.3  # it starts by looking around (measured 0.08)
    assert _final(records) > 0.6  # measured 0.764 (defaults, about 2 s once compiled)
    assert records["lm_error_deg"][-1] < 15  # measured 4.8 deg (22.0 in the first bin)


def test_rl_with_shuffled_faces_stays_at_chance():
    """With faces shuffled the RL model has nothing to learn from: near or below chance (0.2)."""
    config = load_config(SHORT)
    assert _final(run_cell(config, config.experiment.conditions[1], 0)) <= 1.25 * 0.2  # 0.085


def test_rl_never_reads_the_caregivers_judgement():
    """``end_trial`` learns the same whether the caregiver approved the trial or not."""
    agent = _agent()
    agent.begin_trial(FACE, np.zeros(2))  # a first face, so that the next one stands out
    agent.end_trial(Outcome(False, np.zeros(2), DET, None))
    _shift(agent, face=np.random.default_rng(1).integers(0, 256, FACE.shape, np.uint8))
    learnt = []
    for approved in (True, False, None):
        twin = copy.deepcopy(agent)
        twin.end_trial(Outcome(True, np.array([0.1, 0.1]), DET, 0, approved=approved))
        learnt.append(twin)
    assert np.abs(learnt[0].W_).sum() > 0  # the trial taught the shift something
    for twin in learnt[1:]:
        for name in ("W_", "b_", "q_stay_", "place_habituation_"):
            np.testing.assert_array_equal(getattr(twin, name), getattr(learnt[0], name), name)


def test_staying_at_the_face_pays_less_each_step():
    """Looking at the caregiver habituates: each further step pays face_habituation times less.

    A trial spent looking at her to the step limit teaches the stay values the same order.
    """
    agent = _agent()
    rewards = [agent.stay_reward(k) for k in range(4)]
    assert rewards == pytest.approx([0.3, 0.15, 0.075, 0.0375])  # the defaults: 0.3 x 0.5^k
    agent.q_stay_[:] = 1.0  # staying pays so much more than any shift that it always stays
    agent.begin_trial(FACE, np.zeros(2))
    assert all(agent.act(DET, np.zeros(2))[1] == STAY for _ in range(agent.mechanisms.max_steps))
    agent.end_trial(Outcome(False, np.zeros(2), DET, None))
    assert np.all(np.diff(agent.q_stay_[:5]) < 0)  # measured 1.025, 1.01, 1.0025, 0.999, 0.997


def test_a_place_where_an_object_was_found_pays_less_next_time():
    """Finding an object habituates its place (not others); the place recovers trial by trial."""
    agent = _agent()
    here, there = np.array([0.1, 0.1]), np.array([-0.6, -0.5])
    assert agent.object_reward_at(here) == 1.0
    _shift(agent)
    agent.end_trial(Outcome(True, here, DET, 0))
    assert agent.object_reward_at(here) == pytest.approx(0.7)  # 1 - place_habituation
    assert agent.object_reward_at(there) == 1.0
    _shift(agent)
    agent.end_trial(Outcome(False, there, DET, None))  # nothing found: every place recovers
    assert agent.object_reward_at(here) == pytest.approx(1 - 0.3 * 0.9)


def test_rl_options_declare_readings_and_refuse_bad_values():
    """The readings are options; a value out of range is one ConfigError naming it."""
    assert set(RLOptions.readings) <= {f for f in RLOptions.__dataclass_fields__}
    with pytest.raises(ConfigError, match=r"model\.temperature"):
        load_config({"model": {"kind": "rl", "temperature": 0.0}})


def test_a_frozen_rl_agent_that_saw_no_face_is_refused_by_both_engines():
    """Frozen before any face: one error line in either engine (nothing to standardise by)."""
    from jointattention.errors import ArgumentError
    from jointattention.experiment.evaluate import frozen_success

    config = load_config(SHORT)
    ds = datasets_of(config)
    agent = make_agent(config, config.experiment.conditions[0], 0, ds)
    with pytest.raises(ArgumentError, match="seen no face"):
        frozen_success(agent, ds, config, 1, 10, 0)
    agent.learning = False
    with pytest.raises(ArgumentError, match="seen no face"):
        agent.begin_trial(ds.face[0], ds.theta_face_rad[0])
