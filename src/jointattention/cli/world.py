"""The command line's world commands: ``render`` and ``datasets``."""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from ..errors import JointAttentionError
from ._common import add_config, int_in
from .robot import add_import

__all__ = ["add_commands"]


def _cmd_render(args: argparse.Namespace) -> None:
    from ..config import load_config
    from ..figures.world import caregiver_sheet, face_sheet, robot_view
    from ..world.simulator import World

    config = load_config(args.config)
    seed = config.seed if args.seed is None else args.seed
    out = Path(args.out)
    d_th_px = config.agent.d_th_px(config.world.camera.width_px)
    with World(config.world, seed=seed) as world:
        print(robot_view(world, out / "robot_view.png", d_th_px))
        print(face_sheet(world, out / "face_windows.png"))
        if args.caregivers:
            print(caregiver_sheet(world, out / "identities.png", args.caregivers))


def _cmd_datasets_make(args: argparse.Namespace) -> None:
    from tqdm import tqdm

    from ..config import load_config
    from ..datasets import load, save
    from ..world.recording import HELD_OUT, caregivers_of, make_datasets

    config = load_config(args.config)
    if not args.out.endswith(".npz"):
        raise JointAttentionError(f"{args.out}: expected a file name ending in .npz")
    if args.caregivers > args.n:
        raise JointAttentionError(f"--caregivers {args.caregivers}: expected at most --n "
                                  f"({args.n}); each caregiver poses at least one data set")
    identities, stream = None, HELD_OUT if args.held_out else "world"
    if args.caregivers_of is not None:
        if args.caregivers != 1:
            raise JointAttentionError("--caregivers-of: the file's caregivers pose; expected no "
                                      "--caregivers")
        if (os.path.exists(args.out) and os.path.exists(args.caregivers_of)
                and os.path.samefile(args.out, args.caregivers_of)):
            raise JointAttentionError(f"OUT {args.out} conflicts with --caregivers-of "
                                      f"{args.caregivers_of}: the same file, which would be "
                                      "overwritten by its own new poses; expected another OUT")
        identities = caregivers_of(args.caregivers_of, config.world)
        recorded = load(args.caregivers_of).meta
        if recorded.get("seed") == args.seed and recorded.get("stream", "world") == stream:
            raise JointAttentionError(f"--caregivers-of {args.caregivers_of}: recorded with seed "
                                      f"{args.seed} in this stream, so these would be its poses "
                                      "again; expected another --seed (or --held-out)")
        if len(identities) > args.n:
            raise JointAttentionError(f"--caregivers-of {args.caregivers_of}: "
                                      f"{len(identities)} caregivers; expected at most --n "
                                      f"({args.n}); each poses at least one data set")
    with tqdm(total=args.n, desc="data sets", unit="set", disable=args.quiet) as bar:
        ds = make_datasets(config.world, args.n, args.seed, progress=lambda i: bar.update(1),
                           caregivers=args.caregivers, cut=args.cut,
                           stream=stream, identities=identities)
    print(save(ds, args.out))


def _cmd_datasets_check(args: argparse.Namespace) -> None:
    import numpy as np

    from ..datasets import default_datasets, load

    ds = default_datasets() if args.file is None else load(args.file)
    w, h = ds.window_size_px
    cmd = np.rad2deg(ds.command_rad)
    print(
        f"{args.file or 'shipped default'}: {len(ds)} data sets, face windows {w}x{h}, "
        f"commands pan [{cmd[:, 0].min():.1f}, {cmd[:, 0].max():.1f}] deg, "
        f"tilt [{cmd[:, 1].min():.1f}, {cmd[:, 1].max():.1f}] deg, "
        f"target positions {'present' if ds.target_m is not None else 'absent'}"
        + ("" if ds.caregiver is None else f", {ds.n_caregivers} caregivers")
        + ("" if ds.eyes is None else f", eye windows {ds.eyes.shape[2]}x{ds.eyes.shape[1]}")
    )


def add_commands(sub) -> None:
    """Register ``render`` and ``datasets`` on the subparsers ``sub``."""
    p = sub.add_parser(
        "render", help="PNGs of the robot's view and of face windows",
        description="Write robot_view.png (the room, the robot looking at the caregiver and at "
                    "its target) and face_windows.png (face windows across gaze directions) "
                    "into --out.")
    add_config(p)
    p.add_argument("--seed", type=int_in(0, 2**63 - 1),
                   help="world seed (default: the configuration's)")
    p.add_argument("--out", default="runs/render", help="output folder (default: runs/render)")
    p.add_argument("--caregivers", type=int_in(0, 1000), default=0, metavar="K",
                   help="also write identities.png: the faces of K caregivers of the world, "
                        "one new scene each (default: 0, none)")
    p.set_defaults(func=_cmd_render, out_kind="folder")

    p = sub.add_parser("datasets", help="make or check caregiver data sets",
                       description="Caregiver data sets in the paper's protocol.")
    dsub = p.add_subparsers(dest="action", required=True, metavar="ACTION")
    q = dsub.add_parser(
        "make", help="record N data sets from the simulated world",
        description="Record N data sets (face window, head angle, command to the target, "
                    "target position) into OUT (.npz), posed by --caregivers people.")
    add_config(q)
    q.add_argument("--n", type=int_in(1, 100_000), default=125,
                   help="number of data sets (default: 125)")
    q.add_argument("--seed", type=int_in(0, 2**63 - 1), default=0,
                   help="world seed (default: 0)")
    q.add_argument("--caregivers", type=int_in(1, 1000), default=1, metavar="K",
                   help="caregiver identities, the N data sets split evenly among them in turn: "
                        "the seed's own, then new ones drawn by the world; with more than one the "
                        "file names each set's caregiver (schema version 2) (default: 1)")
    q.add_argument("--cut", choices=("box", "finder"), default="box",
                   help="where face windows are cut: around the head's projection (default, "
                        "the experimenter's knowledge) or around the face the robot's own "
                        "finder finds, as follow and datasets import cut them")
    q.add_argument("--held-out", action="store_true",
                   help="record from the held-out stream, which no training world draws from: "
                        "its caregivers and poses are none of those recorded without the flag, "
                        "for every seed")
    q.add_argument("--caregivers-of", metavar="FILE",
                   help="new poses of the caregivers of FILE (a data-set file recorded here, in "
                        "the same world configuration, with another seed or stream): the N data "
                        "sets split evenly among them")
    q.add_argument("--quiet", action="store_true", help="no progress bar")
    q.add_argument("out", metavar="OUT", help="output file, ending in .npz")
    q.set_defaults(func=_cmd_datasets_make, out_kind="file", out_what="OUT")
    q = dsub.add_parser("check", help="validate a data-set file and summarise it",
                        description="Validate FILE (default: the shipped data sets).")
    q.add_argument("file", metavar="FILE", nargs="?", help="a data-set .npz file")
    q.set_defaults(func=_cmd_datasets_check)
    add_import(dsub)  # datasets import: with the robot commands
