"""The one place that writes and reads results: run folders, cell files, tidy tables."""

from __future__ import annotations

import csv
import json
import os
import platform
import tempfile
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from . import __version__
from .config import Config, load_config, to_toml
from .errors import JointAttentionError

__all__ = [
    "TRIAL_COLUMNS",
    "atomic_path",
    "cell_path",
    "load_cell",
    "prepare_run_dir",
    "save_cell",
    "save_json",
    "versions",
    "write_trials_csv",
]

TRIAL_COLUMNS = ("learning_time", "n_steps", "n_lm_steps", "attended", "target", "end",
                 "success", "fired")


@contextmanager
def atomic_path(path: Path):
    """Yield a temporary path beside ``path``; move it into place only if the block succeeds."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    os.close(fd)
    try:
        yield Path(tmp)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    finally:
        Path(tmp).unlink(missing_ok=True)


def versions() -> dict:
    """Versions of what a run ran with."""
    import matplotlib
    import mujoco

    return {"jointattention": __version__, "python": platform.python_version(),
            "numpy": np.__version__, "mujoco": mujoco.__version__,
            "matplotlib": matplotlib.__version__, "platform": platform.platform()}


def save_json(data: dict, path: Path) -> None:
    with atomic_path(path) as tmp:
        tmp.write_text(json.dumps(data, indent=2, sort_keys=True) + "\n")


def prepare_run_dir(out: Path, config: Config) -> None:
    """Create the run folder with its configuration, or check that an existing folder was
    made with the same configuration (so that a resumed run adds to matching results)."""
    out = Path(out)
    cfg_file = out / "config.toml"
    if cfg_file.exists():
        if load_config(cfg_file) != config:
            raise JointAttentionError(
                f"{out}: holds results of another configuration; expected a new --out folder "
                "(or the same configuration, to resume)")
        return
    if out.exists() and any(out.iterdir()):
        raise JointAttentionError(f"{out}: not empty and not a run folder; expected a new or "
                                  "empty folder")
    with atomic_path(cfg_file) as tmp:
        tmp.write_text(to_toml(config))
    save_json(versions(), out / "versions.json")


def cell_path(out: Path, condition: str, seed_index: int) -> Path:
    return Path(out) / "cells" / f"{condition}__seed{seed_index:03d}.npz"


def save_cell(path: Path, records: dict[str, np.ndarray]) -> None:
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        np.savez_compressed(f, **records)


def load_cell(path: Path) -> dict[str, np.ndarray]:
    with np.load(path, allow_pickle=False) as z:
        return {k: z[k] for k in z.files}


def write_trials_csv(out: Path, cells: dict[tuple[str, int], dict[str, np.ndarray]]) -> Path:
    """One tidy table of every trial: condition, seed, then the trial's columns."""
    path = Path(out) / "trials.csv"
    with atomic_path(path) as tmp, open(tmp, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(("condition", "seed", "trial", *TRIAL_COLUMNS))
        for (name, seed), rec in sorted(cells.items()):
            cols = [rec[c].astype(int) for c in TRIAL_COLUMNS]
            for i, row in enumerate(zip(*cols, strict=True)):
                writer.writerow((name, seed, i, *row))
    return path
