"""The main job as a library call (``jointattention reproduce`` calls it).

Every cell of a configuration, the ceilings, the figures, the table and the checked claims, in one
run folder.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from contextlib import ExitStack
from dataclasses import dataclass
from functools import partial
from pathlib import Path

import numpy as np

from .._checks import check_path
from .._files import folder_lock, save_json, write_text
from .._readers import read_json
from ..analysis.claims import Claim, check_claims, claims_summary, readings_table, write_claims
from ..analysis.curves import condition_axis_errors, condition_curves, final_table
from ..analysis.diagnostics import (
    condition_diagnostics,
    diagnostics_table,
    seed_diagnostics,
    seeds_table,
)
from ..analysis.held_out import held_out_claims, held_out_curves, held_out_table
from ..analysis.learning_speed import learning_speed_table
from ..config import Config, check_config
from ..deploy.saved import check_savable
from ..errors import JointAttentionError
from ..experiment.backends import CellJob, check_backend, run_jobs
from ..experiment.cells import measure_ceiling
from ..experiment.evaluate import oracle_success
from ..experiment.held_out import held_out_novelty, held_out_sets, run_cell_measured
from ..experiment.preflight import MAX_CELLS, check_runs
from ..experiment.results import cell_path, load_cell, prepare_run_dir, write_trials_csv
from ..experiment.training import model_path, run_cell_saving_model
from .progress import CellBar

__all__ = ["RunResult", "held_out_ceilings", "reproduce", "run_ceilings", "run_experiment"]

_log = logging.getLogger("jointattention")


def run_experiment(config: Config, out: str | Path, workers: int = 1,
                   progress: Callable[[str], None] | None = None, *, backend: str = "local",
                   address: str | None = None, max_cells: int = MAX_CELLS,
                   save_models: bool = False) -> dict[tuple[str, int], dict[str, np.ndarray]]:
    """Run every condition x seed into ``out``; cells already there are kept, not re-run.

    Returns {(condition, seed): records}. Each cell is saved as it finishes, so an
    interrupted run loses only the cells in progress. ``backend`` and ``address``: see
    :func:`jointattention.experiment.backends.run_jobs`; ``max_cells``: see
    :func:`~.preflight.check_runs`; ``save_models``: each cell's learned model is saved in
    ``out/models/<condition>/seed_<i>.npz`` (:mod:`~.training`).
    """
    out = Path(check_path(out, "out"))
    with ExitStack() as lock:
        jobs, _ = _run_cells(check_config(config), out, workers, progress, backend, address,
                             max_cells, save_models, lock)
        return {(j.condition.name, j.seed_index): load_cell(j.path) for j in jobs}


def _run_cells(config: Config, out: Path, workers: int, progress, backend: str,
               address: str | None, max_cells: int,
               save_models: bool, lock: ExitStack) -> tuple[list[CellJob], int]:
    """Every cell's job, after running those not in ``out`` yet; and how many ran.

    The folder's lock is taken after every check and held by ``lock`` (the caller's).
    """
    check_backend(backend, address, workers)
    exp = config.experiment
    run, also_done = run_cell_measured, None
    if save_models:
        for c in exp.conditions:  # every model must be one that is saved: refused up front
            check_savable(config, c.name)
        run = partial(run_cell_saving_model, models_dir=out / "models")

        def also_done(job: CellJob) -> bool:  # a cell run without --save-models runs again
            return model_path(out / "models", job.condition.name, job.seed_index).is_file()

    check_runs({out: config}, max_cells=max_cells)  # before anything is written
    lock.enter_context(folder_lock(out))  # one run per folder, until the caller is done
    prepare_run_dir(out, config)
    if exp.held_out.n_trials:
        held_out_sets(config)  # recorded here, if at all: the workers read them
    jobs = [CellJob(config, c, i, cell_path(out, c.name, i))
            for c in exp.conditions for i in range(exp.n_seeds)]
    ran = run_jobs(run, jobs, workers=workers, backend=backend, address=address,
                   progress=progress, also_done=also_done)
    return jobs, ran


def _read_or_measure(path: Path, what: str, whole: Callable[[dict], bool], missing: str,
                     measure: Callable[[], dict], progress, phase: str = "ceilings") -> dict:
    """The JSON at ``path`` if it is ``whole``, else measured (after a warning) and saved there."""
    if path.exists():
        try:
            found = read_json(path, what)
            if whole(found):
                return found
            _log.warning("%s: no ceiling for some %s; measured again", path, missing)
        except JointAttentionError as err:
            _log.warning("%s; measured again", err)
    if progress is not None:
        progress(phase)
    measured = measure()
    save_json(measured, path)
    return measured


def held_out_ceilings(config: Config, path: Path,
                      progress=None) -> dict[str, dict[str, float]]:
    """The oracle ceilings of the held-out sets, {kind: {str(n): ceiling}}: read or measured.

    Measured with the trials of the held-out measures (:func:`~.evaluate.oracle_success`,
    ``experiment.n_ceiling_trials`` of them); {} if the run measures no held-out sets.
    """
    if not config.experiment.held_out.n_trials:
        return {}
    counts = sorted({c.n_objects for c in config.experiment.conditions})
    n = config.experiment.n_ceiling_trials
    return _read_or_measure(
        path, "the held-out ceilings of a run folder",
        lambda found: all(type(found.get(k, {}).get(str(m))) in (int, float)
                          for k in held_out_sets(config) for m in counts),
        "set or object count",
        lambda: {kind: {str(k): oracle_success(ds, config, k, n, config.seed) for k in counts}
                 for kind, ds in held_out_sets(config).items()}, progress, "held-out ceilings")


def run_ceilings(config: Config, path: Path, progress=None) -> dict[str, float]:
    """The oracle ceilings of the run's object counts: read from ``path``, or measured there.

    A file that is not whole (unreadable, or without every count) is measured again.
    """
    counts = sorted({c.n_objects for c in config.experiment.conditions})
    return _read_or_measure(
        path, "the oracle ceilings of a run folder",
        lambda found: all(type(found.get(str(n))) in (int, float) and 0 <= found[str(n)] <= 1
                          for n in counts),
        "object count", lambda: {str(n): measure_ceiling(config, n) for n in counts}, progress)


@dataclass(frozen=True)
class RunResult:
    """What :func:`reproduce` did: the files it wrote, the claims, and its timing."""

    out: Path
    files: list[Path]
    claims: list[Claim]
    cells_run: int
    cells_total: int
    cells_min: float  # the wall time of this call's cells
    wall_min: float  # of the whole call

    def summary(self, workers: int | None = None) -> str:
        """A few lines: the cells and time, the folder's size, the claims, figures and tables.

        ``workers``: the number the run used, to name beside its time.
        """
        def names(suffix: str) -> str:
            found = [p.name for p in self.files if p.suffix == suffix]
            return f"{self.out}/" + "{" + ", ".join(found) + "}" if found else "none"

        on = f" on {workers} worker{'s' * (workers != 1)}" if workers else ""
        return "\n".join([
            f"{self.out}: {self.cells_run} of {self.cells_total} cells run in "
            f"{self.cells_min:.1f} min{on}; the whole run {self.wall_min:.1f} min; "
            f"{_size_text(_folder_bytes(self.out))} on disk",
            f"{claims_summary(self.claims)}: {self.out / 'claims.md'}",
            f"figures: {names('.png')}",
            f"tables: {names('.md')}",
            f"the report: jointattention report {self.out}"])


def _folder_bytes(folder: Path) -> int:
    """The bytes of every file under ``folder``."""
    return sum(p.stat().st_size for p in folder.rglob("*") if p.is_file())


def _size_text(n_bytes: int) -> str:
    """``n_bytes`` for a reader: "740 kB", "6.9 MB", "1.2 GB"."""
    for unit, scale in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if n_bytes >= scale:
            return f"{n_bytes / scale:.{0 if n_bytes >= 100 * scale else 1}f} {unit}"
    return f"{n_bytes} B"


def _measured(path: Path) -> bool:
    """Whether ``path`` holds a readable measure of a run's wall time (``timing.json``)."""
    try:
        return "wall_min" in read_json(path, "a run's wall time (timing.json)")
    except JointAttentionError:  # missing or unreadable: measured anew
        return False


