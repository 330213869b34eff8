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


@pytest.fixture(scope="session")
def socket_run():
    """A tiny people-world run that keeps socket patches, and its model (2,000 steps)."""
    import dataclasses

    from jointattention import train
    from jointattention.agent.gates import SigmoidGate
    from jointattention.config import Config, ExperimentConfig, load_config
    from jointattention.config.run import RecordingConfig
    from jointattention.models.bootstrap import BootstrapOptions
    from jointattention.world.options import EyeWindowConfig

    eyes = EyeWindowConfig(width_px=64, height_px=24, span=2.67, placement_sd=0.1,
                           socket_patch_px=12)
    run = Config(
        model=BootstrapOptions(learner="population",
                               gate=SigmoidGate(midpoint_steps=1500.0, width_steps=500.0)),
        world=dataclasses.replace(load_config("people").world, eye_window=eyes),
        recording=RecordingConfig(caregivers=3, poses_per_caregiver=4, seed=7),
        experiment=ExperimentConfig(n_steps=2000, n_seeds=1))
    return run, train(run, run.experiment.conditions[0].name)
