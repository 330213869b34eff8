"""The reinforcement-learning example runs: Stable-Baselines3's PPO on the face mode."""

from __future__ import annotations

import csv
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.rl
EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "rl_ppo.py"


def test_the_ppo_example_trains_a_few_hundred_steps(tmp_path):
    """``examples/rl_ppo.py --smoke`` trains PPO on v2, runs the bootstrap model, writes curves."""
    pytest.importorskip("stable_baselines3", reason="needs the rl extra: make test-rl")
    proc = subprocess.run([sys.executable, str(EXAMPLE), "--smoke", "--n-objects", "3",
                           "--out", str(tmp_path)], capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    with open(tmp_path / "curves.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert {r["model"] for r in rows} == {"ppo", "bootstrap", "random"}
    assert all(0 <= float(r["success"]) <= 1 for r in rows if r["success"] != "nan")
    assert (tmp_path / "curves.png").stat().st_size > 1000
    assert "| 3 |" in proc.stdout
    assert (tmp_path / "curves.md").read_text().splitlines()[2].startswith("| 3 |")
    assert "out of date" not in proc.stderr  # the example makes current (v2) ids
