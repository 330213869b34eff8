"""The robot's mechanisms: Eq. 1-3, the learning module and the gate."""

from __future__ import annotations

import copy

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from jointattention.agent.attention import attended_object, most_interesting, visual_feedback
from jointattention.agent.detections import Detections
from jointattention.agent.face_standardiser import FaceStandardiser
from jointattention.agent.gates import ConstantGate, SigmoidGate
from jointattention.agent.protocol import Agent, Body, Outcome
from jointattention.config import AgentConfig
from jointattention.models.bootstrap import BootstrapAgent, BootstrapOptions
from jointattention.models.network.learner import LearningModule


def _det(centres, areas=None, edges=None, motion=None) -> Detections:
    c = np.asarray(centres, float).reshape(-1, 2)
    n = len(c)
    z = np.zeros(n)
    return Detections(c, z + 1 if areas is None else np.asarray(areas, float),
                      z if edges is None else np.asarray(edges, float),
                      z if motion is None else np.asarray(motion, float), (321, 241))


def test_eq1_picks_the_weighted_most_interesting_object():
    """Eq. 1: colour area alone with (1,0,0); edges decide with (0,1,0); nothing seen: None."""
    det = _det([[10, 10], [20, 20]], areas=[50, 10], edges=[0.1, 0.9])
    assert most_interesting(det, (1, 0, 0)) == 0
    assert most_interesting(det, (0, 1, 0)) == 1
    assert most_interesting(_det(np.zeros((0, 2))), (1, 0, 0)) is None


def test_eq2_turns_toward_the_object():
    """Eq. 2: an object right of and below the centre gives pan > 0 and tilt < 0 (down)."""
    det = _det([[200, 150]])  # centre is (160, 120)
    dtheta = visual_feedback(det, 0, 0.01)
    np.testing.assert_allclose(dtheta, [0.4, -0.3])


def test_eq3_fires_only_inside_the_threshold():
    """Eq. 3: the evaluator fires for the nearest object within d_th, else not."""
    det = _det([[160 + 30, 120], [160, 120 + 12]])
    assert attended_object(det, d_th_px=20) == 1
    assert attended_object(det, d_th_px=10) is None


def test_learning_module_learns_a_mapping():
    """partial_fit on a smooth 2-D mapping lowers the error tenfold."""
    rng = np.random.default_rng(0)
    X = rng.normal(size=(200, 10))
    Y = np.tanh(X[:, :2] @ np.array([[0.8, -0.3], [0.2, 0.5]]))
    net = LearningModule(10, 7, 2, learning_rate=0.01, rng=np.random.default_rng(1))
    before = np.mean((net.predict(X) - Y) ** 2)
    for _ in range(100):
        net.partial_fit(X, Y)
    assert np.mean((net.predict(X) - Y) ** 2) < before / 10
    assert net.predict(X[:3]).shape == (3, 2)


def test_face_standardiser_matches_numpy():
    """Running mean and s.d. equal numpy's over the faces seen."""
    faces = np.random.default_rng(0).integers(0, 255, (50, 12)).astype(float)
    st_ = FaceStandardiser(min_std=0).partial_fit(faces[:20]).partial_fit(faces[20:])
    np.testing.assert_allclose(st_.transform(faces), (faces - faces.mean(0)) / faces.std(0))


@given(t=st.lists(st.floats(0, 1e6), min_size=2, max_size=20))
def test_sigmoid_gate_is_a_rising_rate(t):
    """The sigmoid gate's rate lies in [0, 1] and never falls with learning time."""
    t = np.sort(t)
    r = SigmoidGate(midpoint_steps=1e5, width_steps=2e4).rate_at(t)
    assert np.all((r >= 0) & (r <= 1)) and np.all(np.diff(r) >= 0)


def test_hypothesis_keeps_no_deadline_in_this_suite():
    """Hypothesis runs with conftest's profile: no deadline for a slow first example."""
    assert settings.default.deadline is None
    assert HealthCheck.too_slow in settings.default.suppress_health_check


def test_gate_values():
    """The sigmoid is 0.5 at its midpoint; a constant gate is constant."""
    assert SigmoidGate(midpoint_steps=1e5, width_steps=2e4).rate_at(1e5) == pytest.approx(0.5)
    assert np.all(ConstantGate(rate=0.7).rate_at([0, 1e5, 3e5]) == 0.7)
    assert ConstantGate(rate=0.7).label == "constant 0.7" and SigmoidGate().label == "sigmoid"


