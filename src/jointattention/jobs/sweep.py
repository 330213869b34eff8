"""Sweeps: a grid of configurations x the conditions x the seeds, from a TOML spec.

A spec::

    base = "quick"                    # a preset, or a TOML file relative to the spec
    [set]                             # optional: settings changed for every point
    "experiment.n_seeds" = 3
    [grid]                            # dotted settings -> values; the sweep is their product
    "model.learning_rate" = [0.0003, 0.001]
    "model.n_hidden" = [7, 14]
    "world.eye_window" = { none = { width_px = 0, height_px = 0 }, eyes = { width_px = 96,
                           height_px = 24 } }  # values by name: each point is named by it
    [[conditions]]                    # optional: replaces the base's conditions
    name = "n5-sigmoid"
    n_objects = 5

Each grid point is a run folder ``OUT/<point>/`` (``key=value,...``; a value given by name, as
a whole section may be, goes by its name), as ``reproduce`` writes it, so finished cells
are kept and a re-run does only the missing ones. ``OUT/summary.csv`` and ``summary.md`` give
the final success per point and condition.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._checks import UNSAFE
from .._fields import from_mapping, to_mapping
from .._files import check_writable, folder_lock
from .._readers import read_toml
from ..analysis.curves import condition_curves
from ..analysis.held_out import held_out_curves
from ..analysis.metrics import final_success, mean_interval
from ..analysis.tables import Table
from ..config import Config, load_config
from ..errors import ConfigError, FileError
from ..experiment.backends import CellJob, check_backend, run_jobs
from ..experiment.held_out import held_out_sets, run_cell_measured
from ..experiment.preflight import MAX_CELLS, check_runs
from ..experiment.results import cell_path, prepare_run_dir

__all__ = ["Sweep", "load_sweep", "run_sweep", "summarise"]

_SPEC_KEYS = ("base", "set", "grid", "conditions")


@dataclass(frozen=True)
class Sweep:
    """A parsed spec: the grid's keys, and one configuration per point, by point name.

    ``values``: each point's values, as named (a value given by name goes by its name).
    """

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
    """The point's folder name: ``key=value,...``, any character unsafe in a file name as _."""
    short = [k.rsplit(".", 1)[-1] for k in keys]
    names = short if len(set(short)) == len(short) else list(keys)
    parts = [f"{n}={v}" for n, v in zip(names, values, strict=True)]
    return UNSAFE.sub("_", ",".join(parts))[:200] or "base"


def _read_grid(grid: object, where: str, max_cells: int) -> dict[str, list[tuple]]:
    """The grid table, checked: each setting's (name, value) pairs, at most ``max_cells`` points.

    A setting takes a non-empty list of distinct values (each named by its text) or a table
    of values by name.
    """
    if not isinstance(grid, dict):
        raise ConfigError(f"{where}: grid = {grid!r}: expected a table of settings -> lists")
    n_points, named = 1, {}
    for key, values in grid.items():
        if isinstance(values, dict) and values:
            named[key] = list(values.items())
            values = list(values.values())
        elif not isinstance(values, list) or not values:
            raise ConfigError(f"{where} [grid]: {key} = {values!r}: expected a non-empty list, "
                              "or a table of values by name")
        else:
            named[key] = [(v, v) for v in values]
        seen = []  # 1e-3 and 0.001 are one value; true and 1 are two
        for v in values:
            same = repr(v) if isinstance(v, (dict, list)) else (type(v) is bool, v)
            if same in seen:
                raise ConfigError(f"{where} [grid]: {key} = {values!r}: {v!r} repeats; "
                                  "expected distinct values")
            seen.append(same)
        n_points *= len(values)
        if n_points > max_cells:
            raise ConfigError(f"{where} [grid]: more than {max_cells:,} points; expected at "
                              "most that many (--max-cells raises the bound)")
    return named


