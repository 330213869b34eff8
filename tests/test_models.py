"""The models beside the bootstrap model: the teacher and the developmental model, checked."""

from __future__ import annotations

from typing import ClassVar

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from jointattention.agent.detections import Detections
from jointattention.agent.protocol import Body, Outcome
from jointattention.analysis.claims import check_claims
from jointattention.analysis.metrics import final_success
from jointattention.config import load_config, model_options
from jointattention.errors import ConfigError
from jointattention.experiment.cells import run_cell
from jointattention.jobs.reproduce import run_experiment

SHORT = {"seed": 0, "model": {"gate": {"midpoint_steps": 25000.0, "width_steps": 5000.0}},
         "experiment": {"n_steps": 60000, "n_seeds": 2, "bin_steps": 5000,
                        "n_ceiling_trials": 50, "conditions": [
                            {"name": "teacher-n1", "n_objects": 1,
                             "model": {"kind": "teacher"}},
                            {"name": "teacher-n5-shuffled", "n_objects": 5,
                             "shuffle_faces": True, "model": {"kind": "teacher"}}]}}


def _final(records: dict) -> float:
    """Success over the last fifth of the trials."""
    return final_success(records["success"].astype(float), 0.2)


def test_teacher_learns_on_one_object():
    """With 1 object the teacher rises from about 0.1 to above 0.6 in 6x10^4 steps."""
    config = load_config(SHORT)
    records = run_cell(config, config.experiment.conditions[0], 0)
    assert records["success"][:50].mean() < 0.3  # it starts by wandering (measured 0.12)
    assert _final(records) > 0.6  # measured 0.72 (the quick preset's schedule)


def test_teacher_with_shuffled_faces_stays_at_chance():
    """With faces shuffled the teacher has nothing to learn from: near or below chance (0.2)."""
    config = load_config(SHORT)
    assert _final(run_cell(config, config.experiment.conditions[1], 0)) <= 1.25 * 0.2


def test_teacher_learns_only_from_approved_trials():
    """A trial the evaluator ended on another object teaches the teacher nothing."""
    config = load_config({"model": {"kind": "teacher"}})
    body = Body((320, 240), ((-1.0, 1.0), (-0.8, 0.6)), (30, 25))
    agent = model_options(config, config.experiment.conditions[0]).build(
        config.agent, body, np.random.default_rng(0))
    det = Detections(np.array([[100.0, 120.0]]), np.array([400.0]), np.zeros(1), np.zeros(1),
                     (320, 240))
    taught = []
    for approved in (False, True):
        agent.begin_trial(np.full((25, 30), 100, np.uint8), np.zeros(2))
        agent.act(det, np.zeros(2))
        taught.append(agent.end_trial(Outcome(True, np.zeros(2), det, 0, approved=approved)))
    assert taught[0] == 0 and taught[1] > 0


@pytest.mark.parametrize("kind", ["teacher", "developmental", "rl"])
def test_cells_do_not_depend_on_workers(tmp_path, kind):
    """Each neighbour's cells, learning and shuffled, are the same on 1 and 2 worker processes."""
    config = load_config({**SHORT, "experiment": {**SHORT["experiment"], "engine": "auto",
                                                  "n_steps": 3000, "bin_steps": 1000,
                                                  "conditions": [
        {"name": "n1", "n_objects": 1, "model": {"kind": kind}},
        {"name": "n5-shuffled", "n_objects": 5, "shuffle_faces": True,
         "model": {"kind": kind}}]}})
    one = run_experiment(config, tmp_path / "one", workers=1)
    two = run_experiment(config, tmp_path / "two", workers=2)
    for key, cell in one.items():
        for column, values in cell.items():
            np.testing.assert_array_equal(values, two[key][column], err_msg=str((key, column)))


def test_teacher_refuses_the_memory_learner():
    """The teacher is the paper's network: the memory learner is one ConfigError line."""
    with pytest.raises(ConfigError, match="expected learner = 'backprop'"):
        load_config({"model": {"kind": "teacher", "learner": "memory"}})


