"""The eye window: a fovea's view of the caregiver's eyes, recorded with the face window."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from jointattention import GazeFollower, evaluate, load_model, run_cell, train
from jointattention.agent.gates import SigmoidGate
from jointattention.config import ConditionConfig, Config, ExperimentConfig, load_config
from jointattention.config.run import RecordingConfig
from jointattention.datasets import CaregiverDatasets, load, save
from jointattention.errors import ArgumentError, ConfigError, DatasetError
from jointattention.experiment.cells import datasets_of, make_agent
from jointattention.models.bootstrap import BootstrapOptions
from jointattention.models.population.features import n_features
from jointattention.world.options import EyeWindowConfig
from jointattention.world.recording import _placement_error, eye_box, make_datasets
from jointattention.world.simulator import World

PEOPLE = load_config("people").world
EYES = dataclasses.replace(PEOPLE, eye_window=EyeWindowConfig(width_px=48, height_px=12))


def with_camera(world, width_px: int):
    """``world`` seen by a camera of ``width_px`` (4:3), the rest the same."""
    return dataclasses.replace(world, camera=dataclasses.replace(
        world.camera, width_px=width_px, height_px=width_px * 3 // 4))


@pytest.fixture(scope="module")
def recorded() -> CaregiverDatasets:
    """Twelve data sets of four caregivers, with eye windows."""
    return make_datasets(EYES, 12, seed=3, caregivers=4)


@pytest.mark.parametrize("size", [(0, 12), (48, 0), (3, 12), (48, 2)])
def test_half_set_or_tiny_eye_windows_are_refused(size):
    """An eye window with one side 0 or under 4 pixels is one ConfigError naming it."""
    with pytest.raises(ConfigError, match="eye_window"):
        EyeWindowConfig(width_px=size[0], height_px=size[1])


def test_the_fovea_sees_what_a_finer_camera_sees_there():
    """The fovea's render is the crop of a camera zoom times finer, to a fraction of a level."""
    zoom = 4
    fine = with_camera(PEOPLE, PEOPLE.camera.width_px * zoom)
    with World(PEOPLE, seed=3) as world, World(fine, seed=3) as finer:
        for w in (world, finer):
            w.set_head_angle(w.face_angle_rad + [0.02, -0.01])  # the eyes off the centre
        plain = dataclasses.replace(world.state.look, blur_sd_px=0.0, gain=1.0, noise_sd=0.0)
        for w in (world, finer):
            w.set_scene(dataclasses.replace(w.state, look=plain))
            w.set_head_angle(w.face_angle_rad + [0.02, -0.01])
        _, distance = eye_box(world)
        fine_centre, _ = eye_box(finer)
        width, height = 96, 32
        cx, cy = np.rint(fine_centre).astype(int)
        crop = finer.render()[cy - height // 2: cy + height // 2, cx - width // 2: cx + width // 2]
        crop_centre = np.array([cx, cy]) - 0.5  # pixel indices: the crop's middle
        at = (crop_centre - finer.kinematics.centre_px) / zoom + world.kinematics.centre_px
        fovea = world.render_fovea(at, width / zoom, (width, height))
    assert distance > 10  # the eyes are in view, apart
    assert np.abs(fovea.astype(int) - crop).mean() < 0.05  # measured: 0.0


def test_recorded_sets_hold_eye_windows_that_round_trip(tmp_path, recorded):
    """Data sets of a world with an eye window keep one per set, saved and loaded as they are."""
    assert recorded.eyes.shape == (12, 12, 48) and recorded.eyes.dtype == np.uint8
    assert recorded.eyes.std() > 5  # not blank: eyes, skin, brows
    back = load(save(recorded, tmp_path / "sets.npz"))
    np.testing.assert_array_equal(back.eyes, recorded.eyes)
    assert back.subset([0, 2]).eyes.shape == (2, 12, 48)


def test_the_eye_window_moves_with_the_gaze(recorded):
    """Two poses of one caregiver give different eye windows; the recording is deterministic."""
    assert not np.array_equal(recorded.eyes[0], recorded.eyes[1])
    np.testing.assert_array_equal(make_datasets(EYES, 3, seed=3, caregivers=1).eyes,
                                  make_datasets(EYES, 3, seed=3, caregivers=1).eyes)


def test_the_eye_window_leaves_the_face_windows_as_they_were():
    """Recording eye windows changes nothing else of the data sets."""
    with_eyes, without = make_datasets(EYES, 4, seed=5), make_datasets(PEOPLE, 4, seed=5)
    assert without.eyes is None
    for field in ("face", "theta_face_rad", "command_rad", "target_m"):
        np.testing.assert_array_equal(getattr(with_eyes, field), getattr(without, field))


def test_placement_error_moves_the_eye_window_only():
    """placement_sd moves each eye window, reproducibly, and leaves the rest of the sets."""
    sloppy = dataclasses.replace(EYES, eye_window=dataclasses.replace(EYES.eye_window,
                                                                      placement_sd=0.05))
    exact, moved = make_datasets(EYES, 4, seed=5), make_datasets(sloppy, 4, seed=5)
    for field in ("face", "theta_face_rad", "command_rad", "target_m"):
        np.testing.assert_array_equal(getattr(moved, field), getattr(exact, field))
    assert all(not np.array_equal(a, b) for a, b in zip(moved.eyes, exact.eyes, strict=True))
    np.testing.assert_array_equal(make_datasets(sloppy, 4, seed=5).eyes, moved.eyes)


def test_each_scene_draws_its_own_placement_error():
    """Without sensor noise too, each scene's eye window is placed with an error of its own."""
    quiet = dataclasses.replace(EYES, sensor=dataclasses.replace(
        EYES.sensor, noise_sd_range_levels=(0.0, 0.0)))
    with World(quiet, seed=5) as world:
        errors = []
        for _ in range(3):
            world.reset()
            errors.append(_placement_error(world, 0.05))
    assert len({tuple(e) for e in errors}) == 3 and np.std(errors) > 0.01


def test_the_fovea_renders_the_whole_view_finer_than_the_camera():
    """A fovea larger than the camera's buffer renders (its own buffer), the camera's unchanged."""
    with World(EYES, seed=3) as world:
        kin = world.kinematics
        before = world.render()
        fine = world.render_zoomed(4)
        small = np.asarray(fine.reshape(kin.height_px, 4, kin.width_px, 4, 3).mean(axis=(1, 3)))
        assert fine.shape == (4 * kin.height_px, 4 * kin.width_px, 3)
        assert world.model.vis.global_.offwidth == kin.width_px
        after = world.render().astype(int)
    assert np.abs(after - before).mean() < 3  # the camera's view as it was (its noise aside)
    assert np.abs(small - before).mean() < 8  # the same view, averaged down (sensor aside)


def test_the_finder_cut_with_an_eye_window_is_refused():
    """The finder's cut with an eye window is one ValueError naming both."""
    with pytest.raises(ValueError, match=r"finder.*eye window"):
        make_datasets(EYES, 2, seed=1, cut="finder")


def test_malformed_eye_windows_are_refused_naming_the_field(tmp_path, recorded):
    """An eyes field of another length or dtype is one DatasetError naming 'eyes'."""
    arrays = dict(np.load(save(recorded, tmp_path / "sets.npz")))
    for bad in (arrays["eyes"][:5], arrays["eyes"].astype(float)):
        np.savez(tmp_path / "bad.npz", **{**arrays, "eyes": bad})
        with pytest.raises(DatasetError, match="field 'eyes'"):
            load(tmp_path / "bad.npz")


LEARNERS = [
    ConditionConfig(name="population", n_objects=5, model={
        "learner": "population", "vf_fallback": "sweep", "population": {"n_hidden": 16}}),
    ConditionConfig(name="network", n_objects=3),
    ConditionConfig(name="memory", n_objects=5, model={"learner": "memory"}),
]
RUN = Config(
    model=BootstrapOptions(gate=SigmoidGate(midpoint_steps=1500.0, width_steps=500.0)),
    world=dataclasses.replace(EYES, eye_window=EyeWindowConfig(width_px=24, height_px=8)),
    recording=RecordingConfig(caregivers=4, poses_per_caregiver=6, seed=7),
    experiment=ExperimentConfig(n_steps=3000, n_seeds=1, conditions=tuple(LEARNERS)))


def _engine(engine: str) -> Config:
    return dataclasses.replace(RUN, experiment=dataclasses.replace(RUN.experiment, engine=engine))


@pytest.mark.parametrize("condition", LEARNERS, ids=lambda c: c.name)
def test_learners_with_an_eye_window_run_alike_in_both_engines(condition):
    """With eye windows, the compiled engine writes the python engine's records, bit for bit."""
    compiled = run_cell(_engine("compiled"), condition, 0)
    python = run_cell(_engine("python"), condition, 0)
    for key in compiled:
        assert np.array_equal(compiled[key], python[key], equal_nan=True), key
    assert compiled["n_lm_steps"].sum() > 0


def test_the_population_code_reads_the_eye_window():
    """Its input holds the eye window's features: a blank eye window changes its command."""
    ds = datasets_of(RUN)
    agent = make_agent(RUN, LEARNERS[0], 0, ds)
    assert agent.body.view_size == 30 * 25 + 24 * 8
    assert agent.module.n_features == n_features((30, 25), 5, 12) + n_features((24, 8), 5, 12)
    blank = ds.views.copy()
    blank[:, 30 * 25:] = 128
    assert not np.allclose(agent.lm_commands(ds.views, ds.theta_face_rad),
                           agent.lm_commands(blank, ds.theta_face_rad))
    with pytest.raises(ArgumentError, match="eye window"):
        agent.lm_commands(ds.face, ds.theta_face_rad)  # the face window alone


@pytest.mark.parametrize("kind", [{"kind": "developmental"}, {"kind": "rl"}])
def test_models_that_read_the_face_window_only_refuse_an_eye_window(kind):
    """The developmental and RL models refuse a body with an eye window, in one line."""
    condition = ConditionConfig(name="x", n_objects=3, model=kind)
    with pytest.raises(ConfigError, match="eye window"):
        make_agent(RUN, condition, 0, datasets_of(RUN))


def test_a_model_with_an_eye_window_is_saved_loaded_and_evaluated(tmp_path):
    """Saved and loaded, the model keeps its eye window; evaluate reads it; follow checks frames."""
    model = train(RUN, "population")
    back = load_model(model.save(tmp_path / "m.npz"))
    assert back.robot.eye_size_px == (24, 8)
    ds = datasets_of(RUN)
    np.testing.assert_array_equal(back.lm_command(ds.view(0), ds.theta_face_rad[0]),
                                  model.lm_command(ds.view(0), ds.theta_face_rad[0]))
    result = evaluate(back, ds, n_objects=3, n_trials=20)
    assert 0.0 <= result.success <= 1.0
    no_eyes = dataclasses.replace(ds, eyes=None)
    with pytest.raises(ConfigError, match="eye windows none"):
        evaluate(back, no_eyes, n_objects=3, n_trials=20)
    follower = GazeFollower(back)
    assert follower.frame_size_px == (1280, 960)
    assert GazeFollower(back, min_score=0.9).eye_net.min_score == 0.9  # both looks
    with pytest.raises(ArgumentError, match="expected RGB uint8 frames 1280 wide and 960 high"):
        follower.look(np.zeros((240, 320, 3), np.uint8), ds.theta_face_rad[0])
    with pytest.raises(ConfigError, match="expected face = 'blazeface'"):
        GazeFollower(back, face="template")
