"""The command line: ``jointattention COMMAND --help`` documents each command."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from . import __version__
from ._cli_vision import add_commands as add_vision_commands
from .errors import JointAttentionError

__all__ = ["main"]


def _add_config(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--config",
        metavar="PRESET|FILE.toml",
        help="a preset name or a TOML file (default: built-in defaults)",
    )


class _CellBar:
    """A progress bar over cells, fed by the runners' progress messages."""

    def __init__(self, total: int):
        from tqdm import tqdm

        self.bar = tqdm(total=total, desc="cells", unit="cell")
        self.done_before = 0

    def __call__(self, message: str) -> None:
        if message.endswith("already done"):  # "K of N cells already done"
            self.done_before = int(message.split()[0])
            self.bar.update(self.done_before)
            self.bar.write(message)
        else:
            self.bar.update(1)
            self.bar.set_postfix_str(message)

    def __enter__(self) -> _CellBar:
        return self

    def __exit__(self, *exc) -> None:
        self.bar.close()


def _workers(args: argparse.Namespace) -> int:
    """--workers, or one per core."""
    import os

    return args.workers or os.cpu_count() or 1


def _cmd_render(args: argparse.Namespace) -> None:
    from .config import load_config
    from .world.pictures import face_sheet, robot_view
    from .world.simulator import World

    config = load_config(args.config)
    seed = config.seed if args.seed is None else args.seed
    out = Path(args.out)
    with World(config.world, seed=seed) as world:
        print(robot_view(world, out / "robot_view.png"))
        print(face_sheet(world, out / "face_windows.png"))


def _cmd_datasets_make(args: argparse.Namespace) -> None:
    from tqdm import tqdm

    from .config import load_config
    from .datasets import save
    from .world.recording import make_datasets

    config = load_config(args.config)
    if args.n < 1:
        raise JointAttentionError(f"--n {args.n}: expected at least 1 data set")
    with tqdm(total=args.n, desc="data sets", unit="set", disable=args.quiet) as bar:
        ds = make_datasets(config.world, args.n, args.seed, progress=lambda i: bar.update(1))
    print(save(ds, args.out))


def _cmd_datasets_check(args: argparse.Namespace) -> None:
    import numpy as np

    from .datasets import default_datasets, load

    ds = default_datasets() if args.file is None else load(args.file)
    w, h = ds.window_size_px
    cmd = np.rad2deg(ds.command_rad)
    print(
        f"{args.file or 'shipped default'}: {len(ds)} data sets, face windows {w}x{h}, "
        f"commands pan [{cmd[:, 0].min():.1f}, {cmd[:, 0].max():.1f}] deg, "
        f"tilt [{cmd[:, 1].min():.1f}, {cmd[:, 1].max():.1f}] deg, "
        f"target positions {'present' if ds.target_m is not None else 'absent'}"
    )


def _cmd_bench(args: argparse.Namespace) -> None:
    from .bench import (
        preset_estimates,
        run_agent_benchmark,
        run_env_benchmark,
        run_preset,
        run_world_benchmarks,
    )
    from .config import load_config

    workers = _workers(args)
    for preset in args.run:
        load_config(preset)  # an unknown preset is refused before anything runs
    rows = run_world_benchmarks(load_config(args.config).world)
    agent = run_agent_benchmark()
    rows += run_env_benchmark() + agent + preset_estimates(agent[0][1], agent[1][1], workers)
    for preset in args.run:
        rows += run_preset(preset, workers)
    for name, value, unit in rows:
        print(f"{name:<60} {value:>10,.{1 if unit in ('min', 'x') else 0}f} {unit}")


def _cmd_config(args: argparse.Namespace) -> None:
    from .config import load_config, preset_names, to_toml

    if args.list:
        print("\n".join(preset_names()))
    else:
        print(to_toml(load_config(args.config)), end="")


def _cmd_reproduce(args: argparse.Namespace) -> None:
    from tqdm import tqdm

    from .config import load_config
    from .experiment import measure_ceiling, run_experiment
    from .io import save_json, write_trials_csv
    from .plotting import write_figures

    config = load_config(args.config or args.preset)
    out = Path(args.out)
    workers = _workers(args)
    exp = config.experiment
    start = time.perf_counter()
    with _CellBar(len(exp.conditions) * exp.n_seeds) as bar:
        cells = run_experiment(config, out, workers=workers, progress=bar,
                               backend=args.backend, address=args.address)
    done_before = bar.done_before
    wall_min = (time.perf_counter() - start) / 60
    save_json({"wall_min": round(wall_min, 2), "workers": workers,
               "cells_run": len(cells) - done_before, "cells_total": len(cells)},
              out / "timing.json")
    ceiling_file = out / "ceilings.json"
    if not ceiling_file.exists():
        counts = sorted({c.n_objects for c in exp.conditions})
        ceilings = {str(n): measure_ceiling(config, n) for n in tqdm(counts, desc="ceilings")}
        save_json(ceilings, ceiling_file)
    write_trials_csv(out, cells)
    for path in write_figures(out):
        print(path)
    print((out / "claims.md").read_text(), end="")
    print(f"{len(cells) - done_before} cells in {wall_min:.1f} min on {workers} workers")


def _add_backend(p: argparse.ArgumentParser) -> None:
    p.add_argument("--workers", type=int, default=0,
                   help="worker processes or Ray CPUs (default: one per core); results do not "
                        "depend on it")
    p.add_argument("--backend", choices=("local", "ray"), default="local",
                   help="where cells run: local processes (default) or Ray (the ray extra)")
    p.add_argument("--address", help="with --backend ray: the address of a Ray cluster to join "
                                     "(default: start a local Ray instance)")