def _curves(finals: dict[str, list[float]], n_bins: int = 10) -> dict:
    return {name: (None, np.repeat(np.array(f)[:, None], n_bins, axis=1))
            for name, f in finals.items()}


@pytest.mark.parametrize(("teacher", "holds"), [([0.9, 0.92, 0.88], True),
                                                ([0.5, 0.52, 0.48], False)])
def test_claim_teacher_at_least_bootstrap(teacher, holds):
    """The claim holds when the teacher matches the bootstrap twin, fails when it is worse."""
    config = load_config({"experiment": {"conditions": [
        {"name": "b", "n_objects": 5}, {"name": "t", "n_objects": 5,
                                        "model": {"kind": "teacher"}}]}})
    claims = check_claims(config, _curves({"b": [0.8, 0.82, 0.78], "t": teacher}),
                          {"5": 0.9})
    [claim] = [c for c in claims if "teacher at least bootstrap" in c.claim]
    assert claim.holds is holds


def test_axis_errors_split_the_error_into_pan_and_tilt():
    """A module right in tilt and mirrored in pan errs horizontally only, by twice the pan."""
    from jointattention.datasets import default_datasets
    from jointattention.experiment.probes import axis_errors_deg

    ds = default_datasets()

    class Module:
        def __init__(self, flip):
            self.flip = np.array(flip)

        def lm_commands(self, faces, thetas):
            return ds.command_rad * self.flip * 0.1  # a direction; its length does not matter

    assert axis_errors_deg(Module([1, 1]), ds) == pytest.approx((0, 0), abs=1e-9)
    pan, tilt = axis_errors_deg(Module([-1, 1]), ds)
    assert tilt == pytest.approx(0, abs=1e-9)
    assert pan == pytest.approx(np.median(np.rad2deg(2 * np.abs(ds.command_rad[:, 0]))))


# -- the developmental model -------------------------------------------------------------------
DEV = {**SHORT, "experiment": {**SHORT["experiment"], "conditions": [
    {"name": "developmental-n1", "n_objects": 1, "model": {"kind": "developmental"}},
    {"name": "developmental-n5-shuffled", "n_objects": 5, "shuffle_faces": True,
     "model": {"kind": "developmental"}}]}}


def test_developmental_learns_on_one_object():
    """With 1 object the developmental model rises from about 0.1 to above 0.6 in 6x10^4 steps."""
    config = load_config(DEV)
    records = run_cell(config, config.experiment.conditions[0], 0)
    assert records["success"][:50].mean() < 0.3  # measured 0.12
    assert _final(records) > 0.6  # measured 0.82 (the teacher: 0.72)


def test_developmental_with_shuffled_faces_stays_at_chance():
    """With faces shuffled the developmental model stays near or below chance (0.2)."""
    config = load_config(DEV)
    assert _final(run_cell(config, config.experiment.conditions[1], 0)) <= 1.25 * 0.2  # 0.10


def test_developmental_without_its_developments_is_the_teacher():
    """criterion_start_deg = 0 and blur_start_px = 0 give the teacher's cell, byte for byte."""
    def cell(model):
        config = load_config({**SHORT, "experiment": {**SHORT["experiment"], "n_steps": 4000,
                                                      "conditions": [{"name": "c",
                                                                      "n_objects": 5,
                                                                      "model": model}]}})
        return run_cell(config, config.experiment.conditions[0], 0)

    teacher = cell({"kind": "teacher"})
    plain = cell({"kind": "developmental", "criterion_start_deg": 0.0, "blur_start_px": 0.0})
    developing = cell({"kind": "developmental"})
    for key in teacher:
        np.testing.assert_array_equal(teacher[key], plain[key], err_msg=key)
    assert not np.array_equal(teacher["lm_error_deg"], developing["lm_error_deg"])