def load_sweep(path: str | Path, *, max_cells: int = MAX_CELLS) -> Sweep:
    """Read and check a sweep spec (see the module's docstring).

    A spec with none of its keys is refused (it would run the whole default experiment), and so
    is a grid of more than ``max_cells`` points.
    """
    path = Path(path)
    try:
        spec = read_toml(path, "a sweep spec (TOML; see examples/sweep.toml)")
    except FileError as err:
        raise ConfigError(str(err)) from None
    unknown = sorted(set(spec) - set(_SPEC_KEYS))
    if unknown:
        raise ConfigError(f"{path}: {unknown[0]}: unknown key; expected {', '.join(_SPEC_KEYS)}")
    if not spec:
        raise ConfigError(f"{path}: an empty spec; expected at least one of "
                          f"{', '.join(_SPEC_KEYS)}")
    base = spec.get("base")
    if base is not None and not isinstance(base, str):
        raise ConfigError(f"{path}: base = {base!r}: expected a preset name or a .toml file")
    if base is not None and base.endswith(".toml"):
        base = path.parent / base
    changes = spec.get("set", {})
    if not isinstance(changes, dict):
        raise ConfigError(f"{path}: set = {changes!r}: expected a table of dotted settings")
    config = _apply(load_config(base), changes, f"{path} [set]")
    if "conditions" in spec:
        config = _apply(config, {"experiment.conditions": spec["conditions"]}, str(path))
    grid = _read_grid(spec.get("grid", {}), str(path), max_cells)
    keys = tuple(grid)
    points, values = {}, {}
    for pairs in itertools.product(*grid.values()):
        labels = tuple(label for label, _ in pairs)
        name = _point_name(keys, labels)
        if name in points:
            raise ConfigError(f"{path} [grid]: points {values[name]!r} and {labels!r} share the "
                              f"folder name {name!r}; expected values that differ as text")
        points[name] = _apply(config, {k: v for k, (_, v) in zip(keys, pairs, strict=True)},
                              f"{path} [grid]")
        values[name] = labels
    return Sweep(keys, points, values)


def _jobs(sweep: Sweep, out: Path) -> list[CellJob]:
    return [CellJob(config, c, i, cell_path(out / name, c.name, i))
            for name, config in sweep.points.items()
            for c in config.experiment.conditions
            for i in range(config.experiment.n_seeds)]


def run_sweep(sweep: Sweep, out: str | Path, *, workers: int = 1, backend: str = "local",
              address: str | None = None, progress: Callable[[str], None] | None = None,
              max_cells: int = MAX_CELLS) -> list[dict]:
    """Run the missing cells of ``sweep`` into ``out``; returns the summary rows.

    Every point's folder is checked (:func:`~.preflight.check_runs`) before any is written.
    """
    check_backend(backend, address, workers)
    out = Path(out)
    check_writable(out, "folder")
    check_runs({out / name: config for name, config in sweep.points.items()},
               max_cells=max_cells)
    with folder_lock(out):  # one sweep per folder
        for name, config in sweep.points.items():
            prepare_run_dir(out / name, config)
            if config.experiment.held_out.n_trials:
                held_out_sets(config)  # recorded here, if at all: the workers read them
        run_jobs(run_cell_measured, _jobs(sweep, out), workers=workers, backend=backend,
                 address=address, progress=progress,
                 label=lambda j: f"{j.path.parent.parent.name} {j.condition.name} seed "
                                 f"{j.seed_index}")
        return summarise(sweep, out)


def summarise(sweep: Sweep, out: Path) -> list[dict]:
    """Final success per point and condition, written to ``summary.csv`` and ``.md``.

    The mean and 95% interval over seeds, rounded to 3 decimals; and, for cells measured on
    held-out sets (:mod:`.held_out`), the frozen model's success at the end on new poses and on
    unseen caregivers and its median angle error there (means over seeds; empty if not
    measured). The files go in ``out``.
    """
    rows = []
    for name, config in sweep.points.items():
        held = held_out_curves(out / name, config)
        for c, (_, per_seed) in condition_curves(out / name, config).items():
            finals = [final_success(curve) for curve in per_seed]
            mean, lo, hi = (round(float(v[0]), 3)
                            for v in mean_interval(np.array(finals)[:, None]))
            rows.append({"point": name, **dict(zip(sweep.keys, sweep.values[name], strict=True)),
                         "condition": c, "seeds": len(finals), "final_success": mean,
                         "ci_low": lo, "ci_high": hi, **_held_out_summary(held.get(c))})
    columns = list(rows[0]) if rows else ["point"]
    Table(columns, [[r[k] for k in columns] for r in rows]).write(Path(out) / "summary")
    return rows


def _held_out_summary(held) -> dict:
    """The frozen model's final success on new poses and unseen caregivers, and its error."""
    keys = ("new_poses_success", "unseen_success", "unseen_median_error_deg")
    if held is None:
        return dict.fromkeys(keys, "")
    m = held[1]
    values = (m["success"][:, 1, -1], m["success"][:, 2, -1], m["median_error_deg"][:, 2, -1])
    return {k: round(float(np.mean(v)), 3) for k, v in zip(keys, values, strict=True)}
