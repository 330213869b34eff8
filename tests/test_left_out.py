"""Beyond the paper: the memory leaves out of a face's recalls a place it found empty."""

from __future__ import annotations

import dataclasses
import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from jointattention import run_cell
from jointattention.agent.detections import Detections
from jointattention.agent.gates import EvidenceGate, SigmoidGate
from jointattention.agent.protocol import Body
from jointattention.config import AgentConfig, ConditionConfig, Config, ExperimentConfig
from jointattention.errors import ArgumentError, ConfigError
from jointattention.models.bootstrap import BootstrapOptions
from jointattention.models.memory._left_out import (
    drop_left_out_from,
    empty_arrival,
    leave_out,
    left_out_of,
    passed_over_into,
)
from jointattention.models.memory.episodic import EpisodicMemory
from jointattention.models.memory.options import MemoryOptions

LIMITS = ((-1.0, 1.0), (-0.7, 0.6))
BODY = Body(image_size_px=(320, 240), joint_limits_rad=LIMITS, face_size_px=(4, 3))
OPTIONS = BootstrapOptions(learner="memory", vf_fallback="sweep",
                           memory=MemoryOptions(leave_out_empty=True),
                           gate=EvidenceGate(floor_trials=2.0, half_trials=0.1))
LEAVE_OUT = {"learner": "memory", "vf_fallback": "sweep", "memory": {"leave_out_empty": True},
             "gate": {"kind": "evidence", "floor_trials": 2.0, "half_trials": 0.1}}


def _memory(**options) -> EpisodicMemory:
    options = {"leave_out_empty": True, **options}
    return EpisodicMemory(12, MemoryOptions(**options), LIMITS, np.random.default_rng(0))


def _two_places_memory():
    """A face whose trials found an object at A (4 times), at B (3) and at C (2).

    Another face's trials, at other places, set the base rate; a recall weighs the 9 trials
    nearest (the face's own).
    """
    memory, face = _memory(k_nearest=9), np.arange(12.0)
    places = np.array([[0.5, 0.1]] * 4 + [[-0.4, -0.2]] * 3 + [[0.1, 0.4]] * 2)
    memory.partial_fit(np.tile(face, (9, 1)), places)
    memory.partial_fit(np.tile(face[::-1], (9, 1)), np.column_stack(
        [np.linspace(-0.9, 0.9, 9), np.full(9, -0.5)]))
    return memory, memory.code(face), places[[0, 4, 7]]


def test_a_place_left_out_gives_way_to_the_next_and_then_to_nothing():
    """A, then B, then C is recalled as each before is left out; then nothing is."""
    memory, code, (a, b, c) = _two_places_memory()
    for place in (a, b, c):
        aim, support = memory.recall(code)
        assert np.allclose(aim, place) and support > 0
        memory.leave_out(code, aim)
    assert memory.recall(code) == (None, -1.0) and memory.n_left_ == 3
    assert memory.recall_evidence(code)[2] == 0.0


def test_another_face_still_recalls_a_place_left_out_of_one_face():
    """Places are left out per face code: a different face recalls A as before."""
    memory, code, (a, _, _) = _two_places_memory()
    other = memory.code(np.arange(12.0) + 0.5)
    memory.leave_out(code, a)
    assert np.allclose(memory.recall(other)[0], a)


def test_a_memory_that_leaves_nothing_out_refuses_to_with_one_line():
    """leave_out on a memory without the option is a clear error, not a silent no-op."""
    memory = EpisodicMemory(12, MemoryOptions(), LIMITS, np.random.default_rng(0))
    with pytest.raises(ArgumentError, match=r"expected memory\.leave_out_empty = true"):
        memory.leave_out(np.zeros(32), (0.0, 0.0))


def test_the_ring_of_left_out_places_forgets_the_oldest():
    """With capacity 2, a third place left out replaces the first."""
    codes, aims = np.zeros((3, 2)), np.zeros((2, 2))
    code = np.array([1.0, 2.0, 3.0])
    n = 0
    for pan in (0.1, 0.2, 0.3):
        n = leave_out(code, pan, 0.0, codes, aims, n)
    assert n == 3
    assert sorted(left_out_of(code, codes, aims, n)[:, 0]) == [0.2, 0.3]
    assert len(left_out_of(code + 1.0, codes, aims, n)) == 0


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 10_000), n_left=st.integers(0, 5))
def test_a_recalled_place_is_never_near_a_place_left_out(seed, n_left):
    """Whatever is left out, the recall lies outside the voting radius of each such place."""
    rng = np.random.default_rng(seed)
    memory, faces = _memory(), rng.uniform(0, 255, (3, 12))
    spots = np.column_stack([np.linspace(-0.9, 0.9, 8), rng.uniform(-0.6, 0.5, 8)])
    which = rng.integers(0, 8, 60)  # places apart by more than two radii, each found often
    memory.partial_fit(faces[rng.integers(0, 3, 60)], spots[which])
    code = memory.code(faces[0])
    plain = memory.recall_evidence(code)
    for place in spots[rng.permutation(8)[:n_left]]:
        memory.leave_out(code, place)
    aim, support, evidence = memory.recall_evidence(code)
    if n_left == 0:
        assert np.array_equal(aim, plain[0]) and (support, evidence) == plain[1:]
    if aim is not None:
        gaps = np.linalg.norm(memory.left_out(code) - aim, axis=1)
        assert (gaps >= memory.radius_rad).all()
    else:  # every place left out (-1, 0), or the best one below the base rate
        assert support < 0 and evidence <= 0.0


