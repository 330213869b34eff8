"""Generalisation: evaluate, the held-out measures of every run, and the held-out sets."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from jointattention.cli import main
from jointattention.config import load_config
from jointattention.datasets import default_datasets, load
from jointattention.errors import ConfigError, FileError
from jointattention.experiment.evaluate import _errors, evaluate, evaluate_agent, freeze
from jointattention.experiment.held_out import (
    KINDS,
    MEASURES,
    checkpoint_steps,
    held_out_novelty,
    held_out_sets,
    measure_held_out,
    shipped_held_out,
)
from jointattention.experiment.probes import probe_sets
from jointattention.experiment.results import cell_path, load_cell, save_cell
from jointattention.experiment.training import train
from jointattention.jobs.reproduce import reproduce
from jointattention.world.recording import caregivers_of

QUICK = {"experiment": {"n_steps": 6000, "n_seeds": 1, "bin_steps": 2000,
                        "n_ceiling_trials": 200,
                        "held_out": {"n_trials": 100, "n_checkpoints": 2},
                        "conditions": [{"name": "n3", "n_objects": 3}]}}


@pytest.fixture(scope="module")
def model():
    """A small learned paper model of the shipped data sets."""
    return train(load_config(QUICK), "n3")


def test_the_shipped_held_out_sets_are_disjoint_from_the_training_sets():
    """New poses: the training caregiver, other poses; unseen: 16 other caregivers."""
    config, train_ds = load_config(None), default_datasets()
    poses, unseen = shipped_held_out("new poses"), shipped_held_out("unseen caregivers")
    trained = caregivers_of(train_ds, config.world)
    assert caregivers_of(poses, config.world) == trained * len(caregivers_of(poses,
                                                                             config.world))
    strangers = caregivers_of(unseen, config.world)
    assert len(strangers) == 16
    varied = [f.name for f in dataclasses.fields(trained[0])
              if len({repr(getattr(c, f.name)) for c in strangers}) > 1]
    assert {"head_scale", "skin_rgb", "shirt_rgb"} <= set(varied)
    for name in varied:  # every field the world varies differs from the trained caregiver's
        assert all(getattr(c, name) != getattr(trained[0], name) for c in strangers
                   if name != "hair_rgb"), name  # hair comes from a palette of five
    for held in (poses, unseen):  # no pose is a training pose
        d = np.linalg.norm(held.target_m[:, None] - train_ds.target_m[None], axis=2)
        assert d.min() > 1e-6
        assert not (held.face[:, None] == train_ds.face[None]).all(axis=(2, 3)).any()


def test_evaluate_reports_the_documented_numbers(model, tmp_path):
    """Success, ceiling, their fraction, errors and the share of identities, in range."""
    path = model.save(tmp_path / "m.npz")
    result = evaluate(path, shipped_held_out("unseen caregivers"), n_objects=3, n_trials=150)
    row = result.as_dict()
    assert row["n_sets"] == 400 and row["n_identities"] == 16 and row["n_trials"] == 150
    assert 0 <= row["success"] <= 1 and 0 < row["ceiling"] <= 1
    assert row["fraction_of_ceiling"] == pytest.approx(row["success"] / row["ceiling"])
    assert 0 <= row["median_error_deg"] <= row["p90_error_deg"] <= 180
    assert 0 <= row["share_identities_over_10deg"] <= 1
    assert np.isnan(row["novelty_median"])  # learned from one caregiver: no spacing


def test_evaluate_says_how_new_the_caregivers_are(model):
    """Caregivers it learned from have novelty 0; others above 0 (known: half of them)."""
    unseen, config = shipped_held_out("unseen caregivers"), load_config(QUICK)
    people = caregivers_of(unseen, config.world)
    own = evaluate_agent(model.agent, unseen, config, n_objects=3, n_trials=20, known=people)
    assert own.novelty_median == own.novelty_max == 0
    half = evaluate_agent(model.agent, unseen, config, n_objects=3, n_trials=20,
                          known=people[:8])
    assert 0 < half.novelty_median < half.novelty_max


def test_the_evaluate_command_prints_one_json_object(model, tmp_path, capsys):
    """--json prints the fields the issue names; --out writes CSV and JSON."""
    model_file = model.save(tmp_path / "m.npz")
    sets = tmp_path / "sets.npz"
    import shutil

    from jointattention.experiment.held_out import SHIPPED

    with __import__("importlib").resources.as_file(
            __import__("importlib").resources.files("jointattention.data")
            / SHIPPED["new poses"]) as p:
        shutil.copy(p, sets)
    assert main(["evaluate", str(model_file), "--datasets", str(sets), "--trials", "100",
                 "--json", "--out", str(tmp_path / "ev")]) == 0
    row = json.loads(capsys.readouterr().out)
    for key in ("fraction_of_ceiling", "success", "ceiling", "median_error_deg",
                "p90_error_deg", "share_identities_over_10deg", "n_sets", "novelty_median",
                "novelty_max"):
        assert key in row
    assert row["n_sets"] == 250
    assert (tmp_path / "ev" / "evaluation.csv").is_file()
    assert json.loads((tmp_path / "ev" / "evaluation.json").read_text()) == row


@pytest.mark.parametrize("args, words", [
    ([], "expected either --datasets FILE or --caregivers K"),
    (["--datasets", "README.md"], "not a readable .npz archive"),
    (["--datasets", "nowhere.npz"], "nowhere.npz"),
])
def test_evaluate_refuses_bad_input_in_one_line(model, tmp_path, capsys, args, words):
    """A missing choice or a bad data-set file is one error line, exit 2, no traceback."""
    model_file = model.save(tmp_path / "m.npz")
    assert main(["evaluate", str(model_file), *args]) == 2
    err = capsys.readouterr().err
    assert words in err and err.count("\n") == 1 and "Traceback" not in err


def test_evaluate_refuses_data_sets_of_another_window(model):
    """Face windows of another size than the model's are refused, naming both sizes."""
    ds = default_datasets()
    small = dataclasses.replace(ds, face=np.ascontiguousarray(ds.face[:, :10, :12]))
    with pytest.raises(ConfigError, match="12x10 px; expected the model's 30x25"):
        evaluate_agent(model.agent, small, model.config)