def _developmental_agent(**options):
    config = load_config({"model": {"kind": "developmental", **options}})
    body = Body((320, 240), ((-1.0, 1.0), (-0.8, 0.6)), (30, 25))
    return model_options(config, config.experiment.conditions[0]).build(
        config.agent, body, np.random.default_rng(0))


def test_the_caregiver_approves_near_objects_and_narrows_her_criterion():
    """Within her criterion she approves another object; approving above her level narrows it."""
    agent = _developmental_agent(criterion_start_deg=20.0, criterion_level=0.0,
                                 criterion_shrink=0.5)
    det = Detections(np.array([[100.0, 120.0]]), np.array([400.0]), np.zeros(1), np.zeros(1),
                     (320, 240))
    taught = []
    for error_deg in (10.0, 10.0, 30.0):
        agent.begin_trial(np.full((25, 30), 100, np.uint8), np.zeros(2))
        agent.act(det, np.zeros(2))
        taught.append(agent.end_trial(Outcome(True, np.zeros(2), det, 0, approved=False,
                                              caregiver_error_rad=np.radians(error_deg))))
    # 20 deg: approved (then 10); 10 deg: approved (then 5); 30 deg: not
    assert taught[0] > 0 and taught[1] > 0 and taught[2] == 0
    assert np.degrees(agent.criterion_rad_) == pytest.approx(20 * 0.5 ** 3)


def test_the_face_sharpens_with_learning_time():
    """The blur's s.d. falls linearly to 0 at blur_sharp_steps; a sharp face is the face itself."""
    agent = _developmental_agent(blur_start_px=3.0, blur_sharp_steps=1000.0)
    assert [agent.blur_px(t) for t in (0, 500, 1000, 2000)] == [3.0, 1.5, 0.0, 0.0]
    face = np.random.default_rng(1).integers(0, 256, (25, 30)).astype(np.uint8)
    assert agent.see(face).std() < face.std()
    agent.learning_time_steps = 1000
    np.testing.assert_array_equal(agent.see(face), face)


@pytest.mark.parametrize("learning_time_steps", [0, 500, 1000])
def test_the_batched_commands_see_each_face_as_one_command_does(learning_time_steps):
    """lm_commands blurs every face as lm_command does one at a time (blurred and sharp)."""
    agent = _developmental_agent(blur_start_px=3.0, blur_sharp_steps=1000.0)
    agent.learning_time_steps = learning_time_steps
    rng = np.random.default_rng(4)
    faces = rng.integers(0, 256, (5, 25, 30)).astype(np.uint8)
    thetas = rng.uniform(-0.5, 0.5, (5, 2))
    agent.faces.partial_fit(faces.reshape(5, -1))  # the standardiser's statistics
    alone = [agent.lm_command(f, t) for f, t in zip(faces, thetas, strict=True)]
    assert np.array_equal(agent.lm_commands(faces, thetas), np.array(alone))


@settings(max_examples=30, deadline=None)
@given(sigma=st.floats(0.3, 4.0), seed=st.integers(0, 2**16))
def test_the_blur_is_opencvs_gaussian_blur(sigma, seed):
    """blur_into equals cv2.GaussianBlur with the same s.d., 3 s.d. wide, borders repeated."""
    import cv2

    from jointattention.models.developmental import blur_into

    face = np.random.default_rng(seed).uniform(0, 255, (25, 30))
    out = np.empty(face.size)
    blur_into(face.ravel(), 30, 25, sigma, np.empty(face.size), out)
    size = 2 * int(np.ceil(3 * sigma)) + 1
    expected = cv2.GaussianBlur(face, (size, size), sigma, borderType=cv2.BORDER_REPLICATE)
    np.testing.assert_allclose(out.reshape(25, 30), expected, atol=1e-9)


@pytest.mark.parametrize(("developmental", "holds"), [([0.7, 0.72, 0.69], True),
                                                      ([0.6, 0.61, 0.59], False)])
