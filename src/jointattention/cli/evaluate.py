"""The command line's ``evaluate`` and ``closed-loop``: a saved model, frozen, measured.

``evaluate`` runs it on held-out data sets in the fast world; ``closed-loop`` drives the
rendered head with it through images alone.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

from ..agent.finders import DEFAULT_FACE, FACE_METHODS
from ..errors import ArgumentError
from ._common import LazyBar, int_in

__all__ = ["add_commands"]

COLUMNS = ("name", "n_sets", "n_identities", "n_objects", "n_trials", "success", "ceiling",
           "fraction_of_ceiling", "median_error_deg", "p90_error_deg",
           "share_identities_over_10deg", "novelty_median", "novelty_max")
POSES = 25  # evaluate --caregivers: data sets per caregiver, by default


def _number(value):
    """A JSON-safe value: NaN as null."""
    return None if isinstance(value, float) and not math.isfinite(value) else value


def _cmd_evaluate(args: argparse.Namespace) -> None:
    from ..datasets import load
    from ..deploy.saved import load_model
    from ..experiment.evaluate import evaluate_agent, learned_from

    if (args.datasets is None) == (args.caregivers is None):
        raise ArgumentError("expected either --datasets FILE or --caregivers K (with --seed S): "
                            "the held-out data sets to measure the model on")
    if args.poses is not None and args.caregivers is None:  # it would be ignored
        raise ArgumentError(f"--poses {args.poses} conflicts with --datasets: it is the data "
                            "sets recorded per caregiver; expected it with --caregivers K")
    out = None if args.out is None else Path(args.out)
    model = load_model(args.model)
    known = learned_from(model, str(args.model))
    if args.datasets is not None:
        ds, name = load(args.datasets), Path(args.datasets).name
    else:
        from tqdm import tqdm

        from ..experiment.held_out import held_out_datasets

        poses = POSES if args.poses is None else args.poses
        with tqdm(total=args.caregivers * poses, desc="recording held-out data sets",
                  unit="set", disable=args.quiet or args.json) as bar:
            ds = held_out_datasets(model.config.world, args.caregivers, poses, args.seed,
                                   progress=lambda i: bar.update(1))
        name = f"{args.caregivers} unseen caregivers (held-out seed {args.seed})"
    result = evaluate_agent(model.agent, ds, model.config, name=name, n_objects=args.objects,
                            n_trials=args.trials, seed=args.seed,
                            known=known).as_dict()
    row = {k: _number(result[k]) for k in COLUMNS}
    if out is not None:
        from .._files import save_json, write_text

        save_json(row, out / "evaluation.json")
        write_text(out / "evaluation.csv", ",".join(COLUMNS) + "\n" + ",".join(
            "" if row[k] is None else str(row[k]) for k in COLUMNS) + "\n")
    if args.json:
        print(json.dumps(row))
        return
    print(f"{args.model} on {name}: {row['n_sets']} data sets, {row['n_identities']} "
          f"caregivers, {row['n_objects']} objects, {row['n_trials']} trials")
    print(f"  success {row['success']:.3f} of a ceiling of {row['ceiling']:.3f}: "
          f"{row['fraction_of_ceiling']:.2f} of the ceiling")
    if row["median_error_deg"] is not None:
        print(f"  angle error at the face: median {row['median_error_deg']:.1f} deg, 90th "
              f"percentile {row['p90_error_deg']:.1f} deg; identities above 10 deg: "
              f"{row['share_identities_over_10deg']:.2f}")
    if row["novelty_median"] is not None:
        print(f"  how new its caregivers are: median {row['novelty_median']:.2f}, largest "
              f"{row['novelty_max']:.2f} times the spacing of the caregivers it learned from")
    if out is not None:
        print(out / "evaluation.json")


def _cmd_closed_loop(args: argparse.Namespace) -> None:
    import time

    from tqdm import tqdm

    from .._files import write_text
    from ..deploy.saved import load_model
    from ..experiment.training import model_datasets
    from ..jobs.closed_loop import TABLE_HEAD, closed_loop
    from ..world import gl

    model = load_model(args.model)
    if args.datasets is None:  # the model's own, by content; recorded once per machine
        r = model.config.recording
        with tqdm(total=r.caregivers * r.poses_per_caregiver, unit="set", delay=1,
                  desc="recording the model's training sets (once on this machine)") as bar:
            datasets = model_datasets(model, args.model, progress=lambda i: bar.update(1))
    else:
        from ..datasets import load
        from ..jobs.closed_loop import caregivers_shown, check_windows

        datasets = load(args.datasets)
        check_windows(datasets, model, f"--datasets {args.datasets}")  # before any bar
        caregivers_shown(datasets, model.config.world)  # who posed them, before rendering
    gl.mujoco()  # rendered: refused before any trial if OpenGL cannot start
    rows = list(TABLE_HEAD)
    start = time.perf_counter()
    for n in args.objects:
        # drawn at the first trial: a refusal before it (e.g. OpenGL) shows no bar
        with LazyBar(total=args.trials, desc=f"{n} objects", unit="trial") as bar:
            r = closed_loop(model, n, args.trials, seed=args.seed, face=args.face,
                            progress=bar.update_to, datasets=datasets)
        rows.append(r.row())
    where = ("its own data sets" if args.datasets is None else
             f"the data sets of {args.datasets}")
    text = "\n".join(rows) + (f"\n\nSuccess of {args.model} on {where} (face finder {args.face}; "
                              f"learning time {model.agent.learning_time_steps:,} steps), "
                              f"{(time.perf_counter() - start) / 60:.1f} min.\n")
    text += _held_out_lines(model.held_out)
    print(text, end="")
    if args.out:
        write_text(args.out, text)


def _held_out_lines(held_out: dict | None) -> str:
    """What a model file says of its model on held-out sets at the end of its learning."""
    if not held_out:
        return "The model file holds no held-out measures (learned before version 0.3).\n"
    lines = ["The model when it was learned, frozen, in the fast world (its held-out measures):"]
    for kind, m in held_out.items():
        error = m.get("median_error_deg")
        lines.append(f"- {kind}: success {m.get('success', float('nan')):.3f}"
                     + ("" if error is None else f", median angle error {error:.1f}°"))
    return "\n".join(lines) + "\n"


def add_commands(sub) -> None:
    """Register ``evaluate`` and ``closed-loop`` on the subparsers ``sub``."""
    p = sub.add_parser(
        "evaluate", help="a saved model, frozen, on held-out data sets",
        description="Run a saved model, frozen (it learns nothing), on held-out data sets in "
                    "the fast world with the trial rules of learning: its success, that set's "
                    "oracle ceiling and the fraction of it, and the learning module's angle "
                    "error at the faces (median, 90th percentile, share of identities whose "
                    "median is above 10 deg), and how new the caregivers are (each one's "
                    "distance to the nearest the model learned from, over their spacing).")
    p.add_argument("model", metavar="MODEL", type=Path, help="a model file (train --out)")
    p.add_argument("--datasets", metavar="FILE", help="held-out data sets (.npz)")
    p.add_argument("--caregivers", type=int_in(1, 1000), metavar="K",
                   help="instead: record K caregivers from the held-out stream (one no "
                        "training recording uses) in the model's world, with rendering")
    p.add_argument("--poses", type=int_in(1, 10_000),
                   help=f"with --caregivers: data sets per caregiver (default: {POSES})")
    p.add_argument("--seed", type=int_in(0, 2**63 - 1), default=0,
                   help="seed of the held-out recording and of the trials (default: 0)")
    p.add_argument("--objects", type=int_in(1, 20), default=5,
                   help="objects per trial, the target among them (default: 5)")
    p.add_argument("--trials", type=int_in(1, 10**6), default=2000,
                   help="trials of the model and of the oracle (default: 2000)")
    p.add_argument("--out", help="folder for evaluation.csv and evaluation.json")
    p.add_argument("--json", action="store_true", help="print one JSON object instead")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_evaluate, out_kind="folder")

    p = sub.add_parser(
        "closed-loop", help="a saved model driving the rendered head through images alone",
        description="For each object count: trials in the rendered world where the face is "
                    "found in the first image, its window cut, and the learning module moves "
                    "the head while OpenCV detects and the evaluator (Eq. 3) ends the trial; "
                    "the same trials with the window cut around the head's projection in the "
                    "same first image (the experimenter's box), with the data set's window, "
                    "and in the fast world. "
                    "Prints a Markdown table of success, and the median angle between the "
                    "module's first command and the direction to the target with each window.")
    p.add_argument("model", metavar="MODEL", type=Path, help="a model file (train --out)")
    p.add_argument("--objects", type=int_in(1, 20), nargs="+", default=[1, 3, 5, 10],
                   help="object counts (default: 1 3 5 10)")
    p.add_argument("--trials", type=int_in(1, 10**6), default=200,
                   help="trials per object count (default: 200)")
    p.add_argument("--seed", type=int_in(0, 2**63 - 1), default=0,
                   help="seed of the trials (default: 0)")
    p.add_argument("--face", choices=FACE_METHODS, default=DEFAULT_FACE,
                   help="face finder (default: blazeface; template: the model's mean face)")
    p.add_argument("--datasets", metavar="FILE",
                   help="trials from these data sets of the model's world, their caregivers "
                        "rendered (e.g. unseen ones: datasets make --held-out); default: the "
                        "model's own")
    p.add_argument("--out", help="also write the table to this Markdown file")
    p.set_defaults(func=_cmd_closed_loop, out_kind="file")
