"""What the learning module learned: angle errors, held-out poses, the grid and Fig. 7."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from jointattention.config import load_config
from jointattention.errors import ConfigError
from jointattention.experiment import probes
from jointattention.experiment.cells import datasets_of
from jointattention.jobs import learned


@pytest.fixture(scope="module")
def trained():
    """The quick preset's one-object condition learned for 30,000 steps."""
    cfg = load_config("quick")
    cfg = dataclasses.replace(cfg, experiment=dataclasses.replace(cfg.experiment,
                                                                  n_steps=30_000))
    return cfg, learned.snapshots(cfg, "n1-sigmoid", 0, [0, 15_000])


def test_learning_turns_the_output_toward_the_target(trained):
    """Learning turns the module's output from chance toward the target.

    Untrained, the median angle to the target is near chance (over 60 deg); after learning it is
    under 30 deg on the data sets.
    """
    cfg, agents = trained
    assert sorted(agents) == [0, 15_000, 30_000]
    ds = datasets_of(cfg)
    before = np.median(probes.angle_errors(agents[0], ds))
    after = np.median(probes.angle_errors(agents[30_000], ds))
    assert before > 60 and after < 30


def test_an_unknown_condition_is_refused():
    """Training a condition the configuration lacks names the ones it has."""
    with pytest.raises(ConfigError, match="expected one of n1-sigmoid"):
        learned.snapshots(load_config("quick"), "n2-sigmoid", 0, [])


def test_held_out_poses_continue_the_recording(needs_gl):
    """Held-out poses are the same caregiver's next recordings: none repeats a data set."""
    cfg = load_config("quick")
    ds = datasets_of(cfg)
    held = learned.held_out_poses(cfg, ds, 5)
    assert len(held) == 5
    for c in held.command_rad:
        assert np.min(np.linalg.norm(ds.command_rad - c, axis=1)) > 1e-6


def test_grid_faces_follow_the_gaze(needs_gl):
    """Grid face windows differ by gaze direction, and the commands point the grid's way.

    Pan to the right is a positive pan command.
    """
    cfg = load_config("quick")
    faces, thetas, commands = learned.grid_faces(cfg, 0, (-30, 30), (0,))
    assert faces.shape[:2] == (1, 2) and thetas.shape == commands.shape == (1, 2, 2)
    assert np.abs(faces[0, 0].astype(int) - faces[0, 1]).mean() > 2
    assert commands[0, 0, 0] < 0 < commands[0, 1, 0]


def test_a_recorded_trial_ends_with_the_target_in_the_gazing_circle(trained, needs_gl):
    """Fig. 7's trial ends with the caregiver's target inside the evaluator's circle.

    One frame per look, with the learning-module steps counted.
    """
    cfg, agents = trained
    agent = agents[30_000]
    frames, result = learned.record_trial(cfg, agent, 1, min_lm_steps=1)
    assert result.success and len(frames) == result.n_steps + 1
    assert sum(f.module == "lm" for f in frames) == result.n_lm_steps
    centre = np.array([(320 - 1) / 2, (240 - 1) / 2])
    assert np.hypot(*(frames[-1].target_px - centre)) < cfg.agent.d_th_px(320)