def test_train_and_a_run_keep_the_held_out_measures(model, tmp_path):
    """A trained model carries its held-out measures; a run's cells, table and figure too."""
    assert set(model.held_out) == set(KINDS)
    assert 0 <= model.held_out["unseen caregivers"]["success"] <= 1
    config = load_config(QUICK)
    result = reproduce(config, tmp_path / "run")
    cell = load_cell(cell_path(tmp_path / "run", "n3", 0))
    assert list(cell["held_out_steps"]) == list(checkpoint_steps(config)) == [3000, 6000]
    for m in MEASURES:
        assert cell[m].shape == (3, 2)
    names = {p.name for p in result.files}
    assert {"held_out.md", "held_out.csv", "held_out.png"} <= names
    table = (tmp_path / "run" / "table.md").read_text()
    assert "unseen_caregivers_fraction" in table
    assert any("follows caregivers it never saw" in c.claim for c in result.claims)


def test_a_cell_with_part_of_the_held_out_measures_is_refused(model, tmp_path):
    """A cell file holding some held-out arrays but not all is named as not whole."""
    config = load_config(QUICK)
    reproduce(config, tmp_path / "run")
    path = cell_path(tmp_path / "run", "n3", 0)
    cell = dict(load_cell(path))
    del cell["held_out_p90_error_deg"]
    save_cell(path, cell)
    with pytest.raises(FileError, match="held_out_p90_error_deg"):
        load_cell(path)


