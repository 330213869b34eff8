"""Where cells run: in this process, in local worker processes, or on a Ray cluster.

A cell's records depend only on its configuration, condition and seed index, so every
backend gives the same results. Each finished cell is saved (atomically) by the calling
process as soon as it arrives: an interrupted run loses only the cells in progress.
"""

from __future__ import annotations

import ctypes
import logging
import numbers
import os
import shutil
import signal
import sys
import threading
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from contextlib import closing, contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._checks import short_repr
from ..config import ConditionConfig, Config
from ..errors import ConfigError, JointAttentionError
from .results import load_cell, save_cell

__all__ = ["BACKENDS", "MAX_WORKERS", "CellFunction", "CellJob", "check_backend", "run_jobs"]

# What runs one cell: (config, condition, seed index) -> records (e.g. cells.run_cell). It
# must be importable by name (a module-level function) for worker processes and Ray.
CellFunction = Callable[[Config, ConditionConfig, int], dict[str, np.ndarray]]

BACKENDS = ("local", "ray")
MAX_WORKERS = 1024
_PR_SET_PDEATHSIG = 1  # Linux prctl: the signal a process gets when its parent ends
_log = logging.getLogger("jointattention")


@dataclass(frozen=True)
class CellJob:
    """One cell to run, and the file its records go to."""

    config: Config
    condition: ConditionConfig
    seed_index: int
    path: Path


def _run(run: CellFunction, job: CellJob) -> tuple[CellJob, dict[str, np.ndarray]]:
    return job, run(job.config, job.condition, job.seed_index)


def _run_saved(run: CellFunction, job: CellJob) -> tuple[CellJob, None]:
    """Run a cell and save it in the process that ran it (local processes share the folder).

    Compressing a cell costs about as much as a short cell's learning: done by the parent, it
    would take a core from the workers.
    """
    save_cell(job.path, run(job.config, job.condition, job.seed_index))
    return job, None


def _end_with_parent(parent_pid: int) -> None:
    """In a worker: end when the parent process ends, however it ends; leave signals to it."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C reaches the whole group: the parent
    signal.signal(signal.SIGTERM, signal.SIG_DFL)  # decides, and ends the workers itself
    if sys.platform.startswith("linux"):  # even after SIGKILL of the parent
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL)
        if os.getppid() != parent_pid:  # the parent died before prctl took hold
            os._exit(1)


def _pool(workers: int) -> ProcessPoolExecutor:
    """A pool of ``workers`` processes that end with this one and leave signals to it."""
    return ProcessPoolExecutor(max_workers=workers, initializer=_end_with_parent,
                               initargs=(os.getpid(),))


def _stop_workers(pool: ProcessPoolExecutor) -> None:
    """End ``pool``'s workers now: their cells in progress are lost, finished ones are saved."""
    # Read these first: shutdown() sets them to None (Python 3.11-3.13).
    manager = getattr(pool, "_executor_manager_thread", None)
    processes = dict(getattr(pool, "_processes", None) or {})
    if hasattr(pool, "terminate_workers"):  # Python 3.14+
        pool.terminate_workers()
    else:
        pool.shutdown(wait=False, cancel_futures=True)
        for p in list(processes.values()):
            p.terminate()
        for p in list(processes.values()):
            p.join(5)
    # Until its manager thread has closed the pool's wake-up pipe, the interpreter's exit hook
    # can write to the pipe as it closes: "OSError: Bad file descriptor" on Ctrl-C (3.11).
    if manager is not None:
        manager.join(5)


@contextmanager
def _signals_noted() -> Iterator[list[int]]:
    """SIGINT and SIGTERM only noted while the pool is waited on; then their own handlers run.

    A handler that raises at any bytecode can land inside the executor's locks (e.g. half-way
    through acquiring its futures' conditions), and the process then hangs at exit. Noted,
    the signal is raised again from the caller's own code (:func:`_local`), at once.
    """
    noted: list[int] = []
    if threading.current_thread() is not threading.main_thread():
        yield noted
        return
    previous = {s: signal.signal(s, lambda signum, frame: noted.append(signum))
                for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield noted
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)


def _local(run: CellFunction, jobs: Sequence[CellJob], workers: int) -> Iterator[tuple]:
    workers = min(workers, len(jobs))  # no idle processes
    if workers <= 1:
        yield from (_run_saved(run, j) for j in jobs)
        return
    pool = _pool(workers)
    try:
        with _signals_noted() as noted:
            pending = {pool.submit(_run_saved, run, j) for j in jobs}
            while pending and not noted:
                done, pending = wait(pending, timeout=0.1, return_when=FIRST_COMPLETED)
                for f in done:
                    yield f.result()
        if noted:  # its own handler now: KeyboardInterrupt, or the command's SIGTERM
            signal.raise_signal(noted[0])
    except BaseException:  # an interrupt, SIGTERM, or a failed cell: stop the rest at once
        _stop_workers(pool)
        raise
    pool.shutdown()


