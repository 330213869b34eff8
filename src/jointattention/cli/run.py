"""The command line's run commands.

``reproduce``, ``sweep``, ``report``, ``bench`` and ``config``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ._common import CellBar, add_backend, add_config, add_max_cells, int_in, workers

__all__ = ["add_commands"]


def _cmd_reproduce(args: argparse.Namespace) -> None:
    from ..config import load_config
    from ..jobs.reproduce import reproduce

    config = load_config(args.preset if args.config is None else args.config)
    n_workers = workers(args)
    exp = config.experiment
    with CellBar(len(exp.conditions) * exp.n_seeds) as bar:
        result = reproduce(config, Path(args.out), workers=n_workers, backend=args.backend,
                           address=args.address, progress=bar, max_cells=args.max_cells,
                           save_models=args.save_models)
    for path in result.files:
        print(path)
    print((result.out / "claims.md").read_text(), end="")
    print(f"{result.cells_run} cells in {result.cells_min:.1f} min on {n_workers} workers; "
          f"the whole run {result.wall_min:.1f} min")


def _cmd_sweep(args: argparse.Namespace) -> None:
    from ..jobs.sweep import load_sweep, run_sweep

    sweep = load_sweep(args.spec, max_cells=args.max_cells)
    out = Path(args.out or Path("runs") / Path(args.spec).stem)
    total = sum(len(c.experiment.conditions) * c.experiment.n_seeds
                for c in sweep.points.values())
    with CellBar(total) as bar:
        run_sweep(sweep, out, workers=workers(args), backend=args.backend,
                  address=args.address, progress=bar, max_cells=args.max_cells)
    print((out / "summary.md").read_text(), end="")
    print(out / "summary.csv")


def _cmd_report(args: argparse.Namespace) -> None:
    from .._files import check_writable
    from ..figures.report import write_report

    if args.out:
        check_writable(args.out, "file")
    print(write_report(args.run, args.out))


def _cmd_bench(args: argparse.Namespace) -> None:
    from ..config import load_config
    from ..jobs.bench import (
        compile_times,
        run_agent_benchmark,
        run_env_benchmark,
        run_follow_benchmark,
        run_world_benchmarks,
    )
    from ..jobs.estimates import agent_rates, preset_estimates, run_preset

    n_workers = workers(args)
    for preset in args.run:
        load_config(preset)  # an unknown preset is refused before anything runs
    rows = compile_times() + run_world_benchmarks(load_config(args.config).world)
    agent = run_agent_benchmark()
    rows += run_env_benchmark() + run_follow_benchmark() + agent + preset_estimates(
        agent_rates(agent), n_workers)
    for preset in args.run:
        rows += run_preset(preset, n_workers)
    for name, value, unit in rows:
        print(f"{name:<60} {value:>10,.{1 if unit in ('min', 'x', 's', 'us') else 0}f} {unit}")


def _cmd_config(args: argparse.Namespace) -> None:
    from ..config import load_config, preset_names, to_toml

    if args.list:
        print("\n".join(preset_names()))
    else:
        print(to_toml(load_config(args.config)), end="")


def add_commands(sub) -> None:
    """Register ``reproduce``, ``sweep``, ``report``, ``bench`` and ``config`` on ``sub``."""
    p = sub.add_parser("reproduce", help="the main job: run the paper's experiments",
                       description="Run every condition x seed of the preset (learning in the "
                                   "fast world), measure the oracle ceilings, and write "
                                   "Fig. 4(a), Fig. 4(b), Fig. 5, table.md/csv, claims.md/csv "
                                   "and trials.csv into --out. Re-running the same command "
                                   "resumes: finished cells are kept.")
    p.add_argument("--preset", default="quick",
                   help="a shipped preset (`jointattention config --list`): quick (minutes), "
                        "paper (the paper's scale), ablation, ablation-paper, beyond (the models "
                        "beyond the paper), rendered")
    add_config(p)
    p.add_argument("--out", default="runs/reproduce", help="run folder (default: runs/reproduce)")
    p.add_argument("--save-models", action="store_true",
                   help="also save each cell's learned model in RUN/models/<condition>/"
                        "seed_<i>.npz (the bootstrap model; see jointattention follow)")
    add_backend(p)
    add_max_cells(p)
    p.set_defaults(func=_cmd_reproduce, out_kind="run")

    p = sub.add_parser(
        "sweep", help="run a grid of settings x conditions x seeds from a TOML spec",
        description="Run every point of SPEC's grid (each a run folder under --out), every "
                    "condition and seed; write summary.csv and summary.md. Re-running resumes: "
                    "finished cells are kept, and an interrupt loses none of them. The spec's "
                    "format: see examples/sweep.toml or `help(jointattention.jobs.sweep)`.")
    p.add_argument("spec", metavar="SPEC.toml", help="the sweep spec")
    p.add_argument("--out", help="output folder (default: runs/<SPEC's name>)")
    add_backend(p)
    add_max_cells(p)
    p.set_defaults(func=_cmd_sweep, out_kind="run")

    p = sub.add_parser(
        "report", help="one self-contained HTML page of a run folder",
        description="Write RUN_FOLDER/report.html: the claims, the table, the figures (inline), "
                    "the ceilings, the configuration and the versions it ran with; readable "
                    "offline. Also takes a sweep's folder.")
    p.add_argument("run", metavar="RUN_FOLDER", help="a folder written by reproduce or sweep")
    p.add_argument("--out", help="the HTML file (default: RUN_FOLDER/report.html)")
    p.set_defaults(func=_cmd_report, out_kind="file")

    p = sub.add_parser(
        "bench", help="print speeds: rendering, projection, agent steps, preset wall times",
        description="Measure frames/s of rendering and projections/s of the fast path at the "
                    "configured image size, agent-steps/s of a learning run, and estimate each "
                    "preset's wall time from it (--run PRESET measures it).")
    add_config(p)
    p.add_argument("--workers", type=int_in(0, 1024), default=0,
                   help="worker processes for the preset times (default: all cores)")
    p.add_argument("--run", action="append", default=[], metavar="PRESET",
                   help="also run this preset from scratch and print its wall time "
                        "(repeatable; the paper preset takes the better part of an hour)")
    p.set_defaults(func=_cmd_bench)

    p = sub.add_parser("config", help="print a configuration as TOML",
                       description="Print the configuration (with every default) as TOML.")
    add_config(p)
    p.add_argument("--list", action="store_true", help="list the shipped presets")
    p.set_defaults(func=_cmd_config)
