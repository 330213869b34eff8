"""Benchmarks: figures printed, never asserted (machines here are shared and noisy)."""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from .config import WorldConfig

__all__ = ["run_agent_benchmark", "run_world_benchmarks"]


def _rate(fn: Callable[[int], object], n: int, repeats: int = 3) -> float:
    """Best of ``repeats`` runs of ``n`` calls, in calls per second."""
    best = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        for i in range(n):
            fn(i)
        best = min(best, time.perf_counter() - start)
    return n / best


def run_world_benchmarks(
    config: WorldConfig | None = None, n_frames: int = 200, n_projections: int = 20000
) -> list[tuple[str, float, str]]:
    """(name, value, unit) rows for rendering and fast projection at ``config``'s size."""
    from .world.simulator import World

    config = config if config is not None else WorldConfig()
    rows = []
    with World(config, seed=0) as world:
        rng = np.random.default_rng(0)
        thetas = world.kinematics.clip(rng.uniform(-1, 1, (max(n_frames, n_projections), 2)))
        world.render()  # start the GL context outside the timing

        def render(i: int) -> None:
            world.set_head_angle(thetas[i])
            world.render()

        size = f"{config.camera.width_px}x{config.camera.height_px}"
        rows.append(
            (
                f"render robot view ({size}, {world.state.n_objects} objects)",
                _rate(render, n_frames),
                "frames/s",
            )
        )
        rows.append(
            (
                "fast projection (all objects, one head angle)",
                _rate(lambda i: world.project(thetas[i]), n_projections),
                "projections/s",
            )
        )
        rows.append(("new scene (sample + show)", _rate(lambda i: world.reset(), 200), "scenes/s"))
    return rows


def run_agent_benchmark(n_steps: int = 20000) -> list[tuple[str, float, str]]:
    """Agent-steps per second of a learning run in fast mode (5 objects, sigmoid gate)."""
    from .config import ConditionConfig, Config, ExperimentConfig
    from .experiment import run_cell

    config = Config(experiment=ExperimentConfig(n_steps=n_steps))
    start = time.perf_counter()
    run_cell(config, ConditionConfig(n_objects=5), 0)
    return [("agent steps, fast mode, learning (5 objects)",
             n_steps / (time.perf_counter() - start), "steps/s")]
