"""Shared fixtures: a world per test, and a skip where no off-screen OpenGL exists."""

from __future__ import annotations

import os

import matplotlib
import pytest

from jointattention.world.gl import suggested_backend

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
