"""The mean-action measurement runs: PPO's mean and sampled episodes on N1 and its twin."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.rl
SCRIPT = Path(__file__).resolve().parents[1] / "scripts" / "mean_action.py"


def test_the_mean_action_script_measures_both_ids_in_quick_mode(tmp_path):
    """``scripts/mean_action.py --quick`` writes each end's share for mean and sampled actions."""
    pytest.importorskip("stable_baselines3", reason="needs the rl extra: make test-rl")
    proc = subprocess.run([sys.executable, str(SCRIPT), "--quick", "--out", str(tmp_path)],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    result = json.loads((tmp_path / "mean_action.json").read_text())
    assert list(result["ids"]) == ["JointAttentionFace-N1-v2",
                                   "JointAttentionFace-N1-Discrete-v2"]
    for env_id, measured in result["ids"].items():
        for mode in ("mean", "sampled"):
            shares = measured[mode]["shares"]
            assert measured[mode]["episodes"] == 20
            assert sum(shares.values()) == pytest.approx(1)
            assert shares["another object"] == 0  # one object: nothing else to fire on
        assert (measured["policy_std_deg"] is None) == ("Discrete" in env_id)
    table = (tmp_path / "mean_action.md").read_text().splitlines()
    assert len([row for row in table if row.startswith("| JointAttentionFace-N1")]) == 4
    assert "scripts/mean_action.py --quick" in table[-1]