def reproduce(config: Config, out: str | Path, *, workers: int = 1, backend: str = "local",
              address: str | None = None, progress: Callable[[str], None] | bool | None = None,
              max_cells: int = MAX_CELLS, save_models: bool = False,
              trials_csv: bool = False) -> RunResult:
    """Run ``config``'s experiment into the run folder ``out`` and write what it shows.

    Cells already in ``out`` are kept (a re-run resumes). Then the oracle
    ceilings (``ceilings.json``, measured once), ``trials.csv`` if ``trials_csv`` (every
    trial of every cell in one tidy table; the cells' own files in ``cells/`` hold the same
    records, and a large run's table takes most of a gigabyte), the figures
    (:func:`jointattention.figures.paper.write_figures`), ``table.csv``/``.md``,
    ``claims.csv``/``.md``, one row per reading (``readings.csv``/``.md``), the diagnostics per
    learning-time bin
    (``diagnostics.csv``/``.md``/``.png``; per seed ``diagnostics_seeds.csv``/``.png``,
    :mod:`jointattention.analysis.diagnostics`), each seed's final success and steps to 90% of
    it (``learning_speed.csv``/``.md``/``.png``, :mod:`jointattention.analysis.learning_speed`),
    and
    what the models carry over to held-out data sets (``held_out_ceilings.json``,
    ``held_out.csv``/``.md``/``.png``, :mod:`jointattention.analysis.held_out`); last
    ``timing.json``: the wall time of this call (``wall_min``: cells, ceilings, tables and
    figures) and of its cells alone (``cells_min``). A re-run that ran no cell keeps the one
    there.
    ``progress`` hears the runner's messages (see
    :func:`~jointattention.experiment.backends.run_jobs`) and the phases ``"ceilings"``,
    ``"held-out ceilings"`` and ``"tables"``; ``True`` shows them as a progress bar on stderr
    (:class:`~.progress.CellBar`), as the command line does. Nothing is
    written unless the run passes :func:`~.preflight.check_runs` (at most ``max_cells``).
    ``save_models``: see :func:`run_experiment`.
    """
    from ..figures.diagnostics import diagnostics_figure, seeds_figure  # matplotlib: drawn
    from ..figures.held_out import held_out_figure
    from ..figures.learning_speed import learning_speed_figure
    from ..figures.paper import write_figures

    out = Path(check_path(out, "out"))
    check_config(config)
    start = time.perf_counter()
    if progress is not None and not callable(progress) and type(progress) is not bool:
        raise JointAttentionError(f"progress={progress!r}: expected a callable, True, False "
                                  "or None")
    with ExitStack() as lock:  # the folder's lock (taken after every check)
        if progress is True:
            exp = config.experiment
            progress = lock.enter_context(CellBar(len(exp.conditions) * exp.n_seeds))
        progress = progress or None
        jobs, cells_run = _run_cells(config, out, workers, progress, backend, address, max_cells,
                                     save_models, lock)
        cells_min = (time.perf_counter() - start) / 60
        cells = {(j.condition.name, j.seed_index): load_cell(j.path) for j in jobs}
        ceilings = run_ceilings(config, out / "ceilings.json", progress)
        held_ceilings = held_out_ceilings(config, out / "held_out_ceilings.json", progress)
        curves = condition_curves(out, config, cells)
        held = held_out_curves(out, config, cells)
        claims = check_claims(config, curves, ceilings, condition_axis_errors(out, config, cells))
        claims += held_out_claims(config, held, held_ceilings)
        seeds = seed_diagnostics(out, config, curves, cells)
        diagnostics = condition_diagnostics(out, config, seeds)
        speed = learning_speed_table(config, curves, ceilings, held, held_ceilings)
        if progress is not None:
            progress("tables")
        files = [*([write_trials_csv(out, cells)] if trials_csv else []),
                 *write_figures(out, config, curves, ceilings),
                 *final_table(config, curves, ceilings, held, held_ceilings).write(out / "table"),
                 *write_claims(claims, out / "claims"),
                 *readings_table(config, curves, ceilings, claims).write(out / "readings"),
                 *diagnostics_table(diagnostics).write(out / "diagnostics"),
                 diagnostics_figure(diagnostics, out / "diagnostics.png"),
                 write_text(out / "diagnostics_seeds.csv", seeds_table(seeds).to_csv()),
                 seeds_figure(seeds, out / "diagnostics_seeds.png"),
                 *speed.write(out / "learning_speed"),
                 learning_speed_figure(speed, out / "learning_speed.png")]
        if held:
            files += [*held_out_table(config, held, held_ceilings,
                                      held_out_novelty(config)).write(out / "held_out"),
                      held_out_figure(config, held, held_ceilings, out / "held_out.png", curves,
                                      ceilings)]
        wall_min = (time.perf_counter() - start) / 60
        if cells_run or not _measured(out / "timing.json"):  # a redraw keeps the measure
            save_json({"wall_min": round(wall_min, 2), "cells_min": round(cells_min, 2),
                       "workers": workers, "cells_run": cells_run, "cells_total": len(cells)},
                      out / "timing.json")
        return RunResult(out, files, claims, cells_run, len(cells), cells_min, wall_min)
