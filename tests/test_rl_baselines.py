"""The baselines command runs: every algorithm family, the runner's learners, the floor."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytestmark = pytest.mark.rl
ROOT = Path(__file__).resolve().parents[1]


def test_the_baselines_command_writes_one_row_per_learner_in_quick_mode(tmp_path):
    """``rl_baselines.py --quick``: every row, a resumed run, ``--finished-only``, ``--merge``."""
    pytest.importorskip("stable_baselines3", reason="needs the rl extra: make test-rl")
    proc = subprocess.run([sys.executable, str(ROOT / "examples" / "rl_baselines.py"),
                           "--quick", "--out", str(tmp_path)], capture_output=True, text=True,
                          timeout=900)
    assert proc.returncode == 0, proc.stderr
    table = (tmp_path / "baselines.md").read_text().splitlines()
    learners = [row.split(" | ")[0].lstrip("| ") for row in table[2:] if row.startswith("| ")]
    assert learners == ["PPO", "A2C", "SAC", "TD3", "DQN", "A2C, learning_rate=2e-4",
                        "DQN, gamma=0.9", "TD3, action_noise=N(0, 0.1)",
                        "TD3, action_noise=N(0, 0.1), learning_rate=1e-4",
                        "own RL model (kind rl), runner",
                        "bootstrap model (paper), runner", "random actions", "random actions"]
    for dqn in (row for row in table if row.startswith("| DQN")):
        assert "JointAttentionFace-N1-Discrete-v2" in dqn
    learned = len(learners) - 2  # every row but the floor's two
    for row in table[2:2 + learned]:
        cells = row.strip("| ").split(" | ")
        values = [float(c.split(" ")[0]) for c in cells[2:9] if c != "-"]
        assert all(0 <= v <= 1 for v in values) and len(values) >= 4
    runs = json.loads((tmp_path / "baselines_runs.json").read_text())
    assert len(runs) == learned
    again = subprocess.run([sys.executable, str(ROOT / "examples" / "rl_baselines.py"),
                            "--quick", "--algos", "td3", "--out", str(tmp_path)],
                           capture_output=True, text=True, timeout=900)
    assert again.returncode == 0 and "td3 seed 0" in again.stdout  # resumed: no retraining
    assert json.loads((tmp_path / "baselines_runs.json").read_text()) == runs
    # --finished-only: a run not finished is a row that says so, and nothing is trained
    td3 = next(key for key in runs if key.startswith("td3 "))
    elsewhere = {td3: runs.pop(td3)}
    (tmp_path / "baselines_runs.json").write_text(json.dumps(runs))
    table_only = subprocess.run([sys.executable, str(ROOT / "examples" / "rl_baselines.py"),
                                 "--quick", "--finished-only", "--out", str(tmp_path)],
                                capture_output=True, text=True, timeout=900)
    assert table_only.returncode == 0, table_only.stderr
    assert json.loads((tmp_path / "baselines_runs.json").read_text()) == runs
    rows = {row.split(" | ")[0].lstrip("| "): row.strip("| ").split(" | ")
            for row in (tmp_path / "baselines.md").read_text().splitlines()[2:2 + learned]}
    assert rows["TD3"][2] == "not yet run" and rows["TD3"][-1] == "none"
    assert rows["SAC"][-1] == "0" and rows["SAC"][2] != "-"
    # --merge: a run finished in another output folder joins this one's table
    # (and a run both folders hold stays as this folder has it)
    sac = next(key for key in runs if key.startswith("sac "))
    (tmp_path / "td3-alone").mkdir()
    (tmp_path / "td3-alone" / "baselines_runs.json").write_text(
        json.dumps(elsewhere | {sac: runs[sac] | {"minutes": -1.0}}))
    joined = subprocess.run([sys.executable, str(ROOT / "examples" / "rl_baselines.py"),
                             "--quick", "--finished-only", "--out", str(tmp_path),
                             "--merge", str(tmp_path / "td3-alone")],
                            capture_output=True, text=True, timeout=900)
    assert joined.returncode == 0, joined.stderr
    assert json.loads((tmp_path / "baselines_runs.json").read_text()) == runs | elsewhere
    assert "| TD3 | JointAttentionFace-N1-v2 | " in (tmp_path / "baselines.md").read_text()


def _baselines_module():
    """examples/rl_baselines.py as a module."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("rl_baselines",
                                                  ROOT / "examples" / "rl_baselines.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_an_off_policy_run_continues_from_its_checkpoint(tmp_path):
    """A stopped SAC run continues from its saved step count, episodes and replay buffer."""
    pytest.importorskip("stable_baselines3", reason="needs the rl extra: make test-rl")
    baselines = _baselines_module()
    checkpoint = tmp_path / "sac"
    model, ends, _, _ = baselines.train("sac", 1, 300, 0, True, checkpoint, every=100)
    saved = json.loads((checkpoint / "log.json").read_text())
    assert saved["steps"] == 200 and model.num_timesteps == 300  # none saved at the end
    assert [f.name for f in checkpoint.glob("at-*")] == ["at-200"]  # the one before: gone
    assert saved["ends"] == [e for e in ends.tolist() if e <= 200]
    rows = model.replay_buffer.pos
    again, ends_again, _, seconds = baselines.train("sac", 1, 300, 0, True, checkpoint, 100)
    assert again.num_timesteps == 300 and seconds >= saved["seconds"]
    assert ends_again.tolist()[:len(saved["ends"])] == saved["ends"]
    assert again.replay_buffer.pos == rows  # 200 restored, 100 new
    stored = np.load(checkpoint / "at-200" / "replay.npz")
    np.testing.assert_array_equal(again.replay_buffer.actions[:200], stored["actions"])


