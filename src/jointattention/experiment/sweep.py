"""Sweeps: a grid of configurations x the conditions x the seeds, from a TOML spec.

A spec::

    base = "quick"                    # a preset, or a TOML file relative to the spec
    [set]                             # optional: settings changed for every point
    "experiment.n_seeds" = 3
    [grid]                            # dotted settings -> values; the sweep is their product
    "model.learning_rate" = [0.0003, 0.001]
    "model.n_hidden" = [7, 14]
    [[conditions]]                    # optional: replaces the base's conditions
    name = "n5-sigmoid"
    n_objects = 5

Each grid point is a run folder ``OUT/<point>/`` (as ``reproduce`` writes), so finished cells
are kept and a re-run does only the missing ones. ``OUT/summary.csv`` and ``summary.md`` give
the final success per point and condition.
"""

from __future__ import annotations

import itertools
import tomllib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._fields import from_mapping, to_mapping
from ..analysis.curves import condition_curves
from ..analysis.metrics import final_success, mean_interval
from ..analysis.tables import Table
from ..config import Config, load_config
from ..errors import ConfigError
from .backends import CellJob, check_backend, run_jobs
from .cells import run_cell
from .results import cell_path, prepare_run_dir

__all__ = ["Sweep", "load_sweep", "run_sweep", "summarise"]

_SPEC_KEYS = ("base", "set", "grid", "conditions")


@dataclass(frozen=True)
class Sweep:
    """A parsed spec: the grid's keys, and one configuration per point, by point name."""

    keys: tuple[str, ...]
    points: dict[str, Config]
    values: dict[str, tuple]


def _apply(config: Config, changes: dict, where: str) -> Config:
    data = to_mapping(config)
    for dotted, value in changes.items():
        *sections, field = dotted.split(".")
        node = data
        for s in sections:
            if not isinstance(node.get(s), dict):
                raise ConfigError(f"{where}: {dotted!r}: no section {s!r}; expected a dotted "
                                  "setting such as \"model.learning_rate\"")
            node = node[s]
        node[field] = value
    return from_mapping(Config, data)


def _point_name(keys, values) -> str:
    short = [k.rsplit(".", 1)[-1] for k in keys]
    names = short if len(set(short)) == len(short) else list(keys)
    parts = [f"{n}={v}" for n, v in zip(names, values, strict=True)]
    return ",".join(parts).replace("/", "_") or "base"


def load_sweep(path: str | Path) -> Sweep:
    """Read and check a sweep spec (see the module's docstring)."""
    path = Path(path)
    try:
        spec = tomllib.loads(path.read_text(encoding="utf-8"))
    except OSError as err:
        raise ConfigError(f"{path}: cannot read the sweep spec ({err.strerror})") from None
    except tomllib.TOMLDecodeError as err:
        raise ConfigError(f"{path}: not valid TOML ({err})") from None
    unknown = sorted(set(spec) - set(_SPEC_KEYS))
    if unknown:
        raise ConfigError(f"{path}: {unknown[0]}: unknown key; expected {', '.join(_SPEC_KEYS)}")
    base = spec.get("base")
    if base is not None and str(base).endswith(".toml"):
        base = path.parent / base
    config = _apply(load_config(base), spec.get("set", {}), f"{path} [set]")
    if "conditions" in spec:
        config = _apply(config, {"experiment.conditions": spec["conditions"]}, str(path))
    grid = spec.get("grid", {})
    for key, values in grid.items():
        if not isinstance(values, list) or not values:
            raise ConfigError(f"{path} [grid]: {key} = {values!r}: expected a non-empty list")
    keys = tuple(grid)
    points, values = {}, {}
    for combo in itertools.product(*grid.values()):
        name = _point_name(keys, combo)
        points[name] = _apply(config, dict(zip(keys, combo, strict=True)), f"{path} [grid]")
        values[name] = combo
    return Sweep(keys, points, values)


def _jobs(sweep: Sweep, out: Path) -> list[CellJob]:
    return [CellJob(config, c, i, cell_path(out / name, c.name, i))
            for name, config in sweep.points.items()
            for c in config.experiment.conditions
            for i in range(config.experiment.n_seeds)]


def run_sweep(sweep: Sweep, out: str | Path, *, workers: int = 1, backend: str = "local",
              address: str | None = None,
              progress: Callable[[str], None] | None = None) -> list[dict]:
    """Run the missing cells of ``sweep`` into ``out``; returns the summary rows."""
    check_backend(backend, address)
    out = Path(out)
    for name, config in sweep.points.items():
        prepare_run_dir(out / name, config)
    run_jobs(run_cell, _jobs(sweep, out), workers=workers, backend=backend, address=address,
             progress=progress, label=lambda j: (f"{j.path.parent.parent.name} "
                                                 f"{j.condition.name} seed {j.seed_index}"))
    return summarise(sweep, out)


def summarise(sweep: Sweep, out: Path) -> list[dict]:
    """Final success per point and condition, written to ``summary.csv`` and ``.md``.

    The mean and 95% interval over seeds, rounded to 3 decimals; the files go in ``out``.
    """
    rows = []
    for name, config in sweep.points.items():
        for c, (_, per_seed) in condition_curves(out / name, config).items():
            finals = [final_success(curve) for curve in per_seed]
            mean, lo, hi = (round(float(v[0]), 3)
                            for v in mean_interval(np.array(finals)[:, None]))
            rows.append({"point": name, **dict(zip(sweep.keys, sweep.values[name], strict=True)),
                         "condition": c, "seeds": len(finals), "final_success": mean,
                         "ci_low": lo, "ci_high": hi})
    columns = list(rows[0]) if rows else ["point"]
    Table(columns, [[r[k] for k in columns] for r in rows]).write(Path(out) / "summary")
    return rows