def _det(centres) -> Detections:
    centres = np.asarray(centres, dtype=float).reshape(-1, 2)
    n = len(centres)
    return Detections(centres, np.ones(n), np.zeros(n), np.zeros(n), (321, 241))


def test_the_head_finds_the_recalled_place_empty_only_there_and_with_nothing_near():
    """Within a step of the place, no object within the radius: empty; otherwise not."""
    step, r = 0.07, 14.0
    assert empty_arrival(0.3, 0.1, 0.33, 0.1, step, np.empty((0, 2)), 160, 120, r)
    assert empty_arrival(0.3, 0.1, 0.3, 0.1, step, np.array([[160.0, 140.0]]), 160, 120, r)
    assert not empty_arrival(0.3, 0.1, 0.3, 0.1, step, np.array([[165.0, 110.0]]), 160, 120, r)
    assert not empty_arrival(0.3, 0.1, 0.4, 0.1, step, np.empty((0, 2)), 160, 120, r)


def test_recalling_again_goes_on_to_the_face_s_next_place_with_its_evidence():
    """With recall_again, the place found empty (A) gives way at once to the next (B)."""
    for again in (True, False):
        options = dataclasses.replace(OPTIONS, memory=MemoryOptions(
            leave_out_empty=True, recall_again=again))
        agent = options.build(AgentConfig(), BODY, np.random.default_rng(0))
        agent.module.memory, _, (a, b, _) = _two_places_memory()
        agent.begin_trial(np.arange(12.0).reshape(3, 4), (0.0, 0.0))
        assert np.allclose(agent.module._aim_rad, a)
        agent.act(_det([]), a)  # the head reached A: nothing there
        aim, evidence = agent.module._aim_rad, agent.module.evidence_
        assert agent.module.memory.n_left_ == 1
        assert (np.allclose(aim, b) and evidence > 0) if again else (aim is None and evidence == 0)


def test_the_agent_leaves_out_a_recalled_place_only_while_learning():
    """MemoryModule.observe: the place goes, and the trial's evidence with it; frozen, nothing."""
    for learning in (True, False):
        agent = OPTIONS.build(AgentConfig(), BODY, np.random.default_rng(0))
        face = np.arange(12.0)
        memory = agent.module.memory
        memory.partial_fit(np.tile(face, (3, 1)), [[0.2, 0.1]] * 3)
        memory.partial_fit(np.tile(face[::-1], (3, 1)), [[-0.5, 0.3], [0.6, -0.4], [0.0, 0.5]])
        agent.learning = learning
        agent.begin_trial(face.reshape(3, 4), (0.0, 0.0))
        assert agent.module.evidence_ > 0
        agent.act(_det([]), (0.2, 0.1))
        assert (memory.n_left_ == 1) == learning
        assert (agent.module.evidence_ == 0.0) == learning


@pytest.mark.parametrize("name", ["pass_over_left_out", "drop_left_out", "recall_again"])
def test_acting_on_places_left_out_without_leaving_out_is_refused_with_one_line(name):
    """pass_over_left_out, drop_left_out and recall_again need leave_out_empty: one error."""
    with pytest.raises(ConfigError, match=rf"{name}.*leave_out_empty = true"):
        MemoryOptions(**{name: True})


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 10_000), n=st.integers(0, 6), n_left=st.integers(0, 3))
def test_dropping_keeps_exactly_the_places_away_from_those_left_out_in_order(seed, n, n_left):
    """drop_left_out_from leaves, in front and in order, the places outside every radius."""
    rng = np.random.default_rng(seed)
    places, radius = rng.uniform(-0.5, 0.5, (8, 2)), 0.1
    left = places[rng.integers(0, 8, n_left)] + rng.uniform(-0.15, 0.15, (n_left, 2))
    expected = [p.copy() for p in places[:n]
                if not (n_left and (np.linalg.norm(left - p, axis=1) < radius).any())]
    kept = drop_left_out_from(places, n, left, radius)
    assert kept == len(expected) and np.array_equal(places[:kept], np.reshape(expected, (-1, 2)))


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 10_000), n_left=st.integers(0, 4))
def test_attention_passes_over_exactly_the_objects_at_places_left_out(seed, n_left):
    """A detection is passed over iff Eq. 2 puts it within the radius of a place left out."""
    rng = np.random.default_rng(seed)
    gain, radius, pan, tilt = 0.003, 0.035, rng.uniform(-0.5, 0.5), rng.uniform(-0.3, 0.3)
    centres = rng.uniform((0, 0), (320, 240), (8, 2))
    places = np.column_stack([pan + gain * (centres[:, 0] - 159.5),
                              tilt - gain * (centres[:, 1] - 119.5)])
    left = places[:n_left] + rng.uniform(-1.2, 1.2, (n_left, 2)) * radius  # near or not
    out = np.ones(8, dtype=bool)
    passed_over_into(centres, 159.5, 119.5, gain, pan, tilt, left, radius, out)
    d = np.linalg.norm(places[:, None] - left[None], axis=2) if n_left else np.full((8, 1), 9.0)
    assert np.array_equal(out, (d < radius).any(axis=1))