def test_claim_developmental_faster_than_teacher(developmental, holds):
    """It holds when the developmental curve's mean beats its teacher twin's, else fails."""
    config = load_config({"experiment": {"conditions": [
        {"name": "t", "n_objects": 5, "model": {"kind": "teacher"}},
        {"name": "d", "n_objects": 5, "model": {"kind": "developmental"}}]}})
    claims = check_claims(config, _curves({"t": [0.6, 0.62, 0.61], "d": developmental}),
                          {"5": 0.9})
    [claim] = [c for c in claims if "developmental faster than teacher" in c.claim]
    assert claim.holds is holds


@pytest.mark.parametrize(("factor", "holds"), [(0.4, True), (0.7, False), (1.0, False)])
def test_claim_horizontal_before_vertical(factor, holds):
    """It holds when the horizontal error is below what the geometry gives (0.61 x vertical)."""
    from jointattention.analysis.neighbours import geometry_ratio

    config = load_config({"experiment": {"conditions": [
        {"name": "d", "n_objects": 5, "model": {"kind": "developmental"}}]}})
    assert geometry_ratio(config) == pytest.approx(0.61, abs=0.01)  # 18.6 deg over 30.4 deg
    tilt = np.array([np.linspace(20, 1, 10) * (1 + 0.1 * s) for s in range(4)])
    pan = factor * tilt
    claims = check_claims(config, _curves({"d": [0.5] * 4}), {"5": 0.9}, {"d": (pan, tilt)})
    [claim] = [c for c in claims if "horizontal before vertical" in c.claim]
    assert claim.holds is holds


def test_engine_auto_compiles_what_it_can():
    """Engine "auto" compiles every shipped model in the fast world, and none in images."""
    from jointattention.experiment.cells import engine_of

    population = {"learner": "population", "vf_fallback": "sweep"}
    conditions = [{"name": "d", "model": {"kind": "developmental"}},
                  {"name": "r", "model": {"kind": "rl"}}, {"name": "p", "model": population}]
    fast = load_config({"experiment": {"engine": "auto", "conditions": conditions}})
    assert {engine_of(fast, c) for c in fast.experiment.conditions} == {"compiled"}
    rendered = load_config({"experiment": {"engine": "auto", "perception": "rendered",
                                           "conditions": conditions}})
    assert {engine_of(rendered, c) for c in rendered.experiment.conditions} == {"python"}
    with pytest.raises(ConfigError, match="perception = 'rendered'") as error:
        load_config({"experiment": {"engine": "compiled", "perception": "rendered",
                                    "conditions": conditions}})
    assert "\n" not in str(error.value)


def test_a_developmental_model_is_saved_once_it_sees_sharp_faces(tmp_path):
    """Saving while the face is still blurred is one ConfigError line; once sharp, it loads."""
    from jointattention.deploy.saved import load_model, save_model

    config = load_config({"model": {"kind": "developmental", "blur_sharp_steps": 10.0}})
    name = config.experiment.conditions[0].name
    agent = _developmental_agent(blur_sharp_steps=10.0)
    agent.begin_trial(np.full((25, 30), 100, np.uint8), np.zeros(2))
    with pytest.raises(ConfigError, match="still sees the face blurred"):
        save_model(agent, tmp_path / "blurred.npz", config=config, condition=name)
    assert not (tmp_path / "blurred.npz").exists()
    agent.learning_time_steps = 10
    loaded = load_model(save_model(agent, tmp_path / "sharp.npz", config=config,
                                   condition=name))
    np.testing.assert_array_equal(loaded.agent.learner.w1_, agent.learner.w1_)


@pytest.mark.parametrize(("finals", "holds"), [([0.6, 0.62, 0.58], True),
                                               ([0.21, 0.19, 0.2], False)])
def test_claim_gaze_following_emerges_from_the_basic_set(finals, holds):
    """It holds when the RL learner ends above chance and above its first bin, else fails."""
    config = load_config({"experiment": {"engine": "python", "conditions": [
        {"name": "r", "n_objects": 5, "model": {"kind": "rl"}}]}})
    curves = {"r": (None, np.array([[0.2] * 9 + [f] for f in finals]))}
    [claim] = [c for c in check_claims(config, curves, {"5": 0.9})
               if "emerges from the basic set" in c.claim]
    assert claim.holds is holds


