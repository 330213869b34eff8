"""Run folders: the configuration a run was made with, its cells, and the tidy trial table.

A run folder holds ``config.toml`` and ``versions.json`` (written first), one
``cells/<condition>__seed<k>.npz`` per finished cell (the columns of
:data:`~jointattention.experiment.trial.RECORD`), and what :func:`~.reproduce.reproduce`
writes from them.
"""

from __future__ import annotations

import csv
import json
import platform
from importlib import metadata
from pathlib import Path

import numpy as np

from .. import __version__
from .._files import atomic_path, save_json, save_npz, write_text
from ..config import Config, load_config, to_toml
from ..errors import JointAttentionError
from .trial import RECORD

__all__ = ["cell_path", "load_cell", "prepare_run_dir", "save_cell", "versions",
           "write_trials_csv"]


def versions() -> dict:
    """Versions of what a run ran with."""
    def version(package: str) -> str:
        try:
            return metadata.version(package)
        except metadata.PackageNotFoundError:
            return "not installed"

    return {"jointattention": __version__, "python": platform.python_version(),
            "numpy": np.__version__, "mujoco": version("mujoco"),
            "matplotlib": version("matplotlib"), "platform": platform.platform()}


def prepare_run_dir(out: Path, config: Config) -> None:
    """Create the run folder, or check that it holds this configuration.

    An existing folder must have been made with the same configuration, so that a resumed run adds
    to matching results.
    """
    out = Path(out)
    cfg_file = out / "config.toml"
    if cfg_file.exists():
        if load_config(cfg_file) != config:
            raise JointAttentionError(
                f"{out}: holds results of another configuration; expected a new --out folder "
                "(or the same configuration, to resume)")
        made_by = _made_by(out)
        if made_by.split(".")[:2] != __version__.split(".")[:2]:
            raise JointAttentionError(
                f"{out}: made by jointattention {made_by}, whose cells differ from version "
                f"{__version__}'s; expected a new --out folder")
        return
    if out.exists() and any(out.iterdir()):
        raise JointAttentionError(f"{out}: not empty and not a run folder; expected a new or "
                                  "empty folder")
    write_text(cfg_file, to_toml(config))
    save_json(versions(), out / "versions.json")


def _made_by(out: Path) -> str:
    """The version of jointattention that made run folder ``out`` ("unknown" if not told)."""
    try:
        made = json.loads((out / "versions.json").read_text(encoding="utf-8"))
        return str(made["jointattention"])
    except (OSError, ValueError, KeyError, TypeError):
        return "unknown"


def cell_path(out: Path, condition: str, seed_index: int) -> Path:
    """Where the cell of ``condition`` and ``seed_index`` is saved in run folder ``out``."""
    return Path(out) / "cells" / f"{condition}__seed{seed_index:03d}.npz"


def save_cell(path: Path, records: dict[str, np.ndarray]) -> None:
    """Save a cell's records (atomically)."""
    save_npz(path, records)


def load_cell(path: Path) -> dict[str, np.ndarray]:
    """A saved cell's records."""
    with np.load(path, allow_pickle=False) as z:
        return {k: z[k] for k in z.files}


def write_trials_csv(out: Path, cells: dict[tuple[str, int], dict[str, np.ndarray]]) -> Path:
    """One tidy table of every trial: condition, seed, then the trial's columns."""
    path = Path(out) / "trials.csv"
    with atomic_path(path) as tmp, open(tmp, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(("condition", "seed", "trial", *RECORD))
        for (name, seed), rec in sorted(cells.items()):
            cols = [rec[c].astype(int) for c in RECORD]
            for i, row in enumerate(zip(*cols, strict=True)):
                writer.writerow((name, seed, i, *row))
    return path
