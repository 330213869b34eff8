"""Trials and runs: determinism whatever the workers, resuming, the oracle's ceiling."""

from __future__ import annotations

import json

import numpy as np
import pytest

from jointattention import measure_ceiling, reproduce, run_cell, run_experiment
from jointattention.analysis.diagnostics import METRICS
from jointattention.analysis.tables import read_csv
from jointattention.config import ConditionConfig, Config, ExperimentConfig
from jointattention.errors import JointAttentionError
from jointattention.experiment import results

SMALL = Config(experiment=ExperimentConfig(
    n_steps=400, n_seeds=2, conditions=(
        ConditionConfig(name="a", n_objects=3),
        ConditionConfig(name="b", n_objects=5, model={"gate": {"kind": "constant", "rate": 1.0}}))))


def test_same_seed_same_records():
    """A cell run twice gives identical records; another seed index gives others."""
    a = run_cell(SMALL, SMALL.experiment.conditions[0], 0)
    b = run_cell(SMALL, SMALL.experiment.conditions[0], 0)
    c = run_cell(SMALL, SMALL.experiment.conditions[0], 1)
    for key in a:
        assert np.array_equal(a[key], b[key])
    assert not np.array_equal(a["target"], c["target"])
    assert a["learning_time"][-1] < 400 <= a["learning_time"][-1] + a["n_steps"][-1]


def test_results_do_not_depend_on_the_number_of_workers(tmp_path):
    """One worker and two workers write the same cells."""
    one = run_experiment(SMALL, tmp_path / "one", workers=1)
    two = run_experiment(SMALL, tmp_path / "two", workers=2)
    assert one.keys() == two.keys()
    for k in one:
        for col in one[k]:
            assert np.array_equal(one[k][col], two[k][col])


def test_resume_runs_only_missing_cells(tmp_path):
    """Re-running a run folder recomputes only cells that are missing, with equal results."""
    out = tmp_path / "run"
    first = run_experiment(SMALL, out)
    missing = results.cell_path(out, "b", 1)
    missing.unlink()
    kept = results.cell_path(out, "a", 0)
    stamp = kept.stat().st_mtime_ns
    messages = []
    again = run_experiment(SMALL, out, progress=messages.append)
    assert messages[0] == "3 of 4 cells already done"
    assert kept.stat().st_mtime_ns == stamp
    assert np.array_equal(again[("b", 1)]["success"], first[("b", 1)]["success"])


def test_run_folder_of_another_configuration_is_refused(tmp_path):
    """Resuming into a folder made with another configuration is one clear error."""
    run_experiment(SMALL, tmp_path / "run")
    other = SMALL.__class__(seed=1, experiment=SMALL.experiment)
    with pytest.raises(JointAttentionError, match="another configuration"):
        run_experiment(other, tmp_path / "run")


def test_oracle_ceiling_falls_with_more_objects():
    """The oracle always succeeds with one object and less often with ten."""
    assert measure_ceiling(SMALL, 1, 200) == 1.0
    assert measure_ceiling(SMALL, 10, 300) < measure_ceiling(SMALL, 3, 300) < 1.0


def test_run_folder_of_another_version_is_refused(tmp_path):
    """A folder made by a version whose cells differ (0.1.0: one agent stream) is not resumed."""
    out = tmp_path / "run"
    run_experiment(SMALL, out)
    made = json.loads((out / "versions.json").read_text())
    (out / "versions.json").write_text(json.dumps({**made, "jointattention": "0.1.0"}))
    with pytest.raises(JointAttentionError, match=r"made by jointattention 0\.1\.0"):
        run_experiment(SMALL, out)


def test_a_run_folder_explains_itself_bin_by_bin(tmp_path):
    """diagnostics.csv: fractions per bin that add up; learning_speed.csv: a row per seed."""
    cfg = Config(experiment=ExperimentConfig(n_steps=1200, n_seeds=2, bin_steps=400,
                                             n_ceiling_trials=50, conditions=(
        ConditionConfig(name="one", n_objects=1), ConditionConfig(name="five", n_objects=5))))
    result = reproduce(cfg, tmp_path / "run")
    assert (result.out / "diagnostics.png").exists()
    rows = read_csv(result.out / "diagnostics.csv").rows
    assert [(r[0], int(r[1])) for r in rows] == [(c, t) for c in ("one", "five")
                                                 for t in (400, 800, 1200)]
    for row in rows:
        values = dict(zip(METRICS, map(float, row[2:]), strict=True))
        steps = values["lm_steps"] + values["vf_steps"] + values["random_steps"]
        ends = values["fired"] + values["step_limit"] + values["joint_limit"]
        assert steps == pytest.approx(1, abs=0.002) and ends == pytest.approx(1, abs=0.002)
        assert 0 < values["lm_error_deg"] <= 180
        if row[0] == "one" and values["fired"] > 0:
            assert values["on_target"] == 1.0  # the only object is the target
        assert 0 <= values["lm_bias"] <= 1
    cell = results.load_cell(results.cell_path(result.out, "five", 0))
    assert len(cell["lm_error_deg"]) == 3
    seeds = read_csv(result.out / "diagnostics_seeds.csv")
    assert (result.out / "diagnostics_seeds.png").exists()
    speed = read_csv(result.out / "learning_speed.csv")  # each seed's speed and final
    assert [(r[0], int(r[2])) for r in speed.rows] == [(c, i) for c in ("one", "five")
                                                       for i in (0, 1)]
    assert (result.out / "learning_speed.png").exists()
    assert [(r[0], int(r[1]), int(r[3])) for r in seeds.rows] == [
        (c, i, t) for c in ("one", "five") for i in (0, 1) for t in (400, 800, 1200)]
    by_key = {(r[0], int(r[3])): [] for r in seeds.rows}
    for r in seeds.rows:  # the mean over seeds is diagnostics.csv's row
        by_key[(r[0], int(r[3]))].append(float(r[4 + list(METRICS).index("lm_error_deg")]))
    for row in rows:
        assert np.mean(by_key[(row[0], int(row[1]))]) == pytest.approx(
            float(row[2 + list(METRICS).index("lm_error_deg")]), abs=0.002)