def _cmd_sweep(args: argparse.Namespace) -> None:
    from .sweep import load_sweep, run_sweep

    sweep = load_sweep(args.spec)
    out = Path(args.out or Path("runs") / Path(args.spec).stem)
    workers = _workers(args)
    total = sum(len(c.experiment.conditions) * c.experiment.n_seeds
                for c in sweep.points.values())
    with _CellBar(total) as bar:
        run_sweep(sweep, out, workers=workers, backend=args.backend, address=args.address,
                  progress=bar)
    print((out / "summary.md").read_text(), end="")
    print(out / "summary.csv")


def _cmd_report(args: argparse.Namespace) -> None:
    from .report import write_report

    print(write_report(args.run, args.out))


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="jointattention",
        description="The bootstrap learning model for joint attention: simulated world, "
        "data sets and experiments.",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    p = sub.add_parser("reproduce", help="the main job: run the paper's experiments",
                       description="Run every condition x seed of the preset (learning in the "
                                   "fast world), measure the oracle ceilings, and write "
                                   "Fig. 4(a), Fig. 4(b), Fig. 5, table.md/csv and trials.csv "
                                   "into --out. Re-running the same command resumes: finished "
                                   "cells are kept.")
    p.add_argument("--preset", default="quick",
                   help="a shipped preset (`jointattention config --list`): quick (minutes), "
                        "paper (the paper's scale), ablation, ablation-paper")
    _add_config(p)
    p.add_argument("--out", default="runs/reproduce", help="run folder (default: runs/reproduce)")
    _add_backend(p)
    p.set_defaults(func=_cmd_reproduce)

    p = sub.add_parser(
        "sweep", help="run a grid of settings x conditions x seeds from a TOML spec",
        description="Run every point of SPEC's grid (each a run folder under --out), every "
                    "condition and seed; write summary.csv and summary.md. Re-running resumes: "
                    "finished cells are kept, and an interrupt loses none of them. The spec's "
                    "format: see examples/sweep.toml or `help(jointattention.sweep)`.")
    p.add_argument("spec", metavar="SPEC.toml", help="the sweep spec")
    p.add_argument("--out", help="output folder (default: runs/<SPEC's name>)")
    _add_backend(p)
    p.set_defaults(func=_cmd_sweep)

    p = sub.add_parser(
        "report", help="one self-contained HTML page of a run folder",
        description="Write RUN_FOLDER/report.html: the claims, the table, the figures (inline), "
                    "the ceilings, the configuration and the versions it ran with; readable "
                    "offline. Also takes a sweep's folder.")
    p.add_argument("run", metavar="RUN_FOLDER", help="a folder written by reproduce or sweep")
    p.add_argument("--out", help="the HTML file (default: RUN_FOLDER/report.html)")
    p.set_defaults(func=_cmd_report)

    add_vision_commands(sub, _add_config)

    p = sub.add_parser(
        "render",
        help="PNGs of the robot's view and of face windows",
        description="Write robot_view.png (the room, the robot looking at the "
        "caregiver and at its target) and face_windows.png (face "
        "windows across gaze directions) into --out.",
    )
    _add_config(p)
    p.add_argument("--seed", type=int, help="world seed (default: the configuration's)")
    p.add_argument("--out", default="runs/render", help="output folder (default: runs/render)")
    p.set_defaults(func=_cmd_render)

    p = sub.add_parser(
        "datasets",
        help="make or check caregiver data sets",
        description="Caregiver data sets in the paper's protocol.",
    )
    dsub = p.add_subparsers(dest="action", required=True, metavar="ACTION")
    q = dsub.add_parser(
        "make",
        help="record N data sets from the simulated world",
        description="Record N data sets (face window, head angle, command to "
        "the target, target position) into OUT (.npz).",
    )
    _add_config(q)
    q.add_argument("--n", type=int, default=125, help="number of data sets (default: 125)")
    q.add_argument("--seed", type=int, default=0, help="world seed (default: 0)")
    q.add_argument("--quiet", action="store_true", help="no progress bar")
    q.add_argument("out", metavar="OUT", help="output file, ending in .npz")
    q.set_defaults(func=_cmd_datasets_make)
    q = dsub.add_parser(
        "check",
        help="validate a data-set file and summarise it",
        description="Validate FILE (default: the shipped data sets).",
    )
    q.add_argument("file", metavar="FILE", nargs="?", help="a data-set .npz file")
    q.set_defaults(func=_cmd_datasets_check)

    p = sub.add_parser(
        "bench",
        help="print speeds: rendering, projection, agent steps, preset wall times",
        description="Measure frames/s of rendering and projections/s of the fast path at the "
        "configured image size, agent-steps/s of a learning run, and estimate each preset's "
        "wall time from it (--run PRESET measures it).",
    )
    _add_config(p)
    p.add_argument("--workers", type=int, default=0,
                   help="worker processes for the preset times (default: all cores)")
    p.add_argument("--run", action="append", default=[], metavar="PRESET",
                   help="also run this preset from scratch and print its wall time "
                   "(repeatable; the paper preset takes the better part of an hour)")
    p.set_defaults(func=_cmd_bench)

    p = sub.add_parser(
        "config",
        help="print a configuration as TOML",
        description="Print the configuration (with every default) as TOML.",
    )
    _add_config(p)
    p.add_argument("--list", action="store_true", help="list the shipped presets")
    p.set_defaults(func=_cmd_config)
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