def _agent(**changes) -> BootstrapAgent:
    body = Body(image_size_px=(321, 241), joint_limits_rad=((-1, 1), (-1, 1)),
                face_size_px=(3, 2))
    return BootstrapOptions(**changes).build(AgentConfig(), body, np.random.default_rng(0))


def test_the_bootstrap_agent_is_an_agent():
    """The paper's agent meets the Agent protocol the trial loop is written against."""
    assert isinstance(_agent(), Agent)


@pytest.mark.parametrize("target", ["final_direction", "object_direction", "executed_step"])
def test_each_learning_target_teaches_its_direction(target):
    """A fired trial teaches the direction its learning target names.

    The unit direction to the final gaze, to the attended object (final gaze plus the visual
    controller's centring command), or of the executed step: the network learns as one
    ``partial_fit`` toward it of a copy does (the module's compiled ``learn`` kernel).
    """
    agent = _agent(learning_target=target, gate=ConstantGate(rate=1.0))
    agent.begin_trial(np.zeros((2, 3)), [0.5, 0.2])
    twin = copy.deepcopy(agent.learner)
    step, _ = agent.act(_det(np.zeros((0, 2))), [0.5, 0.2])
    end = np.array([0.0, 0.3])
    agent.end_trial(Outcome(True, end, _det([[160 + 20, 120]]), 0))  # the object: 20 px right
    aim = {"final_direction": end, "executed_step": step,
           "object_direction": end + [20 * agent.mechanisms.vf_gain_rad_per_px, 0]}[target]
    if target != "executed_step":
        aim = aim - [0.5, 0.2]
    face_x = agent.faces.transform(np.zeros(6))
    scaled = (np.array([0.5, 0.2]) - agent.theta_mid_rad) / agent.theta_half_rad
    twin.partial_fit(np.concatenate([face_x, scaled])[None], (aim / np.hypot(*aim))[None],
                     shared_inputs=len(face_x))
    assert agent.learner.n_updates_ == twin.n_updates_ == 1
    for learned, expected in zip(agent.learner._params(), twin._params(), strict=True):
        np.testing.assert_allclose(learned, expected, rtol=1e-12, atol=1e-15)


def test_a_trial_that_did_not_fire_teaches_nothing():
    """Trials ending without the evaluator firing give no learning data."""
    agent = _agent()
    agent.begin_trial(np.zeros((2, 3)), [0.0, 0.0])
    agent.act(_det(np.zeros((0, 2))), [0.0, 0.0])
    assert agent.end_trial(Outcome(False, np.array([0.1, 0.0]), _det(np.zeros((0, 2))), None)) == 0


@pytest.mark.parametrize(("rate", "learn_from", "teaches"), [
    (1.0, "every", True), (1.0, "vf", False), (0.0, "vf", True)])
def test_learn_from_vf_teaches_only_trials_the_visual_controller_ended(rate, learn_from, teaches):
    """learn_from = "vf": a trial whose last move the module made teaches nothing."""
    agent = _agent(learn_from=learn_from, gate=ConstantGate(rate=rate))
    agent.begin_trial(np.zeros((2, 3)), [0.0, 0.0])
    agent.act(_det([[160 + 40, 120]]), [0.0, 0.0])  # rate 0: the visual controller moves
    fired = Outcome(True, np.array([0.1, 0.0]), _det([[160 + 5, 120]]), 0)
    assert (agent.end_trial(fired) > 0) is teaches


def test_n_passes_repeats_the_updates_of_a_trial():
    """n_passes = 3 makes three back-propagation passes over the same samples."""
    counts = []
    for n_passes in (1, 3):
        agent = _agent(n_passes=n_passes, gate=ConstantGate(rate=1.0))
        agent.begin_trial(np.zeros((2, 3)), [0.0, 0.0])
        for _ in range(4):
            agent.act(_det(np.zeros((0, 2))), [0.0, 0.0])
        taught = agent.end_trial(Outcome(True, np.array([0.1, 0.0]), _det([[170, 120]]), 0))
        counts.append((taught, agent.learner.n_updates_))
    assert counts == [(4, 4), (4, 12)]


@given(st.floats(-np.pi, np.pi), st.integers(1, 20))
def test_bias_is_one_for_one_direction_and_zero_for_opposite_pairs(angle, n):
    """The bias of the module's outputs: 1 if they all point one way, 0 for opposite pairs."""
    from jointattention.experiment.probes import bias_of

    u = np.tile([np.cos(angle), np.sin(angle)], (n, 1)) * np.arange(1, n + 1)[:, None]
    assert bias_of(u) == pytest.approx(1.0)
    assert bias_of(np.vstack([u, -u])) == pytest.approx(0.0, abs=1e-9)
