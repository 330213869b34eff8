"""Everything a run needs, checked before anything is written.

The configuration checks itself when it is built; here are the checks that need the disk and
the whole run: the output folders, the data sets (loaded and validated) and the bound on
work. A run that fails them writes nothing.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

from ..config import Config
from ..errors import ConfigError
from .cells import datasets_of
from .results import check_run_dir

__all__ = ["MAX_CELLS", "check_runs", "n_cells"]

MAX_CELLS = 100_000  # the beyond preset has 250; raise it with --max-cells / max_cells


def n_cells(config: Config) -> int:
    """The cells of ``config``'s experiment: conditions x seeds."""
    return len(config.experiment.conditions) * config.experiment.n_seeds


def check_runs(runs: Mapping[Path, Config], *, max_cells: int = MAX_CELLS) -> None:
    """Refuse, with one error naming what is wrong, runs into ``runs`` (folder -> config).

    Each folder must be new, empty, or a run folder of the same configuration and data sets;
    each configuration's data sets must load; all the runs together must have at most
    ``max_cells`` cells.
    """
    total = sum(n_cells(config) for config in runs.values())
    if total > max_cells:
        raise ConfigError(f"{total:,} cells (conditions x seeds x points): expected at most "
                          f"{max_cells:,}; raise the bound with --max-cells if you mean it")
    checked = set()
    for out, config in runs.items():
        check_run_dir(Path(out), config)
        if config.datasets not in checked:
            datasets_of(config)
            checked.add(config.datasets)
