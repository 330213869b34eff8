"""Many caregivers: does a module that learned from K people follow a person it never saw?

Usage::

    python scripts/caregivers.py [--out docs/results/caregivers] [--ks "1 2 4 8 16"] [--held-out 4]
        [--poses 125] [--seed 0] [--held-out-seed 1] [--seeds 3] [--n-steps 300000]
        [--setup NAME[:KEY=VALUE,...]]... [--cache DIR] [--quick]

Records (``jointattention.world.recording.make_datasets``) training data sets of K caregiver
identities from world seed ``--seed``, ``--poses`` data sets per identity (so the training data
grow with K: K = 16 is 2000 data sets at 125 poses), and a held-out set of ``--held-out``
identities from another world seed (``--held-out-seed``), checked to be none of the training
identities. A control learns from one identity with as many data sets as the largest K, to
tell more people from more data. Recordings are kept in ``--cache`` (default
runs/caregivers/cache) and reused when their seed, size, caregivers and world match.

For each setup, K and seed index, one cell learns (preset ``paper``, condition ``n5-sigmoid``,
``experiment.cells.run_cell`` with ``datasets`` pointing at the K-identity file), and the
learned module's angle errors (``experiment.probes.angle_errors``) are measured on the faces it
learned from and on the held-out identities: the median, and the fraction within 20 degrees.
A setup is a name and changes to the paper preset: ``n_steps`` (learning time; default
``--n-steps``) and any ``[model]`` option of the condition's model, dotted for tables, e.g.
``wide:n_hidden=30,learning_rate=5e-05,n_steps=1200000`` or ``const:gate.kind=constant,
gate.rate=0.7``. Default setups: ``paper`` (the preset as it is), ``wide`` (30 hidden units)
and ``wide-slow-long`` (30 hidden units, learning rate 5e-5, 1.2x10^6 steps).

Writes into ``--out``: ``table.md`` (one row per setup and K, with the command and wall time),
``results.csv`` (one row per cell) and ``unseen.png`` (median error on unseen identities
against K, the 10 degree aim as a line). ``--quick`` is a small run for tests (2 identities at
most, 6 poses each, 1000 steps, one seed, into runs/caregivers-quick unless --out is given).
"""

from __future__ import annotations

import argparse
import copy
import csv
import dataclasses
import io
import os
import shlex
import sys
import time
import tomllib
from pathlib import Path

import numpy as np

from jointattention._files import write_text
from jointattention.analysis.tables import Table
from jointattention.config import Config, condition_named, load_config, to_toml
from jointattention.datasets import CaregiverDatasets, load, save
from jointattention.errors import DatasetError, JointAttentionError
from jointattention.experiment.cells import run_cell
from jointattention.experiment.probes import angle_errors
from jointattention.figures._save import new_figure, save_figure
from jointattention.world.gl import suggested_backend
from jointattention.world.recording import make_datasets
from jointattention.world.simulator import World

# A program chooses its process's OpenGL backend (the library only reads MUJOCO_GL).
os.environ.setdefault("MUJOCO_GL", suggested_backend())

PRESET, CONDITION = "paper", "n5-sigmoid"
AIM_DEG = 10.0  # the aim: median error on unseen identities at most this
WITHIN_DEG = 20.0
DEFAULT_SETUPS = ("paper", "wide:n_hidden=30",
                  "wide-slow-long:n_hidden=30,learning_rate=5e-05,n_steps=1200000")
QUICK = {"ks": "1 2", "poses": 6, "held_out": 1, "seeds": 1, "n_steps": 1000}


@dataclasses.dataclass(frozen=True)
class Setup:
    """A named change to the paper preset: its learning time and its model's changes."""

    name: str
    n_steps: int
    model: dict

    @property
    def changes(self) -> str:
        """The learning time and the model's changes, as ``KEY=VALUE`` items."""
        items = [f"n_steps={self.n_steps}", *_flat(self.model)]
        return ", ".join(items)


