"""The command line's run commands.

``reproduce``, ``sweep``, ``report``, ``bench`` and ``config``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..config import preset_names
from ._common import CellBar, add_backend, add_config, add_max_cells, int_in, workers

__all__ = ["BENCH_SECTIONS", "add_commands"]

# What the bench measures, in its order (``jointattention bench --only``).
BENCH_SECTIONS = ("compile", "world", "agents", "environments", "following")


def _cmd_reproduce(args: argparse.Namespace) -> None:
    from ..config import load_config, preset_about
    from ..jobs.reproduce import reproduce

    config = load_config(args.preset if args.config is None else args.config)
    n_workers = workers(args)
    exp = config.experiment
    with CellBar(len(exp.conditions) * exp.n_seeds) as bar:
        result = reproduce(config, Path(args.out), workers=n_workers, backend=args.backend,
                           address=args.address, progress=bar, max_cells=args.max_cells,
                           save_models=args.save_models, trials_csv=args.trials_csv)
    if args.config is None:
        print(f"preset {args.preset}: {preset_about(args.preset)}")
    print(result.summary(n_workers))


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
    from ..figures.report import screenshot, write_report

    if args.screenshot:  # --out is judged with every command's (cli.main)
        check_writable(args.screenshot, "file", "--screenshot")
    page = write_report(args.run, args.out)
    print(page)
    if args.screenshot:
        print(screenshot(page, args.screenshot))


def _cmd_bench(args: argparse.Namespace) -> None:
    from ..config import load_config
    from ..jobs.bench import (
        compile_times,
        run_agent_benchmark,
        run_env_benchmark,
        run_follow_benchmark,
        run_world_benchmarks,
        write_bench,
    )
    from ..jobs.estimates import agent_rates, preset_estimates, run_preset

    n_workers = workers(args)
    for preset in args.run:
        load_config(preset)  # an unknown preset is refused before anything runs
    only = [s for s in BENCH_SECTIONS if s in (args.only or BENCH_SECTIONS)]
    measured: list = []

    def show(what: str, rows: list) -> list:
        """Print ``rows`` as soon as they are measured, after a status line on stderr."""
        print(f"measured: {what}", file=sys.stderr, flush=True)
        for name, value, unit in rows:
            digits = 1 if unit in ("min", "x", "s", "us") else 0
            if unit == "x" and value < 10:
                digits = 2  # the ratios against an aim (CartPole's): 0.92, not 0.9
            print(f"{name:<60} {value:>10,.{digits}f} {unit}", flush=True)
        measured.extend(rows)
        return rows

    print(f"measuring: {', '.join(only)} (a few minutes)", file=sys.stderr, flush=True)
    agent, env_rows = [], []
    if "compile" in only:
        show("compile times", compile_times())
    if "world" in only:
        show("the world", run_world_benchmarks(load_config(args.config).world))
    if "agents" in only:
        agent = run_agent_benchmark()
    if "environments" in only:
        env_rows = show("the environments", run_env_benchmark())
    if "following" in only:
        show("following", run_follow_benchmark())
    if agent:
        show("the agents, and each preset's estimated wall time",
             agent + preset_estimates(agent_rates(agent), n_workers))
    for preset in args.run:
        show(f"the {preset} preset, run", run_preset(preset, n_workers))
    if args.out:
        command = "jointattention bench" + "".join(f" --only {s}" for s in args.only or ())
        for path in write_bench(args.out, measured, env_rows, command):
            print(path)


def _cmd_config(args: argparse.Namespace) -> None:
    from ..config import load_config, preset_about, preset_names, to_toml

    if args.list:
        names = preset_names()
        width = max(map(len, names))
        print("\n".join(f"{n:<{width}}  {preset_about(n)}" for n in names))
    else:
        print(to_toml(load_config(args.config)), end="")


def add_commands(sub) -> None:
    """Register ``reproduce``, ``sweep``, ``report``, ``bench`` and ``config`` on ``sub``."""
    p = sub.add_parser("reproduce", help="the main job: run the paper's experiments",
                       description="Run every condition x seed of the preset (learning in the "
                                   "fast world), measure the oracle ceilings, and write "
                                   "Fig. 4(a), Fig. 4(b), Fig. 5, table.md/csv, claims.md/csv "
                                   "and the held-out, diagnostic and learning-speed tables "
                                   "into --out, then print a short summary (the full claims "
                                   "are in claims.md and the report). Re-running the same "
                                   "command resumes: finished cells are kept.")
    p.add_argument("--preset", default="quick", choices=preset_names(), metavar="PRESET",
                   help="a shipped preset: " + ", ".join(preset_names()) + " (default: quick; "
                        "`jointattention config --list` says what each runs)")
    add_config(p)
    p.add_argument("--out", default="runs/reproduce", help="run folder (default: runs/reproduce)")
    p.add_argument("--trials-csv", action="store_true",
                   help="also write trials.csv: every trial of every cell in one tidy table "
                        "(the cells/ files hold the same records; the beyond preset's takes "
                        "most of a gigabyte)")
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
    p.add_argument("--screenshot", metavar="FILE.png",
                   help="also draw the top of the page into FILE.png with a headless Chromium "
                        "(how docs/report_screenshot.png is made from the demo's run)")
    p.set_defaults(func=_cmd_report, out_kind="file")

    p = sub.add_parser(
        "bench", help="print speeds: rendering, projection, agent steps, preset wall times",
        description="Measure frames/s of rendering and projections/s of the fast path at the "
                    "configured image size, agent-steps/s of a learning run, and estimate each "
                    "preset's wall time from it (--run PRESET measures it); the environments' "
                    "steps/s, and JointAttentionFace-v2's against CartPole-v1's in the same "
                    "run.")
    add_config(p)
    p.add_argument("--workers", type=int_in(0, 1024), default=0,
                   help="worker processes for the preset times (default: all cores)")
    p.add_argument("--run", action="append", default=[], metavar="PRESET",
                   help="also run this preset from scratch and print its wall time "
                        "(repeatable; the bench's estimate of each preset comes first)")
    p.add_argument("--only", action="append", choices=BENCH_SECTIONS, metavar="SECTION",
                   help="measure only this section (repeatable): "
                        + ", ".join(BENCH_SECTIONS) + " (default: all)")
    p.add_argument("--out", metavar="FOLDER",
                   help="also write the figures into FOLDER: bench.csv (every row) and "
                        "environments.md (the environments' table, with CartPole-v1's in the "
                        "same run; docs/results/speed/ holds the one the manual includes)")
    p.set_defaults(func=_cmd_bench, out_kind="folder")

    p = sub.add_parser("config", help="print a configuration as TOML",
                       description="Print the configuration (with every default) as TOML.")
    add_config(p)
    p.add_argument("--list", action="store_true",
                   help="list the shipped presets, each with what it runs")
    p.set_defaults(func=_cmd_config)