def test_held_out_sets_of_a_robot_s_recording_are_only_files(tmp_path):
    """Training sets that name no simulated caregiver get no recorded held-out sets."""
    ds = default_datasets()
    meta = {k: v for k, v in ds.meta.items() if k != "seed"}
    path = tmp_path / "robot.npz"
    from jointattention.datasets import save

    save(dataclasses.replace(ds, meta=meta), path)
    config = load_config({**QUICK, "datasets": str(path)})
    assert set(held_out_sets(config)) == {"training"}
    given = load_config({**QUICK, "datasets": str(path), "experiment": {
        **QUICK["experiment"], "held_out": {"caregivers": str(path)}}})
    assert set(held_out_sets(given)) == {"training", "unseen caregivers"}
    assert len(load(path)) == 125


def test_a_configuration_has_one_source_of_training_sets():
    """A data-set file and a recording together are refused, naming both."""
    with pytest.raises(ConfigError, match="one source of training sets"):
        load_config({"datasets": "x.npz", "recording": {"caregivers": 4}})


def test_a_recorded_run_measures_new_poses_of_its_own_caregivers(needs_gl, tmp_path,
                                                                  monkeypatch):
    """With [recording], new poses are of the recorded caregivers, unseen ones are others.

    The new poses' caregivers have novelty 0, the unseen ones above 0.
    """
    monkeypatch.setenv("JOINTATTENTION_CACHE", str(tmp_path))
    config = load_config({**QUICK, "recording": {"caregivers": 2, "poses_per_caregiver": 3,
                                                 "seed": 5},
                          "experiment": {**QUICK["experiment"], "held_out": {
                              "n_poses": 4, "n_caregivers": 2, "poses_per_caregiver": 2}}})
    sets = held_out_sets(config)
    world = config.world
    trained = caregivers_of(sets["training"], world)
    assert len(sets["training"]) == 6 and len(trained) == 2
    assert set(map(repr, caregivers_of(sets["new poses"], world))) == set(map(repr, trained))
    assert not set(map(repr, caregivers_of(sets["unseen caregivers"], world))) & set(
        map(repr, trained))
    assert len(list((tmp_path / "datasets").glob("*.npz"))) == 3  # each recorded once, kept
    novelty = held_out_novelty(config)  # how new each held-out caregiver is
    assert np.all(novelty["new poses"] == 0) and np.all(novelty["unseen caregivers"] > 0)
    assert held_out_novelty(load_config(QUICK))["unseen caregivers"].size == 16


def test_held_out_errors_are_measured_on_the_probes_data_sets_of_a_large_kind(model):
    """Beyond probe_datasets a kind's errors are those of its probed sets; its success is not."""
    # 300: the 400 unseen caregivers' sets are probed; the 125 training and 250 new poses' not
    some = load_config({**QUICK, "experiment": {**QUICK["experiment"], "probe_datasets": 300}})
    every = load_config({**QUICK, "experiment": {**QUICK["experiment"], "probe_datasets": 0}})
    unseen = held_out_sets(some)["unseen caregivers"]
    out_some, out_every = (measure_held_out(model.agent, c, 3) for c in (some, every))
    frozen = freeze(model.agent)
    assert np.array_equal(out_some[1:4, 2], _errors(frozen, probe_sets(unseen, 300, some.seed)))
    assert np.array_equal(out_every[1:4, 2], _errors(frozen, unseen))
    assert not np.array_equal(out_some[1:4, 2], out_every[1:4, 2])
    assert out_some[0, 2] == out_every[0, 2]  # success: trials drawn from all its sets
    assert np.array_equal(out_some[:, :2], out_every[:, :2], equal_nan=True)


def test_a_model_s_caregivers_are_read_as_identities_or_refused(model):
    """learned_from reads a model's caregivers; a malformed one is one FileError naming it."""
    from jointattention.experiment.evaluate import learned_from

    assert learned_from(dataclasses.replace(model, caregivers=None)) is None
    people = learned_from(model)
    assert len(people) == 1 and people[0].head_scale > 0
    bad = dataclasses.replace(model, caregivers=({"head_scale": "big"},))
    with pytest.raises(FileError, match=r"m\.npz: field 'meta\.caregivers\[0\]': head_scale"):
        learned_from(bad, "m.npz")
