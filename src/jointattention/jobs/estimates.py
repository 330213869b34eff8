"""Each shipped preset's wall time: estimated from the bench's agent rates, or measured."""

from __future__ import annotations

import time

import numpy as np

from .bench import AGENT_RATE_ROWS

__all__ = ["agent_rates", "preset_estimates", "run_preset"]


def agent_rates(rows: list[tuple[str, float, str]]) -> dict[str, float]:
    """The rates :func:`preset_estimates` takes, found by name among the bench's ``rows``.

    Each kind of cell's rate is the row :data:`~.bench.AGENT_RATE_ROWS` names, wherever the
    bench prints it.
    """
    by_name = {name: value for name, value, _ in rows}
    return {kind: by_name[name] for kind, name in AGENT_RATE_ROWS.items()}


def preset_estimates(rates: dict[str, float], workers: int) -> list[tuple[str, float, str]]:
    """Estimated wall time of each shipped preset.

    Its agent-steps over ``workers`` processes, each cell at the rate of its engine, perception
    or learner (``rates``: "compiled", "python", "rendered", "memory", "rl", "population");
    ``reproduce`` records the measured time (held-out measures and recordings not estimated).
    """
    from ..config import load_config, model_options, preset_names
    from ..experiment.cells import engine_of
    from ..models.registry import MODELS

    rows = []
    for name in preset_names():
        config = load_config(name)
        exp, minutes = config.experiment, 0.0
        for c in exp.conditions:
            kind = "rendered" if exp.perception == "rendered" else engine_of(config, c)
            options = model_options(config, c)
            if getattr(options, "learner", "") in ("memory", "population"):
                kind = options.learner
            elif MODELS.name_of(options) == "rl":
                kind = "rl"
            minutes += exp.n_seeds * exp.n_steps / rates[kind] / 60
        cells = len(exp.conditions) * exp.n_seeds
        rounds = np.ceil(cells / workers)  # cells are the unit of parallel work
        rows.append((f"preset {name}: {cells} cells on {workers} workers (estimate)",
                     minutes / cells * rounds, "min"))
    return rows


def run_preset(name: str, workers: int) -> list[tuple[str, float, str]]:
    """Measured wall time of running preset ``name`` from scratch (in a temporary folder)."""
    import tempfile

    from ..config import load_config
    from .reproduce import run_experiment

    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        run_experiment(load_config(name), tmp, workers=workers)
        wall = time.perf_counter() - start
    return [(f"preset {name}: cells on {workers} workers (measured)", wall / 60, "min")]