def _ray(run: CellFunction, jobs: Sequence[CellJob], workers: int,
         address: str | None) -> Iterator[tuple]:
    try:
        import ray
    except ImportError:
        raise ConfigError('--backend ray: Ray is not installed; expected it installed: '
                          'pip install "jointattention[ray]"') from None
    started = not ray.is_initialized()
    if started:
        kwargs = {"address": address} if address else {"num_cpus": workers}
        ray.init(include_dashboard=False, log_to_driver=False, **kwargs)
    try:
        remote = ray.remote(_run)
        pending = [remote.remote(run, j) for j in jobs]
        try:
            while pending:
                done, pending = ray.wait(pending, num_returns=1)
                yield ray.get(done[0])
        finally:
            for ref in pending:
                ray.cancel(ref, force=True)
    finally:
        if started:
            ray.shutdown()


def check_backend(backend: str, address: str | None, workers: int = 1) -> None:
    """Refuse an unknown backend, or an address without Ray, before anything is written.

    Also the API's ``workers`` of another kind (the command line's is an integer already).
    """
    if (isinstance(workers, bool) or not isinstance(workers, numbers.Integral)
            or not 0 <= workers <= MAX_WORKERS):
        raise ConfigError(f"workers={short_repr(workers)}: expected an integer from 0 (one per "
                          f"core) to {MAX_WORKERS}")
    if not isinstance(backend, str) or backend not in BACKENDS:
        raise ConfigError(f"backend {short_repr(backend)}: expected one of {', '.join(BACKENDS)}")
    if address is not None and not isinstance(address, str):
        raise ConfigError(f"address {short_repr(address)}: expected a Ray cluster's address "
                          "(host:port) or None")
    if address and backend != "ray":
        raise ConfigError("--address: joins a Ray cluster; expected --backend ray with it")


def _label(job: CellJob) -> str:
    return f"{job.condition.name} seed {job.seed_index}"


def _done(path: Path) -> bool:
    """Whether ``path`` holds a finished cell; a broken one is moved aside with a warning.

    Temporary files of the cell that a killed run left (see :func:`~.._files.atomic_path`) are
    removed.
    """
    for stale in path.parent.glob(f".{path.name}.*.tmp"):
        stale.unlink(missing_ok=True)
    if not path.exists() and not path.is_symlink():
        return False
    try:
        load_cell(path)
        return True
    except JointAttentionError as err:
        aside = path.with_name(path.name + ".corrupt")
        _log.warning("%s; moved to %s and its cell run again", err, aside.name)
        if aside.is_dir():
            shutil.rmtree(aside)
        os.replace(path, aside)
        return False


def run_jobs(run: CellFunction, jobs: Sequence[CellJob], *, workers: int = 1,
             backend: str = "local",
             address: str | None = None, progress: Callable[[str], None] | None = None,
             label: Callable[[CellJob], str] = _label,
             also_done: Callable[[CellJob], bool] | None = None) -> int:
    """Run ``run`` for each job not done yet, saving each cell as it finishes.

    A job is done when its ``path`` holds whole records; each cell's records go to its
    ``path``. A file there that is not whole is named in a warning, moved aside (to
    ``<path>.corrupt``) and its cell run again.

    ``backend`` is ``"local"`` (``workers`` processes; 1 runs in this process) or ``"ray"``
    (a local Ray instance with ``workers`` CPUs, or the cluster at ``address``).
    ``progress`` hears "K of N cells already done", then ``label(job)`` of each finished cell.
    ``also_done(job)``: what else a done job must have written (e.g. its saved model).
    Returns the number of cells run.
    """
    check_backend(backend, address, workers)
    todo = [j for j in jobs
            if not (_done(j.path) and (also_done is None or also_done(j)))]
    if progress is not None:
        progress(f"{len(jobs) - len(todo)} of {len(jobs)} cells already done")
    if not todo:
        return 0
    finished = (_local(run, todo, workers) if backend == "local"
                else _ray(run, todo, workers, address))
    with closing(finished):  # an interrupt stops the backend's waiting cells at once
        for job, records in finished:
            if records is not None:  # Ray's: its workers may not share the run folder
                save_cell(job.path, records)
            if progress is not None:
                progress(label(job))
    return len(todo)