def _passing_over_agent(pass_over: bool):
    """An agent that always picks VF, with (0.1, 0.05) left out of face arange(12)'s recalls."""
    options = BootstrapOptions(
        learner="memory", vf_fallback="sweep", gate=SigmoidGate(midpoint_steps=1e9),
        memory=MemoryOptions(leave_out_empty=True, pass_over_left_out=pass_over))
    agent = options.build(AgentConfig(), BODY, np.random.default_rng(0))
    agent.module.memory.leave_out(agent.module.memory.code(np.arange(12.0)), (0.1, 0.05))
    agent.begin_trial(np.arange(12.0).reshape(3, 4), (0.0, 0.0))
    return agent


def test_visual_attention_passes_over_an_object_at_a_place_left_out_while_learning():
    """The most salient object lies at the place left out: attention takes the other one."""
    gain = AgentConfig().vf_gain_rad_per_px
    at_left_out = (160.0 + 0.1 / gain, 120.0 - 0.05 / gain)
    det = Detections(np.array([at_left_out, (60.0, 200.0)]), np.array([50.0, 10.0]),
                     np.zeros(2), np.zeros(2), (321, 241))
    for pass_over, learning, attended in ((True, True, 1), (True, False, 0), (False, True, 0)):
        agent = _passing_over_agent(pass_over)
        agent.learning = learning
        d_theta, module = agent.act(det, (0.0, 0.0))
        expected = gain * (det.centre_px[attended] - (160.0, 120.0)) * (1, -1)
        assert module == "vf" and np.allclose(d_theta, expected), (pass_over, learning)


CONFIG = Config(model=BootstrapOptions(gate=SigmoidGate(midpoint_steps=1500.0, width_steps=500.0)),
                experiment=ExperimentConfig(n_steps=10_000, n_seeds=1, conditions=(
                    ConditionConfig(name="leave-out", n_objects=10, model=LEAVE_OUT),
                    ConditionConfig(name="leave-out-forgets", n_objects=5, model={
                        **LEAVE_OUT, "gate_per": "trial",
                        "memory": {"leave_out_empty": True, "capacity": 30}}),
                    ConditionConfig(name="pass-over", n_objects=10, model={
                        **LEAVE_OUT, "memory": {"leave_out_empty": True,
                                                "pass_over_left_out": True}}),
                    ConditionConfig(name="pass-over-drop", n_objects=10, model={
                        **LEAVE_OUT, "memory": {"leave_out_empty": True, "pass_over_left_out": True,
                                                "drop_left_out": True}}),
                    ConditionConfig(name="recall-again", n_objects=10, model={
                        **LEAVE_OUT, "memory": {"leave_out_empty": True, "pass_over_left_out": True,
                                                "recall_again": True}}))))


@pytest.mark.parametrize("name", ["leave-out", "leave-out-forgets", "pass-over", "pass-over-drop",
                                  "recall-again"])
def test_both_engines_leave_out_the_same_places_and_run_the_same_trials(name):
    """The compiled engine's records and places left out are the python engine's, bit for bit."""
    ends = {}
    for engine in ("compiled", "python"):
        config = dataclasses.replace(CONFIG, experiment=dataclasses.replace(
            CONFIG.experiment, engine=engine))
        condition = next(c for c in config.experiment.conditions if c.name == name)
        agents = []
        records = run_cell(config, condition, 0, checkpoints=[10_000],
                           on_checkpoint=lambda t, a, agents=agents: agents.append(a))
        ends[engine] = records, agents[-1].module.memory
    (rc, mc), (rp, mp) = ends["compiled"], ends["python"]
    for key in rc:
        assert np.array_equal(rc[key], rp[key], equal_nan=True), key
    assert mc.n_left_ == mp.n_left_ > 0
    assert np.array_equal(mc.left_aims_, mp.left_aims_)
    assert np.array_equal(mc.left_codes_, mp.left_codes_)


@pytest.mark.parametrize("names", [("leave-out", "pass-over", "pass-over-drop"),
                                   ("pass-over", "recall-again")])
def test_passing_over_dropping_and_recalling_again_change_the_cells_the_engines_agree_on(names):
    """The parity cells exercise each option: each changes the trials of the cell before."""
    config = dataclasses.replace(CONFIG, experiment=dataclasses.replace(
        CONFIG.experiment, engine="compiled"))
    cells = [run_cell(config, next(c for c in config.experiment.conditions if c.name == n), 0)
             for n in names]
    for before, after in itertools.pairwise(cells):
        assert not np.array_equal(before["attended"], after["attended"])
