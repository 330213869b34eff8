"""The command line: ``jointattention COMMAND --help`` documents each command.

Each command only parses its arguments and calls the library; the commands are registered by
:mod:`.run` (reproduce, sweep, report, bench, config), :mod:`.vision` (parity, detect, gaze)
and :mod:`.world` (render, datasets).
"""

from __future__ import annotations

import argparse
import sys

from .. import __version__
from ..errors import JointAttentionError
from . import run, vision, world

__all__ = ["build_parser", "main"]


def build_parser() -> argparse.ArgumentParser:
    """The parser of every command."""
    parser = argparse.ArgumentParser(
        prog="jointattention",
        description="The bootstrap learning model for joint attention: simulated world, "
                    "data sets and experiments.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    run.add_commands(sub)
    vision.add_commands(sub)
    world.add_commands(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; user errors print one line and exit with status 2."""
    args = build_parser().parse_args(argv)
    try:
        args.func(args)
    except JointAttentionError as err:
        print(f"jointattention: error: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("jointattention: interrupted", file=sys.stderr)
        return 130
    return 0
