"""The eye window the robot cuts from a camera frame, where BlazeFace puts the eyes."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from jointattention import GazeFollower
from jointattention.agent.blazeface import BlazeFace
from jointattention.agent.eye_windows import eye_landmarks, eye_window_of
from jointattention.config import load_config
from jointattention.deploy.overlay import draw_look
from jointattention.errors import ArgumentError
from jointattention.world.options import EyeWindowConfig
from jointattention.world.recording import HELD_OUT, eye_box, eye_window_at
from jointattention.world.simulator import World

RAMP = np.tile(np.arange(240, dtype=np.uint8), (120, 1))  # grey = x


@settings(max_examples=60, deadline=None)
@given(x=st.floats(60, 180), y=st.floats(40, 80), distance=st.floats(8, 40),
       span=st.sampled_from([2.0, 2.67]))
def test_the_window_samples_the_field_around_the_eyes(x, y, distance, span):
    """On a ramp, each window column holds the frame's grey at its place in the field."""
    width, height = 32, 12
    window = eye_window_of(RAMP, (x, y), distance, (width, height), span)
    field_w = round(span * distance)
    expected = x - field_w / 2 + (np.arange(width) + 0.5) * field_w / width
    assert window.shape == (height, width)
    # rounding, and OpenCV's area weights; the outer columns of a field narrower than the
    # window hold its edge's grey
    np.testing.assert_allclose(window.mean(axis=0)[1:-1], expected[1:-1], atol=0.75)


@pytest.fixture(scope="module")
def people_views():
    """Thirty-two views of sixteen unseen people, 4x the camera: frames and the eyes' true boxes."""
    world_config = dataclasses.replace(
        load_config("people").world,
        eye_window=EyeWindowConfig(width_px=128, height_px=48, span=2.67))
    views = []
    with World(world_config, seed=4242, stream=HELD_OUT) as world:
        for i in range(32):
            world.reset(new_identity=i > 0 and i % 2 == 0)
            world.set_head_angle(world.face_angle_rad)
            frame = world.render_zoomed(4)
            centre, distance = eye_box(world)
            views.append((frame, 4 * centre + 1.5, 4 * distance,
                          eye_window_at(world, centre, distance)))
    return views


def test_a_second_look_places_the_eyes_closer(people_views):
    """BlazeFace's second look puts the eyes' midpoint nearer the eyeballs than its first."""
    net = BlazeFace(0.4)
    first, second = [], []
    for frame, centre, distance, _ in people_views:
        whole = net.detect(frame)
        marks = eye_landmarks(net, frame)
        if not whole or marks is None:
            continue
        first.append(np.linalg.norm(whole[0].landmarks_px[:2].mean(axis=0) - centre) / distance)
        second.append(np.linalg.norm(marks[0] - centre) / distance)
    assert len(second) >= 24  # measured on 96 views: a median 0.076 against 0.179
    assert np.median(second) < 0.15 and np.median(second) < np.median(first)


def test_the_window_it_cuts_is_the_simulators_window(people_views):
    """Cut where BlazeFace puts the eyes, the window is the one cut at the eyeballs, not below."""
    import cv2

    net, placed, below = BlazeFace(0.4), [], []
    for frame, _, _, exact in people_views:
        marks = eye_landmarks(net, frame)
        if marks is None:
            continue
        grey = cv2.cvtColor(frame, cv2.COLOR_RGB2GRAY)
        (x, y), distance = marks
        for at, out in (((x, y), placed), ((x, y + distance / 2), below)):
            window = eye_window_of(grey, at, distance, (128, 48), 2.67)
            out.append(np.corrcoef(window.ravel(), exact.ravel())[0, 1])
    assert len(placed) >= 24
    assert np.median(placed) > 0.45 and np.median(placed) > np.median(below) + 0.2  # 0.59, 0.26


