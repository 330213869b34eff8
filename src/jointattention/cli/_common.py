"""What the commands share: the --config option, the backend options and a progress bar."""

from __future__ import annotations

import argparse
import os

__all__ = ["CellBar", "add_backend", "add_config", "workers"]


def add_config(p: argparse.ArgumentParser) -> None:
    """The ``--config PRESET|FILE.toml`` option."""
    p.add_argument("--config", metavar="PRESET|FILE.toml",
                   help="a preset name or a TOML file (default: built-in defaults)")


def add_backend(p: argparse.ArgumentParser) -> None:
    """The ``--workers``, ``--backend`` and ``--address`` options."""
    p.add_argument("--workers", type=int, default=0,
                   help="worker processes or Ray CPUs (default: one per core); results do not "
                        "depend on it")
    p.add_argument("--backend", choices=("local", "ray"), default="local",
                   help="where cells run: local processes (default) or Ray (the ray extra)")
    p.add_argument("--address", help="with --backend ray: the address of a Ray cluster to join "
                                     "(default: start a local Ray instance)")


def workers(args: argparse.Namespace) -> int:
    """--workers, or one per core."""
    return args.workers or os.cpu_count() or 1


class CellBar:
    """A progress bar over cells, fed by the runners' progress messages."""

    def __init__(self, total: int):
        from tqdm import tqdm

        self.bar = tqdm(total=total, desc="cells", unit="cell")

    def __call__(self, message: str) -> None:
        """Count a finished cell, or show a message of the runner."""
        if message.endswith("already done"):  # "K of N cells already done"
            self.bar.update(int(message.split()[0]))
            self.bar.write(message)
        elif message == "ceilings":
            self.bar.write("measuring the oracle ceilings")
        else:
            self.bar.update(1)
            self.bar.set_postfix_str(message)

    def __enter__(self) -> CellBar:
        return self

    def __exit__(self, *exc) -> None:
        self.bar.close()
