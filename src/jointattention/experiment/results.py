"""Run folders: the configuration a run was made with, its cells, and the tidy trial table.

A run folder holds ``versions.json`` and ``config.toml`` (written first, after every check),
one ``cells/<condition>__seed<k>.npz`` per finished cell (the columns of
:data:`~jointattention.experiment.trial.RECORD`), and what :func:`~.reproduce.reproduce`
writes from them.
"""

from __future__ import annotations

import csv
import io
import platform
from importlib import metadata
from pathlib import Path

import numpy as np

from .._files import (
    LOCK_NAME,
    atomic_path,
    check_writable,
    remove_stale_tmp,
    save_json,
    save_npz,
    write_text,
)
from .._jit import jit
from .._readers import read_json, read_npz, sha256_of
from .._version import __version__
from ..config import Config, load_config, to_toml
from ..errors import FileError, JointAttentionError
from .cells import datasets_file
from .trial import RECORD

__all__ = ["Cells", "cell_path", "cell_records", "check_run_dir", "datasets_sha256",
           "load_cell", "prepare_run_dir", "save_cell", "versions", "write_trials_csv"]


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


def datasets_sha256(config: Config) -> str:
    """The SHA-256 of the content of the run's data-set file (:func:`~.cells.datasets_file`)."""
    return sha256_of(datasets_file(config))


# A run's start: the lock, then versions.json, then config.toml. A folder holding only these
# (a start that was killed) counts as empty.
_START_FILES = (LOCK_NAME, "versions.json")


def _is_tmp(p: Path) -> bool:
    return p.name.startswith(".") and p.name.endswith(".tmp") and p.is_file()


def check_run_dir(out: Path, config: Config) -> None:
    """Refuse ``out`` unless ``config``'s run can be written there (writes nothing).

    ``out`` must be a new or empty folder that can be made, or a run folder made with the same
    configuration, the same data sets (by content, not path) and a compatible version.
    """
    out = Path(out)
    check_writable(out, "folder")
    cfg_file = out / "config.toml"
    if not cfg_file.exists():
        if out.exists() and any(p.name not in _START_FILES and not _is_tmp(p)
                                for p in out.iterdir()):
            raise JointAttentionError(f"{out}: not empty and not a run folder; expected a new "
                                      "or empty folder")
        return
    check_writable(out / "cells", "folder", "the cells' folder")
    if load_config(cfg_file) != config:
        raise JointAttentionError(
            f"{out}: holds results of another configuration; expected a new --out folder "
            "(or the same configuration, to resume)")
    made = read_json(out / "versions.json", "the versions a run folder was made with")
    made_by = str(made.get("jointattention", "unknown"))
    if made_by.split(".")[:2] != __version__.split(".")[:2]:
        raise JointAttentionError(
            f"{out}: made by jointattention {made_by}, whose cells differ from version "
            f"{__version__}'s; expected a new --out folder")
    made_with = made.get("datasets_sha256")
    if made_with is not None and made_with != datasets_sha256(config):
        raise JointAttentionError(
            f"{out}: made with data sets of other content (sha256 {str(made_with)[:12]}..., "
            f"now {datasets_sha256(config)[:12]}... at {config.datasets or 'the shipped path'})"
            "; expected the same data sets, or a new --out folder")


def prepare_run_dir(out: Path, config: Config) -> None:
    """Create the run folder, or check that it holds this configuration (:func:`check_run_dir`).

    Call it under :func:`~jointattention._files.folder_lock`: it removes the temporary files
    of a writer that was killed. A new folder gets ``config.toml`` and ``versions.json``
    (with the data sets' SHA-256).
    """
    out = Path(out)
    check_run_dir(out, config)
    remove_stale_tmp(out)
    if not (out / "config.toml").exists():
        save_json({**versions(), "datasets_sha256": datasets_sha256(config)},
                  out / "versions.json")
        write_text(out / "config.toml", to_toml(config))


def cell_path(out: Path, condition: str, seed_index: int) -> Path:
    """Where the cell of ``condition`` and ``seed_index`` is saved in run folder ``out``."""
    return Path(out) / "cells" / f"{condition}__seed{seed_index:03d}.npz"


Cells = dict[tuple[str, int], dict[str, np.ndarray]]  # loaded cells: {(condition, seed): records}


def cell_records(out: Path, name: str, seed_index: int, cells: Cells | None = None
                 ) -> dict[str, np.ndarray]:
    """A cell's records: from ``cells`` ({(condition, seed): records}) if given, else its file."""
    if cells is not None:
        return cells[(name, seed_index)]
    return load_cell(cell_path(out, name, seed_index))


