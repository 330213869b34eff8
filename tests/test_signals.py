"""Signals during a 2-worker run: no process is left behind, finished cells are kept."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

STOP_S = 2.0  # the documented bound on stopping after a signal (docs/bad-input.md)
BUSY = 10  # what the tests allow of a bound: the machine may be shared (CI, other jobs)

# Cells of about 2 s each, so that the signal, sent when the first cell is written, comes
# while the others still run, even on a busy machine.
CONFIG = """
[experiment]
n_steps = 600000
n_seeds = 3
bin_steps = 100000
n_ceiling_trials = 50
[[experiment.conditions]]
name = "n1"
n_objects = 1
[[experiment.conditions]]
name = "n3"
n_objects = 3
"""


def _children(pid: int) -> set[int]:
    """The processes whose parent is ``pid`` (from /proc)."""
    kids = set()
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid:
            kids.add(int(stat.parent.name))
    return kids


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


def _at_a_terminal() -> None:
    """Ctrl-C as at a terminal: a test run started in the background inherits SIGINT ignored."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _reproduce(tmp: Path, out: str) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "jointattention", "reproduce", "--config",
                             str(tmp / "c.toml"), "--out", str(tmp / out), "--workers", "2"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                            preexec_fn=_at_a_terminal)


@pytest.fixture(scope="module")
def reference(tmp_path_factory) -> Path:
    """An uninterrupted run of the configuration."""
    tmp = tmp_path_factory.mktemp("signals")
    (tmp / "c.toml").write_text(CONFIG)
    proc = _reproduce(tmp, "whole")
    assert proc.wait(600) == 0, proc.stderr.read()
    return tmp


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
@pytest.mark.parametrize(("signum", "status"), [(signal.SIGTERM, 143), (signal.SIGINT, 130),
                                                (signal.SIGKILL, -9)])
def test_a_signal_leaves_no_worker_and_a_rerun_is_identical(reference, signum, status):
    """The run stops (within 10x its 2 s bound), leaves no worker, and re-runs byte for byte."""
    tmp, out = reference, f"cut-{signum}"
    proc = _reproduce(tmp, out)
    workers: set[int] = set()
    deadline = time.monotonic() + 300
    while not any((tmp / out / "cells").glob("*.npz")) and time.monotonic() < deadline:
        workers |= _children(proc.pid)
        time.sleep(0.05)
    workers |= _children(proc.pid)
    assert workers, "the run started no worker processes"
    proc.send_signal(signum)
    sent = time.monotonic()
    assert proc.wait(60) == status, proc.stderr.read()
    stop_s = time.monotonic() - sent
    assert stop_s <= BUSY * STOP_S, f"the run took {stop_s:.1f} s to stop"
    if signum != signal.SIGKILL:
        assert "Traceback" not in proc.stderr.read()
    deadline = time.monotonic() + BUSY * STOP_S  # the kernel ends orphans of SIGKILL promptly
    while any(_alive(w) for w in workers) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not any(_alive(w) for w in workers), "a worker outlived its parent"
    kept = sorted(p.name for p in (tmp / out / "cells").glob("*.npz"))
    assert 1 <= len(kept) < 6
    assert _reproduce(tmp, out).wait(600) == 0
    whole = sorted((tmp / "whole" / "cells").glob("*.npz"))
    assert [p.name for p in whole] == sorted(p.name for p in (tmp / out / "cells").glob("*"))
    for p in whole:
        assert (tmp / out / "cells" / p.name).read_bytes() == p.read_bytes(), p.name
    for name in ("table.csv", "claims.csv"):
        assert (tmp / out / name).read_bytes() == (tmp / "whole" / name).read_bytes(), name


def _sleep(seconds: float) -> float:
    time.sleep(seconds)
    return seconds


def test_stopped_workers_leave_no_pipe_for_the_exit_hook_to_race():
    """After the workers are stopped, the pool's manager thread has ended and closed its pipe.

    Were it still closing the pipe, the interpreter's exit hook could write to it as it closed
    ("OSError: Bad file descriptor" after Ctrl-C, Python 3.11).
    """
    from jointattention.experiment.backends import _pool, _stop_workers

    pool = _pool(2)
    futures = [pool.submit(_sleep, 30.0) for _ in range(4)]
    while not any(f.running() for f in futures):
        time.sleep(0.01)
    manager = pool._executor_manager_thread
    _stop_workers(pool)
    assert not manager.is_alive()


def test_the_fast_world_imports_nothing_of_opengl(tmp_path):
    """A fast-mode run with an OpenGL backend that cannot start imports neither MuJoCo nor GL."""
    (tmp_path / "c.toml").write_text(CONFIG.replace("200000", "2000").replace("n_seeds = 3",
                                                                              "n_seeds = 1"))
    code = ("import sys\nfrom jointattention.cli import main\n"
            "assert main(['reproduce', '--config', 'c.toml', '--out', 'r', '--workers', '1']) "
            "== 0\nprint([m for m in sys.modules if m.split('.')[0] in ('mujoco', 'OpenGL')])")
    env = {**os.environ, "MUJOCO_GL": "osmesa", "PYOPENGL_PLATFORM": "osmesa"}
    proc = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip().splitlines()[-1] == "[]"