@pytest.mark.parametrize("content", [None, "{not json", '{"ppo | N1": 3}'])
def test_merging_a_folder_without_runs_is_one_error_line_and_writes_nothing(tmp_path,
                                                                            content):
    """``--merge`` of a folder with no, broken or foreign runs: one line, nothing written."""
    other = tmp_path / "other"
    other.mkdir()
    if content is not None:
        (other / "baselines_runs.json").write_text(content)
    proc = subprocess.run([sys.executable, str(ROOT / "examples" / "rl_baselines.py"),
                           "--finished-only", "--out", str(tmp_path / "out"),
                           "--merge", str(other)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert proc.stderr.strip().splitlines()[-1].startswith("rl_baselines.py: error: --merge ")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("args, wrong", [
    (["--steps", "0"], "--steps 0: "), (["--steps", "1.5"], "--steps 1.5: "),
    (["--episodes", "0"], "argument --episodes: 0: expected an integer in [1, "),
    (["--checkpoint-every", "-1"], "--checkpoint-every -1: "),
    (["--seeds", "0", "-1"], "argument --seeds: -1: expected an integer in [0, "),
    (["--n-objects", "2"], "argument --n-objects: invalid choice: 2 (choose from 1, 3, 5, 10)"),
    (["--out", "{tmp}/a-file"], "--out "), (["--out", "{tmp}/broken"], "--out ")])
def test_an_argument_out_of_range_is_one_error_line_and_writes_nothing(tmp_path, args, wrong):
    """Bad steps, episodes, seeds, objects, or an --out that is a file or holds broken runs."""
    (tmp_path / "a-file").write_text("not a folder")
    (tmp_path / "broken").mkdir()
    (tmp_path / "broken" / "baselines_runs.json").write_text("{not json")
    before = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    args = [a.format(tmp=tmp_path) for a in args]
    out = [] if "--out" in args else ["--out", str(tmp_path / "out")]
    proc = subprocess.run([sys.executable, str(ROOT / "examples" / "rl_baselines.py"),
                           "--finished-only", *out, *args], capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert proc.stderr.strip().splitlines()[-1].startswith(f"rl_baselines.py: error: {wrong}")
    assert not (tmp_path / "out").exists()
    assert {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()} == before