def test_the_follower_reads_a_socket_model_from_a_fovea_frame(people_views, socket_run):
    """A socket-patch model follows on frames of its fovea: a step, the face in frame pixels."""
    run, model = socket_run
    follower = GazeFollower(model)
    frame, look = next((f, x) for f, *_ in people_views[:4]
                       if (x := follower.look(f, np.zeros(2))) is not None)
    assert look.eyes.shape == (12, 24)
    # the face in the frame's pixels (the head looks at it), not the shrunk frame's
    assert np.hypot(*(look.face.centre_px - (639.5, 479.5))) < 100
    assert draw_look(frame, look).shape == frame.shape
    step = np.deg2rad(run.agent.lm_step_deg)
    assert np.linalg.norm(look.command_rad) == pytest.approx(step, rel=1e-6)


def test_the_closed_loop_runs_a_socket_model_through_its_fovea(socket_run, needs_gl):
    """closed-loop on an eye model: each first look is the fovea's view, every window whole."""
    from jointattention.jobs.closed_loop import closed_loop

    _, model = socket_run
    result = closed_loop(model, 1, 4, seed=1)
    assert result.n_trials == 4 and result.faces_found >= 0.5
    for value in (result.rendered_success, result.rendered_box_face_success,
                  result.rendered_dataset_face_success, result.fast_success):
        assert 0 <= value <= 1
    assert 0 <= result.image_error_deg <= 180 and 0 <= result.dataset_error_deg <= 180


def test_the_closed_loop_refuses_data_sets_without_the_models_eyes(socket_run):
    """Data sets with no eye windows, for a model that reads the eyes: one DatasetError line."""
    from jointattention.errors import DatasetError
    from jointattention.experiment.cells import datasets_of
    from jointattention.jobs.closed_loop import closed_loop

    run, model = socket_run
    no_eyes = dataclasses.replace(datasets_of(run), eyes=None)
    with pytest.raises(DatasetError, match="eye windows none; expected the model's: 24x12 px"):
        closed_loop(model, 1, 2, datasets=no_eyes)


def test_following_moves_as_the_learned_agent_does_when_its_module_leads(socket_run):
    """The closed loop's follower runs the module's trial: the agent's own moves, gate at LM."""
    from jointattention.experiment.cells import datasets_of, evaluator, random_scene
    from jointattention.experiment.evaluate import freeze
    from jointattention.experiment.trial import SceneTrial, run_trial
    from jointattention.jobs.closed_loop import FollowingAgent
    from jointattention.rng import stream
    from jointattention.world.kinematics import HeadKinematics

    run, model = socket_run
    ds, kin = datasets_of(run), HeadKinematics.from_config(run.world)
    leader = freeze(model.agent)
    leader.gate_rate = lambda: 1.0  # the learning module moves the head at every step
    follower, rng = FollowingAgent(model), stream(0, "follow-test")
    for _ in range(12):
        k, scene, _ = random_scene(run, ds, kin, 3, rng)
        outcomes = [run_trial(SceneTrial(scene, ds.theta_face_rad[k], kinematics=kin,
                                         max_steps=run.agent.max_steps,
                                         evaluate=evaluator(run)), agent, ds.view(k))
                    for agent in (leader, follower)]
        assert outcomes[0].success == outcomes[1].success
        assert outcomes[0].n_steps == outcomes[1].n_steps


def test_the_follower_steps_through_a_trial_from_one_look(people_views, socket_run):
    """The follower looks once (begin), then steps on from it; a step with no trial: one error."""
    run, model = socket_run
    follower = GazeFollower(model)
    with pytest.raises(ArgumentError, match=r"expected begin\(frame, theta\) first"):
        follower.step(np.zeros(2))
    start = np.zeros(2)
    look = next(x for f, *_ in people_views[:4] if (x := follower.begin(f, start)) is not None)
    np.testing.assert_allclose(follower.step(start), look.command_rad, atol=1e-12)
    theta = start.copy()
    for _ in range(3):  # along the line read at the face, one step at a time
        step = follower.step(theta)
        assert np.linalg.norm(step) == pytest.approx(np.deg2rad(run.agent.lm_step_deg))
        theta = theta + step
    np.testing.assert_allclose(theta, 3 * look.command_rad, atol=1e-9)
