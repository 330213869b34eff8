"""Benchmarks: figures printed, never asserted (machines here are shared and noisy)."""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from .config import WorldConfig

__all__ = ["preset_estimates", "run_agent_benchmark", "run_env_benchmark", "run_preset",
           "run_world_benchmarks"]


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
        scene = world.fast_scene()
        rows.append(
            (
                "fast projection (all objects, one head angle)",
                _rate(lambda i: scene.observe(thetas[i]), n_projections),
                "projections/s",
            )
        )
        rows.append(("new scene (sample + show)", _rate(lambda i: world.reset(), 200), "scenes/s"))
    return rows


def run_env_benchmark(n_steps: int = 600) -> list[tuple[str, float, str]]:
    """Steps per second of ``JointAttention-v0`` under random actions, resets included.

    Each step renders, detects and evaluates; empty if Gymnasium is not installed.
    """
    try:
        from .env import JointAttentionEnv
    except ImportError:
        return []
    env = JointAttentionEnv()
    env.reset(seed=0)
    env.action_space.seed(0)
    start = time.perf_counter()
    for _ in range(n_steps):
        *_, terminated, truncated, _ = env.step(env.action_space.sample())
        if terminated or truncated:
            env.reset()
    rate = n_steps / (time.perf_counter() - start)
    env.close()
    return [("JointAttention-v0 steps, random actions (rendered)", rate, "steps/s")]


def run_agent_benchmark(rendered_steps: int = 2000) -> list[tuple[str, float, str]]:
    """Agent-steps per second of learning, in fast and in rendered mode.

    The quick preset's 5-object sigmoid cell in fast mode (whose gate goes from the visual
    controller to the learning module), and its first ``rendered_steps`` steps in rendered mode
    (MuJoCo render + OpenCV detection each step).
    """
    import dataclasses

    from .config import load_config
    from .experiment.cells import run_cell

    config = load_config("quick")
    cond = next(c for c in config.experiment.conditions if c.name == "n5-sigmoid")
    start = time.perf_counter()
    run_cell(config, cond, 0)
    fast = config.experiment.n_steps / (time.perf_counter() - start)
    exp = dataclasses.replace(config.experiment, n_steps=rendered_steps, perception="rendered",
                              engine="python")
    start = time.perf_counter()
    run_cell(dataclasses.replace(config, experiment=exp), cond, 0)
    rendered = rendered_steps / (time.perf_counter() - start)
    return [("agent steps, fast mode, learning (quick n5-sigmoid)", fast, "steps/s"),
            ("agent steps, rendered mode + OpenCV, learning (same cell)", rendered, "steps/s"),
            ("fast / rendered", fast / rendered, "x")]


def preset_estimates(fast_steps_per_s: float, rendered_steps_per_s: float,
                     workers: int) -> list[tuple[str, float, str]]:
    """Estimated wall time of each shipped preset.

    Its agent-steps over ``workers`` processes at the rate of its perception mode (``reproduce``
    records the measured time).
    """
    from .config import load_config, preset_names

    rows = []
    for name in preset_names():
        exp = load_config(name).experiment
        rate = rendered_steps_per_s if exp.perception == "rendered" else fast_steps_per_s
        cells = len(exp.conditions) * exp.n_seeds
        rounds = np.ceil(cells / workers)  # cells are the unit of parallel work
        rows.append((f"preset {name}: {cells} cells on {workers} workers (estimate)",
                     rounds * exp.n_steps / rate / 60, "min"))
    return rows


def run_preset(name: str, workers: int) -> list[tuple[str, float, str]]:
    """Measured wall time of running preset ``name`` from scratch (in a temporary folder)."""
    import tempfile

    from .config import load_config
    from .experiment.reproduce import run_experiment

    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        run_experiment(load_config(name), tmp, workers=workers)
        wall = time.perf_counter() - start
    return [(f"preset {name}: cells on {workers} workers (measured)", wall / 60, "min")]