def _flat(table: dict, prefix: str = "") -> list[str]:
    out = []
    for key, value in table.items():
        if isinstance(value, dict):
            out += _flat(value, f"{prefix}{key}.")
        else:
            out.append(f"{prefix}{key}={value}")
    return out


def _value(text: str):
    """A TOML value (number, boolean, quoted string), else the text itself."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


def parse_setup(text: str, n_steps: int) -> Setup:
    """``NAME[:KEY=VALUE,...]``; KEY is ``n_steps`` or a (dotted) ``[model]`` option."""
    name, _, rest = text.partition(":")
    if not name.strip():
        raise argparse.ArgumentTypeError(f"--setup {text!r}: expected NAME[:KEY=VALUE,...]")
    model: dict = {}
    for item in filter(None, (s.strip() for s in rest.split(","))):
        key, eq, value = item.partition("=")
        if not eq or not key.strip():
            raise argparse.ArgumentTypeError(f"--setup {text!r}: {item!r}: expected KEY=VALUE")
        if key.strip() == "n_steps":
            n_steps = _value(value.strip())
            if not isinstance(n_steps, int) or isinstance(n_steps, bool) or n_steps < 1:
                raise argparse.ArgumentTypeError(f"--setup {text!r}: n_steps={value.strip()}: "
                                                 "expected a positive integer")
            continue
        *path, last = key.strip().split(".")
        table = model
        for part in path:
            table = table.setdefault(part, {})
        table[last] = _value(value.strip())
    return Setup(name.strip(), n_steps, model)


def cell_config(setup: Setup, datasets: Path) -> Config:
    """The paper preset learning from ``datasets``, with the setup's changes (validated)."""
    mapping = tomllib.loads(to_toml(load_config(PRESET)))
    mapping["datasets"] = str(datasets)
    mapping["experiment"]["n_steps"] = setup.n_steps
    for c in mapping["experiment"]["conditions"]:
        if c["name"] == CONDITION:
            c["model"] = {**copy.deepcopy(c.get("model", {})), **copy.deepcopy(setup.model)}
    return load_config(mapping)


def recorded(cache: Path, kind: str, n: int, seed: int, k: int) -> tuple[Path, CaregiverDatasets]:
    """``n`` data sets of ``k`` identities from world seed ``seed``, from the cache or new."""
    world = load_config(PRESET).world
    path = cache / f"{kind}_seed{seed}_k{k}_n{n}.npz"
    if path.exists():
        try:
            ds = load(path)
        except DatasetError:
            ds = None
        if (ds is not None and len(ds) == n and (ds.n_caregivers or 1) == k
                and ds.meta.get("seed") == seed
                and ds.meta.get("world_config_toml") == world.to_toml()):
            print(f"cached   {path}", flush=True)
            return path, ds
    t0 = time.perf_counter()
    ds = make_datasets(world, n, seed, caregivers=k)
    save(ds, path)
    print(f"recorded {path} ({time.perf_counter() - t0:.1f} s)", flush=True)
    return path, ds


def identities(ds: CaregiverDatasets, seed: int) -> np.ndarray:
    """Each identity's head size and colours, one row per caregiver of ``ds``."""
    people = ds.meta.get("caregivers")
    if people is None:  # one caregiver: the world seed's own
        with World(load_config(PRESET).world, seed=seed) as world:
            people = [dataclasses.asdict(world.caregiver)]
    return np.array([[p["head_scale"], *p["skin_rgb"], *p["hair_rgb"], *p["shirt_rgb"]]
                     for p in people])


def check_distinct(train: np.ndarray, held: np.ndarray) -> float:
    """The least difference between a held-out and a training identity; refuse equal ones."""
    gap = float(np.min(np.abs(held[:, None, :] - train[None, :, :]).max(axis=2)))
    if gap < 1e-6:
        raise JointAttentionError("a held-out identity is also a training identity; expected "
                                  "another --held-out-seed")
    return gap


