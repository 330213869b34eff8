"""The command line: ``jointattention COMMAND --help`` documents each command.

Each command only parses its arguments and calls the library; the commands are registered by
:mod:`.run` (reproduce, sweep, report, bench, config), :mod:`.vision` (parity, detect, gaze,
faces), :mod:`.world` (render, datasets), :mod:`.robot` (train, follow, datasets import) and
:mod:`.evaluate` (evaluate, closed-loop).

Layer 10, the top: it may import anything; nothing in the package imports it.
"""

from __future__ import annotations

import argparse
import logging
import os
import signal
import sys
import threading

from .._version import __version__
from ..errors import JointAttentionError
from ..world.gl import suggested_backend
from . import evaluate, robot, run, vision, world
from ._common import output_place

__all__ = ["build_parser", "main"]


class _Parser(argparse.ArgumentParser):
    """A parser whose errors are one line, as the commands' own errors are."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message}; see {self.prog} --help\n")


def build_parser() -> argparse.ArgumentParser:
    """The parser of every command."""
    parser = _Parser(
        prog="jointattention",
        description="The bootstrap learning model for joint attention: simulated world, "
                    "data sets and experiments.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    run.add_commands(sub)
    vision.add_commands(sub)
    world.add_commands(sub)
    robot.add_commands(sub)
    evaluate.add_commands(sub)
    return parser


class _Terminated(KeyboardInterrupt):
    """SIGTERM (kill, timeout, Slurm, docker stop), handled as an interrupt is."""


def _terminate(signum, frame) -> None:
    raise _Terminated


def _warnings_to_stderr() -> None:
    """The library's warnings (e.g. a corrupt cell recomputed) as ``jointattention: warning:``."""
    log = logging.getLogger("jointattention")
    if not log.handlers:
        handler = logging.StreamHandler()
        handler.setFormatter(logging.Formatter("jointattention: warning: %(message)s"))
        log.addHandler(handler)
        log.propagate = False


def main(argv: list[str] | None = None) -> int:
    """Run the command line; user errors print one line and exit with status 2.

    SIGINT and SIGTERM end the command and its worker processes; finished cells are kept
    (exit status 130 and 143).
    """
    args = build_parser().parse_args(argv)
    _warnings_to_stderr()
    # The program, not the library, chooses its process's OpenGL backend when the user did not
    # (the library only reads MUJOCO_GL): off-screen, as a command has no window.
    os.environ.setdefault("MUJOCO_GL", suggested_backend())
    previous = signal.getsignal(signal.SIGTERM)
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGTERM, _terminate)
    try:
        with output_place(args):  # judged before any work; held until the command ends
            args.func(args)
    except JointAttentionError as err:
        message = str(err).replace("\n", "\\n")  # one line, whatever a name held
        print(f"jointattention: error: {message}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as err:
        terminated = isinstance(err, _Terminated)
        print(f"jointattention: {'terminated' if terminated else 'interrupted'}; finished "
              "cells are kept, re-run the command to resume", file=sys.stderr)
        return 143 if terminated else 130
    finally:
        if threading.current_thread() is threading.main_thread():
            signal.signal(signal.SIGTERM, previous)
    return 0
