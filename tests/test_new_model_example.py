"""The example of a model from outside the package runs in the compiled engine."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "new_model.py"


def test_the_new_model_example_passes_check_agent_and_runs_compiled():
    """``examples/new_model.py``: check_agent passes the compass, and a cell of it ran compiled."""
    proc = subprocess.run([sys.executable, str(EXAMPLE)], capture_output=True, text=True,
                          timeout=900, env={**os.environ, "MUJOCO_GL": "egl"})
    assert proc.returncode == 0, proc.stderr
    assert "check_agent: the compass passes" in proc.stdout
    assert "ran compiled (engine 'compiled')" in proc.stdout
