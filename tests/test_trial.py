"""The one trial loop: how trials end, what the observer sees, the record schema."""

from __future__ import annotations

from functools import partial
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import jointattention
from jointattention.agent.attention import attended_object
from jointattention.config import WorldConfig
from jointattention.experiment.oracle import OracleAgent
from jointattention.experiment.trial import (
    END_FIRED,
    END_LIMIT,
    END_STEPS,
    RECORD,
    RUNNING,
    SceneTrial,
    end_after_look,
    move_head,
    records,
    run_trial,
)
from jointattention.world.simulator import World

STEP = np.deg2rad(4.0)


def _trial(world: World, max_steps: int = 40) -> SceneTrial:
    kin = world.kinematics
    return SceneTrial(world.fast_scene(), world.face_angle_rad, kinematics=kin,
                      max_steps=max_steps, evaluate=partial(attended_object, d_th_px=320 / 6))


def test_following_the_gaze_line_to_a_lone_object_fires_on_it():
    """With one object, the oracle's trial ends with the evaluator firing on the target."""
    world = World(WorldConfig(), seed=4, n_objects=1)
    for _ in range(5):
        s = world.reset()
        oracle = OracleAgent(world.kinematics.centring_angles(s.target_pos_m), STEP)
        r = run_trial(_trial(world), oracle, np.zeros((25, 30)))
        assert (r.end, r.attended, r.target) == (END_FIRED, 0, 0) and r.success
        assert r.n_lm_steps == r.n_steps == oracle.learning_time_steps


def test_a_still_head_ends_at_the_step_limit():
    """A head that does not move ends at the step limit, after exactly ``max_steps``.

    It never fires: objects are kept clear of the face.
    """
    world = World(seed=1)
    oracle = OracleAgent(world.face_angle_rad, STEP)  # already where it wants to be
    r = run_trial(_trial(world, max_steps=7), oracle, np.zeros((25, 30)))
    assert (r.end, r.n_steps, r.attended, r.fired) == (END_STEPS, 7, -1, False)


def test_a_move_past_the_joint_limit_stops_there_and_ends_the_trial():
    """Pushing past the pan limit stops the head at the limit; the trial ends there."""
    world = World(seed=2)
    kin = world.kinematics
    oracle = OracleAgent(world.face_angle_rad + [3.0, 0.0], 1.0)  # far right, big steps
    trial = _trial(world)
    r = run_trial(trial, oracle, np.zeros((25, 30)))
    assert r.end in (END_LIMIT, END_FIRED)
    if r.end == END_LIMIT:
        assert r.theta_end_rad[0] == pytest.approx(kin.pan_limits_rad[1])
        assert trial.limit_hit
    with pytest.raises(RuntimeError, match="ended"):
        trial.step(np.zeros(2))


def test_the_observer_sees_every_look_and_the_module_that_moved():
    """The observer is called once per look: with the module that moves next, then None."""
    world = World(seed=3)
    oracle = OracleAgent(world.face_angle_rad, STEP)
    seen = []
    r = run_trial(_trial(world, max_steps=5), oracle, np.zeros((25, 30)),
                  observer=lambda t, module: seen.append((t.n_steps, module)))
    assert seen == [(0, "lm"), (1, "lm"), (2, "lm"), (3, "lm"), (4, "lm"), (5, None)]
    assert r.n_steps == 5


def test_records_follow_the_schema():
    """``records`` gives every column of RECORD with its dtype, one row per trial."""
    world = World(seed=5)
    results = [run_trial(_trial(world, max_steps=3), OracleAgent(world.face_angle_rad, STEP),
                         np.zeros((25, 30))) for _ in range(4)]
    rec = records(results)
    assert list(rec) == list(RECORD)
    for name, (dtype, _) in RECORD.items():
        assert rec[name].dtype == np.dtype(dtype) and len(rec[name]) == 4


def test_both_scenes_keep_the_scene_contract_with_object_places(needs_gl):
    """Fast and rendered scenes are Scenes with object places; the outcome's error uses them."""
    from jointattention.config import DetectorConfig
    from jointattention.rng import stream
    from jointattention.world.protocol import Scene
    from jointattention.world.rendered import RenderedScenes

    world = World(WorldConfig(), seed=4, n_objects=3)
    world.reset()
    fast = world.fast_scene()
    scenes = RenderedScenes(world.config, DetectorConfig(), 3, seed=4, rng=stream(0, "t"))
    try:
        rendered = scenes.show(fast, world.state.head_pos_m)
        for scene in (fast, rendered):
            assert isinstance(scene, Scene)
            np.testing.assert_array_equal(scene.object_pos_m, world.state.object_pos_m)
    finally:
        scenes.close()
    kin = world.kinematics
    checked = 0
    for i in range(3):  # fire on each object: the error is its angle from the target
        trial = SceneTrial(fast, kin.centring_angles(world.state.object_pos_m[i]),
                           kinematics=kin, max_steps=5,
                           evaluate=partial(attended_object, d_th_px=320 / 6))
        out = trial.outcome
        if out.fired and trial.attended == i:
            assert (out.caregiver_error_rad == 0) == (i == fast.target_index)
            checked += 1
    assert checked >= 2


@given(pan=st.floats(-3, 3), tilt=st.floats(-3, 3), d_pan=st.floats(-1, 1),
       d_tilt=st.floats(-1, 1))
@settings(max_examples=200, deadline=None)
def test_the_one_head_move_stops_at_the_joint_limits(pan, tilt, d_pan, d_tilt):
    """move_head is the move clipped to the joint ranges, and says whether a limit stopped it."""
    lo, hi = (-1.0, -0.8), (1.0, 0.6)
    got_pan, got_tilt, hit = move_head(pan, tilt, d_pan, d_tilt, lo[0], hi[0], lo[1], hi[1])
    want = np.array([pan + d_pan, tilt + d_tilt])
    assert [got_pan, got_tilt] == list(np.clip(want, lo, hi))
    assert hit == (not np.array_equal(np.clip(want, lo, hi), want))


def test_a_look_ends_a_trial_by_eq3_first_then_the_limit_then_the_step_limit():
    """end_after_look: fired beats a limit, which beats the step limit; else it runs on."""
    assert end_after_look(0, True, 40, 40) == END_FIRED
    assert end_after_look(-1, True, 40, 40) == END_LIMIT
    assert end_after_look(-1, False, 40, 40) == END_STEPS
    assert end_after_look(-1, False, 39, 40) == RUNNING


def test_every_trial_loop_steps_with_the_one_step():
    """The python trial, the compiled loops and the vector env step with the one move and end."""
    root = Path(jointattention.__file__).parent
    assert "end_after_look(" in (root / "experiment/compiled/steps.py").read_text()  # their look
    for name in ("experiment/trial.py", "experiment/compiled/_loop.py",
                 "experiment/compiled/_rl_loop.py", "env/_vector_kernels.py"):
        text = (root / name).read_text()
        # the step's body: after the kernels themselves; the vector env's start may clip the
        # caregiver's face angle into the joint ranges (a start, not a move)
        body = text.split("def end_after_look", 1)[-1] if name.endswith("trial.py") else (
            text.split("def step_all", 1)[-1] if name.endswith("kernels.py") else text)
        ends = "look(" if "_loop" in name else "end_after_look("  # the compiled loops' look
        assert "move_head(" in body and ends in body, name
        assert "min(max(" not in body, name
