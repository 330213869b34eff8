"""Everything a run needs, checked before anything is written.

The configuration checks itself when it is built; here are the checks that need the disk, the
machine and the whole run: the output folders, the data sets (loaded and validated), the bound
on work and the memory a cell's learning needs. A run that fails them writes nothing.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path

from ..config import Config, condition_named, model_options
from ..errors import ConfigError
from .cells import datasets_of
from .results import check_run_dir

__all__ = ["MAX_CELLS", "check_memory", "check_runs", "free_memory_bytes", "learning_bytes",
           "n_cells"]

MAX_CELLS = 100_000  # the beyond preset has 250; raise it with --max-cells / max_cells


def n_cells(config: Config) -> int:
    """The cells of ``config``'s experiment: conditions x seeds."""
    return len(config.experiment.conditions) * config.experiment.n_seeds


def learning_bytes(options, face_size_px: tuple[int, int],
                   eye_size_px: tuple[int, int] | None = None) -> tuple[int, str]:
    """The bytes a model's learning state takes at most, and the option that sizes it.

    Only the states that grow with an option: the population code's replay memory and the
    episodic memory (each ``capacity`` trials long); the rest are kilobytes. ("", 0) for
    the others.
    """
    learner = getattr(options, "learner", None)
    if learner == "population":
        from ..models.population.module import PopulationModule

        o = options.population
        n = PopulationModule.view_features(o, face_size_px, eye_size_px)
        return (PopulationModule.replay_bytes(n, o.replay_capacity),
                f"model.population.replay_capacity = {o.replay_capacity:,}")
    if learner == "memory":
        o = options.memory
        # codes, links (6), places (2) and counts per trial; the places left out likewise
        per_trial = o.code_dims + 9 + (o.code_dims + 2) * o.leave_out_empty
        return o.capacity * per_trial * 8, f"model.memory.capacity = {o.capacity:,}"
    return 0, ""


def free_memory_bytes() -> int | None:
    """The memory free for a new allocation (Linux's MemAvailable); None if unknown."""
    try:
        with open("/proc/meminfo", encoding="ascii") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


def check_memory(config: Config, conditions: list[str] | None = None) -> None:
    """Refuse, with the estimate, a cell whose learning needs more memory than is free.

    ``conditions``: the names of the cells' conditions (default: all of the experiment's).
    An option inside its range can still be more than this machine holds.
    """
    free = free_memory_bytes()
    if free is None:
        return
    fw, ew = config.world.face_window, config.world.eye_window
    windows = [(fw.width_px, fw.height_px)] + [ew.kept_size_px] * ew.enabled
    for name in conditions or [c.name for c in config.experiment.conditions]:
        options = model_options(config, condition_named(config, name))
        need, option = learning_bytes(options, *windows)
        if need > free:
            raise ConfigError(f"condition {name!r}: {option} needs about {need / 2**30:,.1f} GiB "
                              f"of memory to learn, more than the {free / 2**30:,.1f} GiB free "
                              "here; expected a smaller capacity")


def check_runs(runs: Mapping[Path, Config], *, max_cells: int = MAX_CELLS) -> None:
    """Refuse, with one error naming what is wrong, runs into ``runs`` (folder -> config).

    Each folder must be new, empty, or a run folder of the same configuration and data sets;
    each configuration's data sets must load and each cell's learning fit in the memory free;
    all the runs together must have at most ``max_cells`` cells.
    """
    total = sum(n_cells(config) for config in runs.values())
    if total > max_cells:
        raise ConfigError(f"{total:,} cells (conditions x seeds x points): expected at most "
                          f"{max_cells:,}; raise the bound with --max-cells if you mean it")
    checked = set()
    for out, config in runs.items():
        check_run_dir(Path(out), config)
        check_memory(config)
        if config.datasets not in checked:
            datasets_of(config)
            checked.add(config.datasets)