def learn(config: Config, seed_index: int) -> tuple[object, dict]:
    """Learn one cell; the agent at its end and the cell's records."""
    n_steps = config.experiment.n_steps
    got = {}
    records = run_cell(config, condition_named(config, CONDITION), seed_index,
                       checkpoints=[n_steps], on_checkpoint=lambda t, a: got.setdefault("a", a))
    if "a" not in got:
        raise JointAttentionError(f"the cell ended before {n_steps} learning steps")
    return got["a"], records


def measure(agent, ds: CaregiverDatasets) -> tuple[float, float]:
    """Median angle error (deg) and the fraction within WITHIN_DEG."""
    e = angle_errors(agent, ds)
    return float(np.median(e)), float(np.mean(e <= WITHIN_DEG))


def _plot(rows: list[dict], setups: list[Setup], path: Path) -> Path:
    fig = new_figure(7.6, 5.6)
    ax = fig.add_subplot()
    colours = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown")
    for i, setup in enumerate(setups):
        c = colours[i % len(colours)]
        mine = [r for r in rows if r["setup"] == setup.name and not r["control"]]
        ks = sorted({r["K"] for r in mine})
        med = [np.median([r["median_unseen_deg"] for r in mine if r["K"] == k]) for k in ks]
        ax.plot(ks, med, "-o", color=c, label=f"{setup.name}: {setup.changes}")
        ax.scatter([r["K"] for r in mine], [r["median_unseen_deg"] for r in mine], s=12,
                   color=c, alpha=0.4)
        ctrl = [r for r in rows if r["setup"] == setup.name and r["control"]]
        if ctrl:
            ax.scatter([1] * len(ctrl), [r["median_unseen_deg"] for r in ctrl], marker="s",
                       s=40, facecolors="none", edgecolors=c,
                       label=f"{setup.name}: 1 identity, {ctrl[0]['n_datasets']} data sets")
    ax.axhline(AIM_DEG, color="k", ls="--", lw=1, label=f"aim: {AIM_DEG:g}°")
    ax.set_xscale("log", base=2)
    ks = sorted({r["K"] for r in rows})
    ax.set_xticks(ks, [str(k) for k in ks])
    ax.set_ylim(0, max(60.0, max(r["median_unseen_deg"] for r in rows) + 5))
    ax.set_xlabel("caregiver identities learned from (K)")
    ax.set_ylabel("median angle error on unseen identities (°)")
    ax.set_title("Following caregivers never seen (lines: median over seeds; dots: seeds)",
                 fontsize=9)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2)
    return save_figure(fig, path)


def _table(rows: list[dict], setups: list[Setup], seeds: int) -> Table:
    columns = ["setup", "K", "data sets", "median error seen (seed 0)",
               "median error unseen (seed 0)", "within 20° unseen (seed 0)"]
    if seeds > 1:
        columns += [f"median error unseen, seeds 0-{seeds - 1}: median (min-max)",
                    f"seeds at most {AIM_DEG:g}° unseen"]
    out = []
    for setup in setups:
        mine = [r for r in rows if r["setup"] == setup.name]
        for key in dict.fromkeys((r["K"], r["control"]) for r in mine):
            group = [r for r in mine if (r["K"], r["control"]) == key]
            first = group[0]
            unseen = np.array([r["median_unseen_deg"] for r in group])
            row = [setup.name, f"{key[0]} (control)" if key[1] else key[0], first["n_datasets"],
                   f"{first['median_seen_deg']:.1f}°", f"{first['median_unseen_deg']:.1f}°",
                   f"{first['within20_unseen']:.2f}"]
            if seeds > 1:
                row += [f"{np.median(unseen):.1f}° ({unseen.min():.1f}-{unseen.max():.1f})",
                        f"{np.count_nonzero(unseen <= AIM_DEG)} of {len(unseen)}"]
            out.append(row)
    return Table(columns, out)


