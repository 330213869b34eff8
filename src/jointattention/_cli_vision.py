"""The command line's vision commands: ``parity`` and ``detect``."""

from __future__ import annotations

import argparse
from pathlib import Path

__all__ = ["add_commands"]


def _cmd_parity(args: argparse.Namespace) -> None:
    from tqdm import tqdm

    from .config import load_config, with_n_objects
    from .parity import CAUSES, measure_parity

    config = load_config(args.config)
    lines = ["| objects | cases | agree | same choice | centres within 2 px | median error px "
             "| 99th pct px | max px | disagreements by cause |", "|---" * 9 + "|"]
    for n in args.objects:
        with tqdm(total=args.cases, desc=f"{n} objects", unit="case") as bar:
            r = measure_parity(with_n_objects(config, n), args.cases, seed=args.seed,
                               progress=lambda _: bar.update(1))
        s = r.summary()
        causes = ", ".join(f"{k} {v}" for k, v in sorted(s["causes"].items())) or "none"
        lines.append(f"| {n} | {s['cases']} | {s['agree']:.3f} | {s['same_choice']:.3f} | "
                     f"{s['centres_within_tol']:.3f} | {s['error_px_median']:.2f} | "
                     f"{s['error_px_p99']:.2f} | {s['error_px_max']:.2f} | {causes} |")
    lines += ["", "Causes: " + "; ".join(f"{k}: {v}" for k, v in CAUSES.items()) + "."]
    text = "\n".join(lines) + "\n"
    print(text, end="")
    if args.out:
        from .io import atomic_path

        with atomic_path(Path(args.out)) as tmp:
            tmp.write_text(text)


def _cmd_detect(args: argparse.Namespace) -> None:
    from .config import load_config
    from .overlay import detect_files

    config = load_config(args.config)
    for path, found in detect_files(args.images, Path(args.out), config, args.face):
        print(f"{path}: {len(found.area_px)} bright-colour regions, {len(found.faces)} faces, "
              f"{len(found.edge_regions)} edge-rich regions")


def add_commands(sub, add_config) -> None:
    """Register ``parity`` and ``detect`` on the subparsers ``sub``."""
    p = sub.add_parser(
        "parity", help="how often the OpenCV and fast detectors agree in rendered scenes",
        description="Render random scenes from random head angles and compare the image "
                    "detector with the fast projection: the same most interesting object "
                    "(Eq. 1) and centres within 2 px; print a Markdown table with the causes "
                    "of disagreements.")
    add_config(p)
    p.add_argument("--cases", type=int, default=1000, help="scenes per object count "
                                                           "(default: 1000)")
    p.add_argument("--objects", type=int, nargs="+", default=[5, 10],
                   help="object counts (default: 5 10)")
    p.add_argument("--seed", type=int, default=0, help="seed of the scenes (default: 0)")
    p.add_argument("--out", help="also write the table to this Markdown file")
    p.set_defaults(func=_cmd_parity)

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
    p.set_defaults(func=_cmd_detect)