def test_a_rerun_that_only_redraws_keeps_the_measured_time(tmp_path):
    """timing.json keeps the wall time of the call that ran the cells, not of a redraw."""
    cfg = Config(experiment=ExperimentConfig(n_steps=400, n_seeds=1, bin_steps=200,
                                             n_ceiling_trials=20, conditions=(
        ConditionConfig(name="one", n_objects=1),)))
    reproduce(cfg, tmp_path / "run")
    first = json.loads((tmp_path / "run" / "timing.json").read_text())
    reproduce(cfg, tmp_path / "run")
    assert json.loads((tmp_path / "run" / "timing.json").read_text()) == first
    assert first["cells_run"] == 1
    assert 0 <= first["cells_min"] <= first["wall_min"]  # the whole call: cells and outputs


def test_the_time_to_90pct_never_exceeds_the_learning_time():
    """With bins wider than the run (one bin ends at n_steps), the time is n_steps, not the bin."""
    from jointattention.analysis.metrics import time_to_fraction

    exp = ExperimentConfig(n_steps=2000, bin_steps=10**9, conditions=SMALL.experiment.conditions)
    assert list(exp.bin_ends_steps()) == [2000]
    assert time_to_fraction(np.array([0.5]), exp.bin_ends_steps()) == 2000
    exp = ExperimentConfig(n_steps=2500, bin_steps=1000, conditions=SMALL.experiment.conditions)
    curve = np.array([0.1, 0.2, 0.6])
    assert time_to_fraction(curve, exp.bin_ends_steps()) == 2500  # the last bin ends early


def test_the_probe_s_angle_errors_are_angle_deg_row_by_row():
    """The probe's errors, in one pass, are angle_deg of each output and command, bit for bit."""
    from jointattention.datasets import default_datasets
    from jointattention.experiment.probes import _angle_errors_of, angle_deg

    ds = default_datasets()
    out = np.random.default_rng(0).normal(size=(len(ds), 2)) * 0.03
    out[:5] = ds.command_rad[:5] * 2.0  # parallel: the clip
    rows = np.array([angle_deg(o, c) for o, c in zip(out, ds.command_rad, strict=True)])
    assert np.array_equal(_angle_errors_of(out, ds), rows)


def test_the_probe_measures_a_fixed_draw_of_many_data_sets():
    """Beyond probe_datasets, the probe takes the same draw each time, in order; else all."""
    from jointattention.datasets import default_datasets
    from jointattention.experiment.probes import probe_sets

    ds = default_datasets()
    assert probe_sets(ds, 125, 0) is ds and probe_sets(ds, 0, 0) is ds
    a, b, other = probe_sets(ds, 40, 0), probe_sets(ds, 40, 0), probe_sets(ds, 40, 1)
    assert len(a) == 40 and np.array_equal(a.face, b.face)
    assert not np.array_equal(a.face, other.face)
    rows = [int(np.flatnonzero((ds.theta_face_rad == t).all(axis=1))[0])
            for t in a.theta_face_rad]
    assert rows == sorted(rows) and np.array_equal(ds.command_rad[rows], a.command_rad)


@pytest.mark.parametrize("n_objects", [1, 5, 10])
def test_the_compiled_oracle_wins_the_step_by_step_oracle_s_trials(n_objects):
    """The ceiling's compiled loop ends on the target exactly when OracleAgent's trials do."""
    from jointattention.datasets import default_datasets
    from jointattention.experiment.cells import evaluator, oracle_wins, random_scene
    from jointattention.experiment.oracle import OracleAgent
    from jointattention.experiment.trial import SceneTrial, run_trial
    from jointattention.rng import stream
    from jointattention.world.kinematics import HeadKinematics

    config, ds = Config(), default_datasets()
    kin, step = HeadKinematics.from_config(config.world), np.deg2rad(config.agent.lm_step_deg)
    rng, wins = stream(3, "ceiling", n_objects), 0
    for _ in range(300):
        k, scene, _ = random_scene(config, ds, kin, n_objects, rng)
        trial = SceneTrial(scene, ds.theta_face_rad[k], kinematics=kin,
                           max_steps=config.agent.max_steps, evaluate=evaluator(config))
        wins += run_trial(trial, OracleAgent(ds.theta_face_rad[k] + ds.command_rad[k], step),
                          ds.face[k]).success
    compiled = stream(3, "ceiling", n_objects)
    assert oracle_wins(ds, config, n_objects, 300, compiled) == wins
    assert compiled.random() == rng.random()  # the same draws, to the last
    assert 0 < wins <= 300
