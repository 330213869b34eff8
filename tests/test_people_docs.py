"""The people world's scripts under docs/results/people run, small, and write their tables."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from jointattention.config import load_config
from jointattention.experiment.training import train

DOCS = Path(__file__).resolve().parents[1] / "docs" / "results" / "people"


def _run(script: str, *args: str) -> str:
    proc = subprocess.run([sys.executable, str(DOCS / script), *args], capture_output=True,
                          text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout


def test_the_head_pose_bound_is_written_for_each_world(tmp_path):
    """head_pose_bound.py writes a row per world; knowing the eyes reads the people world best."""
    out = tmp_path / "bound.md"
    _run("head_pose_bound.py", "--scenes", "600", "--out", str(out))
    rows = [r for r in out.read_text().splitlines() if r.startswith("| people |")]
    head, gaze = (float(c.strip(" °")) for c in rows[0].split("|")[2:5:2])
    assert gaze < head


def test_the_robustness_table_has_a_row_per_group_and_object_count(tmp_path, needs_gl,
                                                                    monkeypatch):
    """robustness.py measures a saved model on each widened world, with 5 and 10 objects."""
    monkeypatch.setenv("JOINTATTENTION_CACHE", str(tmp_path / "cache"))
    config = load_config({"recording": {"caregivers": 3, "poses_per_caregiver": 4, "seed": 1},
                          "experiment": {"n_steps": 2000, "n_seeds": 1, "bin_steps": 1000,
                                         "n_ceiling_trials": 50,
                                         "held_out": {"n_trials": 20, "n_checkpoints": 1}}})
    model = train(config, "n5-sigmoid").save(tmp_path / "m.npz")
    out = tmp_path / "robustness.md"
    _run("robustness.py", str(model), "--caregivers", "2", "--poses", "2", "--trials", "20",
         "--out", str(out))
    rows = [r for r in out.read_text().splitlines() if r.startswith(f"| `{model}`")]
    # its own world, nine groups, all at once, the many-caregivers world (the default is its own)
    assert len(rows) == 2 * 12
    assert all("nan" not in r for r in rows)  # it learned from 3: the novelty is measured



def test_recording_the_people_world_writes_its_time(tmp_path, needs_gl):
    """record.py records the preset's caregivers and says how long it took."""
    out = tmp_path / "recording.md"
    _run("record.py", "--caregivers", "2", "--poses", "2", "--out", str(out))
    assert "4 data sets of 2 caregivers" in out.read_text()


def test_the_taught_bound_is_written_for_each_world(tmp_path, needs_gl, monkeypatch):
    """taught_bound.py teaches the network the true directions and writes a row per world."""
    monkeypatch.setenv("JOINTATTENTION_CACHE", str(tmp_path / "cache"))
    out = tmp_path / "taught.md"
    _run("taught_bound.py", "--epochs", "1", "--caregivers", "2", "--train-caregivers", "3",
         "--out", str(out))
    rows = [r for r in out.read_text().splitlines() if r.startswith("| ") and "°" in r]
    assert len(rows) == 8 and all("| 12 |" in r for r in rows)
    assert "eye window" in rows[-4] and "placed with an error" in rows[-3]
    assert "socket patches" in rows[-2] and "socket network" in rows[-1]


def test_the_closed_loop_taught_bound_stands_beside_each_run(tmp_path, needs_gl, monkeypatch):
    """taught_closed_loop.py measures each eye run's learner taught the truth, beside the run."""
    monkeypatch.setenv("JOINTATTENTION_CACHE", str(tmp_path / "cache"))
    out = tmp_path / "taught.md"
    _run("taught_closed_loop.py", "--passes", "1", "--train-caregivers", "3", "--out",
         str(out))
    rows = [r.split("|")[1:-1] for r in out.read_text().splitlines() if "°" in r]
    assert [(r[0].strip(), r[1].strip()) for r in rows] == [
        ("placed exactly", "5"), ("placed exactly", "10"),
        ("socket patches the robot finds", "5"), ("socket patches the robot finds", "10")]
    assert all(0 <= float(c) <= 2 for r in rows for c in r[2:5])  # fractions of a ceiling
    shipped = (DOCS / "belief" / "held_out.md").read_text()  # the run's own column, read
    assert all(f"| {r[6].strip()} |" in shipped for r in rows[:2])


def test_the_novelty_of_a_preset_s_held_out_sets_is_written(tmp_path):
    """novelty.py writes a row per held-out kind of each preset named."""
    out = tmp_path / "novelty.md"
    _run("novelty.py", "default", "--out", str(out))
    rows = [r for r in out.read_text().splitlines() if r.startswith("| default |")]
    assert [r.split("|")[2].strip() for r in rows] == ["new poses", "unseen caregivers"]


def test_the_ladder_is_gathered_from_the_runs_own_tables(tmp_path):
    """ladder.py writes the shipped ladder.md again, a row per run, from the runs' tables."""
    out = tmp_path / "ladder.md"
    _run("ladder.py", "--out", str(out))
    assert out.read_text() == (DOCS / "ladder.md").read_text()
    runs = [r.split("|")[1].strip(" `") for r in out.read_text().splitlines()[2:]
            if r.startswith("| `")]
    assert runs[0] == "people" and {"eyes", "sockets_net"} <= set(runs)
    sockets_net = (DOCS / "sockets_net" / "held_out.md").read_text().splitlines()[3]
    assert f"| {sockets_net.split('|')[5].strip()} (" in out.read_text()  # its 10 objects
