"""The command line's vision commands: ``parity``, ``detect`` and ``gaze``."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .._files import write_text
from ..errors import ArgumentError
from ..world import gl
from ._common import add_cell, add_config, int_in

__all__ = ["add_commands"]


def _cmd_parity(args: argparse.Namespace) -> None:
    from tqdm import tqdm

    from ..config import load_config
    from ..jobs.parity import CAUSES, measure_parity, parity_table

    config = load_config(args.config)
    gl.mujoco()  # rendering: refused before the progress bar if OpenGL cannot start
    results = {}
    for n in args.objects:
        with tqdm(total=args.cases, desc=f"{n} objects", unit="case") as bar:
            results[n] = measure_parity(config, args.cases, seed=args.seed, n_objects=n,
                                        progress=lambda _: bar.update(1))
    causes = "; ".join(f"{k}: {v}" for k, v in CAUSES.items())
    text = parity_table(results).to_markdown() + f"\nCauses: {causes}.\n"
    print(text, end="")
    if args.out:
        write_text(args.out, text)


def _cmd_detect(args: argparse.Namespace) -> None:
    from ..config import load_config
    from ..figures.detect import detect_files

    config = load_config(args.config)
    for path, found in detect_files(args.images, Path(args.out), config, args.face):
        print(f"{path}: {len(found.area_px)} bright-colour regions, {len(found.faces)} faces, "
              f"{len(found.edge_regions)} edge-rich regions")


def _cmd_gaze(args: argparse.Namespace) -> None:
    from tqdm import tqdm

    from ..config import condition_named, load_config
    from ..experiment.cells import datasets_of
    from ..experiment.preflight import check_memory
    from ..jobs.learned import write_gaze_figures

    config = load_config(args.preset if args.config is None else args.config)
    condition_named(config, args.condition)  # all checked before the progress bar
    datasets_of(config)
    check_memory(config, [args.condition])
    gl.mujoco()  # Fig. 7 is rendered: refused before learning if OpenGL cannot start
    with tqdm(total=config.experiment.n_steps, desc="learning", unit="step") as bar:
        numbers = write_gaze_figures(config, args.condition, args.seed_index, Path(args.out),
                                     progress=lambda t: bar.update(t - bar.n))
    errors = numbers["median_error_deg"]
    before, after = errors["0"], errors[str(config.experiment.n_steps)]
    print(f"median angle error, data sets: {before['data_sets']:.1f} -> "
          f"{after['data_sets']:.1f} deg; held-out poses: {before['held_out']:.1f} -> "
          f"{after['held_out']:.1f} deg")
    for name in ("fig6.png", "lm_error.png", "fig7.png", "fig7.gif", "gaze.json"):
        print(Path(args.out) / name)


def _cmd_faces(args: argparse.Namespace) -> None:
    from tqdm import tqdm

    from ..config import load_config
    from ..jobs import face_finders as ff

    config = load_config(args.config).world
    if args.caregivers > args.n:
        raise ArgumentError(f"faces: --caregivers {args.caregivers} is more than --n {args.n}; "
                            "expected at most one caregiver per view")
    gl.mujoco()

    bars = []

    def status(line: str) -> None:
        for bar in bars:
            bar.close()  # a status line never lands inside the bar
        print(line, file=sys.stderr, flush=True)

    status("rendering the template finder's training views")
    template = ff.template_of(config)
    chosen = ff.finders(template)
    with tqdm(total=args.n, desc="views", unit="view") as bar:
        bars.append(bar)
        rendered = ff.rendered_scores(config, args.n, args.caregivers, args.seed, chosen,
                                      progress=lambda i: bar.update(i - bar.n), status=status)
    command = (f"jointattention faces --config {args.config} --n {args.n} "
               f"--caregivers {args.caregivers} --seed {args.seed}")
    status("every finder on the photographs scikit-image ships (if installed)")
    text = ff.finders_table(rendered, ff.photo_scores(chosen), command)
    print(text, end="")
    if args.out:
        write_text(args.out, text)


def add_commands(sub) -> None:
    """Register ``parity``, ``detect``, ``faces`` and ``gaze`` on the subparsers ``sub``."""
    p = sub.add_parser(
        "parity", help="how often the OpenCV and fast detectors agree in rendered scenes",
        description="Render random scenes from random head angles and compare the image "
                    "detector with the fast projection: the same most interesting object "
                    "(Eq. 1) and centres within 2 px; print a Markdown table with the causes "
                    "of disagreements.")
    add_config(p)
    p.add_argument("--cases", type=int_in(1, 10**6), default=1000,
                   help="scenes per object count (default: 1000)")
    p.add_argument("--objects", type=int_in(1, 20), nargs="+", default=[5, 10],
                   help="object counts (default: 5 10)")
    p.add_argument("--seed", type=int_in(0, 2**63 - 1), default=0,
                   help="seed of the scenes (default: 0)")
    p.add_argument("--out", help="also write the table to this Markdown file")
    p.set_defaults(func=_cmd_parity, out_kind="file")

    p = sub.add_parser(
        "detect", help="draw what the robot's detectors find on photographs",
        description="For each IMAGE write OUT/<name>_detected.png: bright-colour regions "
                    "(the most interesting by Eq. 1 in yellow), faces and edge-rich regions.")
    p.add_argument("images", metavar="IMAGE", nargs="+", type=Path, help="PNG, JPEG, ...")
    add_config(p)
    p.add_argument("--face", choices=("haar", "template"), default="haar",
                   help="face finder: OpenCV's Haar cascade (default, for people) or the "
                        "template of the shipped data sets' caregiver (for the simulation)")
    p.add_argument("--out", default="runs/detect", help="output folder (default: runs/detect)")
    p.set_defaults(func=_cmd_detect, out_kind="folder")

    p = sub.add_parser(
        "faces", help="compare the face finders on rendered faces and photographs",
        description="Render views of many held-out caregivers and run every face finder on "
                    "them (BlazeFace, the template, Haar cascades, libfacedetection if "
                    "installed), then on the photographs scikit-image ships; print recall, "
                    "precision, the centre error and frames per second at 640x480.")
    p.add_argument("--config", default="many-caregivers", metavar="PRESET|FILE.toml",
                   help="the world's preset or TOML file (default: many-caregivers)")
    p.add_argument("--n", type=int_in(1, 10**6), default=2000, help="views (default: 2000)")
    p.add_argument("--caregivers", type=int_in(1, 10**6), default=64,
                   help="caregivers, in turn (default: 64)")
    p.add_argument("--seed", type=int_in(0, 2**63 - 1), default=0,
                   help="seed of the held-out views (default: 0)")
    p.add_argument("--out", help="also write the table to this Markdown file")
    p.set_defaults(func=_cmd_faces, out_kind="file")

    p = sub.add_parser(
        "gaze", help="the paper's Fig. 6 and Fig. 7: what the learning module learned",
        description="Learn one cell (fast mode), then write into --out: fig6.png (the "
                    "module's output on face windows over a grid of gaze directions, some "
                    "unseen in the data sets), lm_error.png (median angle to the target on the "
                    "data sets and on held-out poses, over learning time), fig7.png and "
                    "fig7.gif (one rendered trial after learning) and gaze.json.")
    add_cell(p)
    p.add_argument("--out", default="runs/gaze", help="output folder (default: runs/gaze)")
    p.set_defaults(func=_cmd_gaze, out_kind="folder")