def save_cell(path: Path, records: dict[str, np.ndarray]) -> None:
    """Save a cell's records (atomically)."""
    save_npz(path, records)


# the last three optional (cells written before they were measured)
_PER_BIN = ("lm_error_deg", "lm_pan_error_deg", "lm_tilt_error_deg", "lm_bias")
# the held-out measures (experiment/held_out.py): optional, and all or none
_HELD_OUT = ("held_out_steps", "held_out_success", "held_out_median_error_deg",
             "held_out_p90_error_deg", "held_out_share_over_10deg",
             "held_out_blank_spread_deg", "held_out_mirror_flip_share")


def load_cell(path: Path) -> dict[str, np.ndarray]:
    """A saved cell's records; a :class:`~..errors.FileError` if they are not whole.

    Whole: the columns of :data:`~.trial.RECORD`, one row per trial each and of its type, and
    ``lm_error_deg`` (one value per learning-time bin); ``lm_pan_error_deg``,
    ``lm_tilt_error_deg`` and ``lm_bias`` too, except in cells written before they were
    measured; and all or
    none of the held-out measures (``held_out_steps`` and one (3, checkpoints) array each).
    """
    records = read_npz(path, "a cell's records (cells/*.npz)")
    expected = {**{k: np.dtype(t) for k, (t, _) in RECORD.items()},
                **{k: np.dtype(np.float64) for k in (*_PER_BIN, *_HELD_OUT)},
                "held_out_steps": np.dtype(np.int64)}
    odd = sorted((set(expected) ^ set(records)) - {*_PER_BIN[1:], *_HELD_OUT})
    held_out = [k for k in _HELD_OUT if k in records]
    if odd or held_out not in ([], list(_HELD_OUT)):
        missing = odd[0] if odd else next(k for k in _HELD_OUT if k not in records)
        raise FileError(f"{path}: column {missing!r} missing or unknown; expected the columns "
                        f"{', '.join(k for k in expected if k not in _HELD_OUT)} (and all or "
                        "none of the held-out measures)")
    shapes = {r.shape for k, r in records.items() if k in RECORD}
    ndim = {k: 1 + (k in _HELD_OUT[1:]) for k in expected}
    typed = all(r.dtype == expected[k] and r.ndim == ndim[k] for k, r in records.items())
    if held_out and typed:
        n = len(records["held_out_steps"])
        typed = all(records[k].shape == (3, n) for k in _HELD_OUT[1:])
    if len(shapes) != 1 or not typed:
        raise FileError(f"{path}: columns of other shapes or types; expected one row per trial "
                        "in each column of its type")
    return records


def write_trials_csv(out: Path, cells: Cells) -> Path:
    """One tidy table of every trial: condition, seed, then the trial's columns.

    As :mod:`csv` writes it (the header and each cell's condition and seed through
    :func:`csv.writer`); the integers of the rows are written by a compiled loop, since a
    large run has millions of trials.
    """
    path = Path(out) / "trials.csv"
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        f.write(_csv_line(("condition", "seed", "trial", *RECORD)).encode())
        for (name, seed), rec in sorted(cells.items()):
            cols = np.array([rec[c].astype(np.int64) for c in RECORD]).reshape(len(RECORD), -1)
            prefix = np.frombuffer(_csv_line((name, seed, ""))[:-2].encode(), np.uint8)
            buf = np.empty(cols.shape[1] * (len(prefix) + 21 * (len(RECORD) + 1) + 2), np.uint8)
            f.write(buf[: _int_rows_into(prefix, cols, buf)].tobytes())
    return path


def _csv_line(row) -> str:
    """``row`` as :func:`csv.writer` writes it (quoted as needed, ending in CR LF)."""
    text = io.StringIO()
    csv.writer(text).writerow(row)
    return text.getvalue()


@jit
def _int_rows_into(prefix, columns, out) -> int:
    """Row i: ``prefix``, i, then ``columns[:, i]``, comma-separated, CR LF; the bytes used."""
    at = 0
    digits = np.empty(20, np.uint8)
    for i in range(columns.shape[1]):
        for b in prefix:
            out[at] = b
            at += 1
        for c in range(-1, columns.shape[0]):
            value = i if c < 0 else columns[c, i]
            if c >= 0:
                out[at] = 44  # ","
                at += 1
            if value < 0:
                out[at] = 45  # "-"
                at += 1
                value = -value
            n = 0
            while True:
                digits[n] = 48 + value % 10
                value //= 10
                n += 1
                if value == 0:
                    break
            for k in range(n - 1, -1, -1):
                out[at] = digits[k]
                at += 1
        out[at], out[at + 1] = 13, 10
        at += 2
    return at
