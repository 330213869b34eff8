"""What the commands share: the --config option, the backend options and a progress bar.

The bar (:class:`~jointattention.jobs.progress.CellBar`) is the jobs', for Python callers too.
"""

from __future__ import annotations

import argparse
import os
from collections.abc import Iterator
from contextlib import contextmanager

from ..jobs.progress import CellBar, LazyBar

__all__ = ["CellBar", "LazyBar", "add_backend", "add_cell", "add_config", "add_max_cells",
           "int_in", "output_place", "workers"]


def int_in(lo: int, hi: int):
    """An argparse type: an integer in [lo, hi], else argparse's one error line."""
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r}: expected an integer") from None
        if not lo <= value <= hi:
            raise argparse.ArgumentTypeError(f"{value}: expected an integer in [{lo}, {hi}]")
        return value

    parse.__name__ = "integer"
    return parse


def add_config(p: argparse.ArgumentParser) -> None:
    """The ``--config PRESET|FILE.toml`` option."""
    p.add_argument("--config", metavar="PRESET|FILE.toml",
                   help="a preset name or a TOML file (default: built-in defaults)")


def add_cell(p: argparse.ArgumentParser) -> None:
    """The options naming one cell: --preset, --config, --condition and --seed-index."""
    p.add_argument("--preset", default="paper", help="a shipped preset (default: paper)")
    add_config(p)
    p.add_argument("--condition", default="n5-sigmoid",
                   help="the condition to learn (default: n5-sigmoid)")
    p.add_argument("--seed-index", type=int_in(0, 10**6), default=0,
                   help="the cell's seed index (default: 0)")


def add_backend(p: argparse.ArgumentParser) -> None:
    """The ``--workers``, ``--backend`` and ``--address`` options."""
    p.add_argument("--workers", type=int_in(0, 1024), default=0,
                   help="worker processes or Ray CPUs (default: one per core, never more than "
                        "cells); results do not depend on it")
    p.add_argument("--backend", choices=("local", "ray"), default="local",
                   help="where cells run: local processes (default) or Ray (the ray extra)")
    p.add_argument("--address", help="with --backend ray: the address of a Ray cluster to join "
                                     "(default: start a local Ray instance)")


def add_max_cells(p: argparse.ArgumentParser) -> None:
    """The ``--max-cells`` bound on work."""
    p.add_argument("--max-cells", type=int_in(1, 10**9), default=100_000,
                   help="refuse runs of more cells than this, before anything runs "
                        "(default: 100,000)")


@contextmanager
def output_place(args: argparse.Namespace) -> Iterator[None]:
    """Check the command's output place before any work, and hold it while the command runs.

    A command declares its output with ``set_defaults(out_kind="file" | "folder" | "run")``
    (and ``out_what``, if it is not ``--out``); "run": a run folder, which the run locks
    itself (:func:`~jointattention._files.folder_lock`). A command given no output is let be.
    """
    from .._files import check_writable, output_lock

    kind, out = getattr(args, "out_kind", None), getattr(args, "out", None)
    if kind is None or out is None:
        yield
        return
    what = getattr(args, "out_what", "--out")
    check_writable(out, "folder" if kind == "run" else kind, what)
    if kind == "run":
        yield
        return
    with output_lock(out, what):
        yield


def workers(args: argparse.Namespace) -> int:
    """--workers, or one per core."""
    return args.workers or os.cpu_count() or 1
