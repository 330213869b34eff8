"""Shared fixtures: a world per test, a skip where no off-screen OpenGL exists, no deadlines."""

from __future__ import annotations

import os

import matplotlib
import pytest
from hypothesis import HealthCheck, settings

from jointattention.world.gl import suggested_backend

# No wall-clock limits in the tests (times are measured by `jointattention bench`): a first
# example may compile a kernel or start a process, and the machine may be shared, so
# Hypothesis's deadline and its too-slow health check would fail on load, not on behaviour.
settings.register_profile("jointattention", deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])
settings.load_profile("jointattention")

matplotlib.use("Agg")
os.environ.setdefault("MPLBACKEND", "Agg")
# The tests choose MuJoCo's off-screen backend as the command line does (the library only
# reads MUJOCO_GL); subprocesses and workers inherit it.
os.environ.setdefault("MUJOCO_GL", suggested_backend())


@pytest.fixture(scope="session")
def gl_available() -> bool:
    """Whether a world can render here (EGL or OSMesa)."""
    from jointattention.errors import RenderingUnavailable
    from jointattention.world.simulator import World

    try:
        with World(seed=0) as world:
            world.render()
    except RenderingUnavailable:
        return False
    return True


@pytest.fixture
def needs_gl(gl_available: bool) -> None:
    """Skip the test where no world can render."""
    if not gl_available:
        pytest.skip("no off-screen OpenGL (EGL or OSMesa) on this machine")