def test_the_environment_tells_the_developmental_caregiver_her_error():
    """Through Gymnasium (EnvTrial) a trial ended on another object carries her angle error."""
    import gymnasium as gym

    from jointattention.env import EnvTrial
    from jointattention.experiment.trial import run_trial

    env = gym.make("JointAttentionFace-v1", n_objects=5)
    agent, outcomes = _developmental_agent(), []
    learn = agent.end_trial
    agent.end_trial = lambda outcome: (outcomes.append(outcome), learn(outcome))[1]
    trial = EnvTrial(env, seed=0)
    while len([o for o in outcomes if o.fired]) < 20:
        run_trial(trial, agent, trial.observation["face"])
        trial = EnvTrial(env)
    env.close()
    fired = [o for o in outcomes if o.fired]
    assert all(o.caregiver_error_rad is None for o in outcomes if not o.fired)
    assert all((o.caregiver_error_rad == 0) == o.approved for o in fired)
    assert any(o.caregiver_error_rad > 0 for o in fired)  # another object: graded, not 0


def test_the_constant_one_claim_is_the_self_evaluating_robots_only():
    """A taught model with the learning module alone is not held to "stays near chance"."""
    config = load_config({"experiment": {"conditions": [
        {"name": "t", "n_objects": 5,
         "model": {"kind": "teacher", "gate": {"kind": "constant", "rate": 1.0}}},
        {"name": "b", "n_objects": 5, "model": {"gate": {"kind": "constant", "rate": 1.0}}}]}})
    claims = check_claims(config, _curves({"t": [0.6] * 3, "b": [0.1] * 3}), {"5": 0.9})
    [claim] = [c for c in claims if "constant 1.0 stays near or below chance" in c.claim]
    assert claim.holds and "model=teacher" not in claim.reading


@pytest.mark.parametrize(("blurred", "holds"), [([0.8, 0.82, 0.79], True),
                                                ([0.7, 0.71, 0.69], False)])
def test_claim_visual_development_improves_accuracy(blurred, holds):
    """It holds when the blurred-then-sharp model ends above its twin that always sees sharp."""
    config = load_config({"experiment": {"conditions": [
        {"name": "d", "n_objects": 5, "model": {"kind": "developmental"}},
        {"name": "s", "n_objects": 5, "model": {"kind": "developmental", "blur_start_px": 0.0}}
    ]}})
    claims = check_claims(config, _curves({"d": blurred, "s": [0.7, 0.72, 0.71]}), {"5": 0.9})
    [claim] = [c for c in claims if "visual development improves accuracy" in c.claim]
    assert claim.holds is holds and claim.claim.startswith("d:")


def test_only_classes_that_say_so_run_compiled():
    """A model class runs compiled only if it declares it itself: a subclass must say so too."""
    from dataclasses import dataclass

    from jointattention.models.bootstrap import BootstrapOptions

    @dataclass(frozen=True)
    class Changed(BootstrapOptions):
        """A bootstrap model with something the compiled loop was not written for."""

    @dataclass(frozen=True)
    class Partly(BootstrapOptions):
        """A bootstrap model whose compiled loop runs every learner but one."""

        compiled: ClassVar[bool] = True
        python_only: ClassVar[dict] = {"learner": ("population",)}

    assert BootstrapOptions().compiled_refusal() is None
    assert BootstrapOptions(learner="population").compiled_refusal() is None
    assert "does not run model kind" in Changed().compiled_refusal()
    assert "does not run learner 'population'" in Partly(learner="population").compiled_refusal()
    assert Partly().compiled_refusal() is None
    # The kinds it names are the registries' compiled ones: all four gates, not a copied list.
    assert "with a gate of kind constant, evidence, performance or sigmoid" in Changed(
        ).compiled_refusal()
    assert "of kind bootstrap, developmental, rl or teacher" in Changed().compiled_refusal()