def _verdict(rows: list[dict], setups: list[Setup]) -> str:
    """Which setups and K reached the aim on unseen identities in every seed, in some, in none."""
    groups: dict[str, list[str]] = {"every": [], "some": []}
    for setup in setups:
        for k in sorted({r["K"] for r in rows if r["setup"] == setup.name and not r["control"]}):
            unseen = [r["median_unseen_deg"] for r in rows
                      if r["setup"] == setup.name and r["K"] == k and not r["control"]]
            hits = sum(u <= AIM_DEG for u in unseen)
            if hits:
                groups["every" if hits == len(unseen) else "some"].append(f"`{setup.name}` K = {k}")
    return (f"At most {AIM_DEG:g}° on unseen identities in every seed: "
            f"{', '.join(groups['every']) or 'none'}; in some seeds only: "
            f"{', '.join(groups['some']) or 'none'}; elsewhere in no seed.")


def main(argv: list[str] | None = None) -> int:
    """Record, learn, measure and write; 0 when done, 2 on a refused input."""
    argv = sys.argv[1:] if argv is None else argv
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, help="output folder (default: docs/results/caregivers; "
                                             "runs/caregivers-quick with --quick)")
    ap.add_argument("--cache", type=Path, default=Path("runs/caregivers/cache"),
                    help="folder of the recorded data sets (default: runs/caregivers/cache)")
    ap.add_argument("--ks", help='training identity counts (default: "1 2 4 8 16")')
    ap.add_argument("--held-out", type=int, help="held-out identities (default: 4)")
    ap.add_argument("--poses", type=int, help="data sets per identity (default: 125)")
    ap.add_argument("--seed", type=int, default=0, help="world seed of the training identities")
    ap.add_argument("--held-out-seed", type=int, default=1,
                    help="world seed of the held-out identities (default: 1)")
    ap.add_argument("--seeds", type=int, help="seed indices 0..SEEDS-1 of each cell (default: 3)")
    ap.add_argument("--n-steps", type=int,
                    help="learning time of setups that do not set it (default: the preset's)")
    ap.add_argument("--setup", action="append", metavar="NAME[:KEY=VALUE,...]",
                    help=f"a setup (repeat; default: {' and '.join(DEFAULT_SETUPS)})")
    ap.add_argument("--quick", action="store_true", help="a small run (tests)")
    args = ap.parse_args(argv)
    defaults = {"ks": "1 2 4 8 16", "poses": 125, "held_out": 4, "seeds": 3,
                "n_steps": load_config(PRESET).experiment.n_steps}
    for key, value in defaults.items():
        if getattr(args, key) is None:
            setattr(args, key, QUICK[key] if args.quick else value)
    out = args.out or Path("runs/caregivers-quick" if args.quick else "docs/results/caregivers")
    try:
        ks = sorted({int(k) for k in args.ks.split()})
    except ValueError:
        ap.error(f"--ks {args.ks!r}: expected integers")
    if not ks or ks[0] < 1 or ks[-1] > 1000:
        ap.error(f"--ks {args.ks!r}: expected identity counts in [1, 1000]")
    for name in ("held_out", "poses", "seeds", "n_steps"):
        if getattr(args, name) < 1:
            ap.error(f"--{name.replace('_', '-')} {getattr(args, name)}: expected at least 1")
    if args.held_out_seed == args.seed:
        ap.error("--held-out-seed: expected a world seed other than --seed (other people)")
    try:
        setups = [parse_setup(s, args.n_steps) for s in (args.setup or DEFAULT_SETUPS)]
    except argparse.ArgumentTypeError as err:
        ap.error(str(err))
    if args.quick:
        setups = [dataclasses.replace(s, n_steps=min(s.n_steps, args.n_steps)) for s in setups]
    if len({s.name for s in setups}) < len(setups):
        ap.error("--setup: expected distinct setup names")

    started = time.perf_counter()
    try:
        for setup in setups:  # refuse a bad setup before any work
            cell_config(setup, Path("check.npz"))
        _, held = recorded(args.cache, "heldout", args.held_out * args.poses,
                           args.held_out_seed, args.held_out)
        train = {k: recorded(args.cache, "train", k * args.poses, args.seed, k) for k in ks}
        control = None
        if ks[-1] > 1:
            control = recorded(args.cache, "train", ks[-1] * args.poses, args.seed, 1)
        gap = check_distinct(identities(train[ks[-1]][1], args.seed),
                             identities(held, args.held_out_seed))
        rows = []
        runs = [(k, False, *train[k]) for k in ks]
        if control is not None:
            runs.append((1, True, *control))
        for setup in setups:
            for k, is_control, path, ds in runs:
                config = cell_config(setup, path)
                for seed_index in range(args.seeds):
                    t0 = time.perf_counter()
                    agent, records = learn(config, seed_index)
                    seen, seen20 = measure(agent, ds)
                    unseen, unseen20 = measure(agent, held)
                    success = records["success"]
                    rows.append({
                        "setup": setup.name, "changes": setup.changes, "K": k,
                        "control": is_control, "n_datasets": len(ds),
                        "seed_index": seed_index, "median_seen_deg": seen,
                        "within20_seen": seen20, "median_unseen_deg": unseen,
                        "within20_unseen": unseen20,
                        "success_last_fifth": float(success[len(success) * 4 // 5:].mean()),
                        "cell_s": time.perf_counter() - t0})
                    print(f"{setup.name} K={k}{' (control)' if is_control else ''} "
                          f"n={len(ds)} seed {seed_index}: seen {seen:.1f}° unseen "
                          f"{unseen:.1f}° within 20° {unseen20:.2f} "
                          f"({rows[-1]['cell_s']:.0f} s)", flush=True)
    except JointAttentionError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    wall = time.perf_counter() - started

    out.mkdir(parents=True, exist_ok=True)
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=list(rows[0]), lineterminator="\n")
    writer.writeheader()
    writer.writerows({k: f"{v:.3f}" if isinstance(v, float) else v for k, v in r.items()}
                     for r in rows)
    write_text(out / "results.csv", buffer.getvalue())
    _plot(rows, setups, out / "unseen.png")
    command = shlex.join(["python", "scripts/caregivers.py", *argv])
    held_n = args.held_out * args.poses
    text = [
        "# Many caregivers: following a caregiver never seen", "",
        f"`{command}`: {wall / 60:.1f} min on this machine (recording and learning, one "
        "process).", "",
        f"Training: K caregiver identities from world seed {args.seed}, {args.poses} data sets "
        f"per identity (the data grow with K). Held out: {args.held_out} "
        f"{'identity' if args.held_out == 1 else 'identities'} from world "
        f"seed {args.held_out_seed}, {args.poses} data sets each ({held_n}), none of them a "
        f"training identity (least difference in head size or a colour channel: {gap:.3f}). "
        + (f"Control: one identity with {ks[-1] * args.poses} data sets, as many as K = "
           f"{ks[-1]}. " if control is not None else "")
        + f"Each cell: preset `{PRESET}`, condition `{CONDITION}`; setups: "
        + "; ".join(f"`{s.name}` ({s.changes})" for s in setups) + ".", "",
        "Error: the angle between the learning module's output at the face and the command to "
        f"the target (median over the data sets). Aim: at most {AIM_DEG:g}° on unseen "
        "identities. Per cell (seen, unseen, success over the last fifth of the trials, "
        "seconds): `results.csv`.", "",
        _table(rows, setups, args.seeds).to_markdown(),
        _verdict(rows, setups), "",
    ]
    write_text(out / "table.md", "\n".join(text))
    print(f"wrote {out / 'table.md'}, {out / 'results.csv'}, {out / 'unseen.png'} "
          f"({wall / 60:.1f} min)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
