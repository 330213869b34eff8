"""The command line's robot commands: train, follow, closed-loop and datasets import."""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

from ..agent.finders import DEFAULT_FACE, FACE_METHODS
from ..errors import ArgumentError, FileError
from ._common import LazyBar, add_cell, add_config, int_in

__all__ = ["add_commands", "add_import"]

MAX_FRAMES = 10**7


def _cmd_train(args: argparse.Namespace) -> None:
    import numpy as np
    from tqdm import tqdm

    from ..config import load_config
    from ..deploy.saved import check_savable
    from ..experiment.cells import datasets_of
    from ..experiment.preflight import check_memory
    from ..experiment.probes import angle_errors
    from ..experiment.training import train

    config = load_config(args.preset if args.config is None else args.config)
    check_savable(config, args.condition)
    if not args.out.endswith(".npz"):
        raise FileError(f"{args.out}: expected a model file name ending in .npz")
    ds = datasets_of(config)  # a bad data-set file is refused before learning
    check_memory(config, [args.condition])  # an in-range capacity may not fit this machine
    with tqdm(total=config.experiment.n_steps, desc="learning", unit="step",
              disable=args.quiet) as bar:
        model = train(config, args.condition, args.seed_index,
                      progress=lambda t: bar.update(t - bar.n))
    errors = angle_errors(model.agent, ds)
    print(f"median angle error on the {len(ds)} data sets learned from: "
          f"{float(np.median(errors)):.1f} deg")
    print(model.save(args.out))


def _theta(text: str):
    parts = text.split(",")
    try:
        values = [float(v) for v in parts]
    except ValueError:
        values = []
    if len(values) != 2 or not all(math.isfinite(v) for v in values):
        raise argparse.ArgumentTypeError(f"{text!r}: expected PAN,TILT in degrees, e.g. 0,-10")
    return values


def _frames(args: argparse.Namespace):
    """(source name, frame index, RGB frame) of the images, the video or the camera."""
    from .._readers import MAX_IMAGE_PIXELS, quiet_stderr, read_image

    if args.images:
        images = [(p, read_image(p)) for p in args.images]  # all read before any is written
        for path, image in images:
            yield path.stem, None, image
        return
    import cv2

    source = args.camera if args.video is None else str(args.video)
    if args.video is not None and not Path(args.video).is_file():
        raise FileError(f"{args.video}: not a file; expected a video file OpenCV can read")
    with quiet_stderr():  # OpenCV and FFmpeg print their own lines on a failed open
        capture = cv2.VideoCapture(source)
    try:
        if not capture.isOpened():
            what = f"camera {args.camera}" if args.video is None else str(args.video)
            raise FileError(f"{what}: OpenCV could not open it; expected a video file or a "
                            "camera index OpenCV can read")
        w, h = (int(capture.get(p)) for p in (cv2.CAP_PROP_FRAME_WIDTH, cv2.CAP_PROP_FRAME_HEIGHT))
        if w * h > MAX_IMAGE_PIXELS:
            raise FileError(f"{source}: frames of {w}x{h} pixels; expected at most "
                            f"{MAX_IMAGE_PIXELS:,} pixels a frame")
        name = f"camera{args.camera}" if args.video is None else Path(args.video).stem
        for i in range(args.max_frames):
            with quiet_stderr():  # FFmpeg's lines about a damaged stream
                ok, bgr = capture.read()
            if not ok:
                if i == 0:
                    raise FileError(f"{source}: no frame could be read; expected a video")
                break
            yield name, i, cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB)
    finally:
        capture.release()


def _cmd_follow(args: argparse.Namespace) -> None:
    import cv2
    import numpy as np

    from .._files import atomic_path
    from ..deploy.follower import GazeFollower
    from ..deploy.overlay import draw_look

    if sum(x is not None and x != [] for x in (args.images, args.video, args.camera)) != 1:
        raise ArgumentError("follow: expected IMAGE files, --video FILE or --camera N (one "
                            "of them)")
    if args.landmarks_only and args.face != "blazeface":  # the others have no landmarks
        raise ArgumentError(f"--landmarks-only conflicts with --face {args.face}: it places "
                            "BlazeFace's window; expected --face blazeface, or no "
                            "--landmarks-only")
    follower = GazeFollower.load(args.model, face=args.face, min_score=args.min_score,
                                 refine=not args.landmarks_only)
    theta = np.deg2rad(args.theta_deg)
    follower.check_angle(theta)  # before any frame is read
    out = Path(args.out) if args.out else None
    for name, index, frame in _frames(args):
        look = follower.look(frame, theta)
        record = {"source": name, "frame": index, "theta_deg": list(args.theta_deg),
                  "face": None, "command_deg": None}
        if look is not None:
            record["face"] = {"centre_px": [round(float(v), 1) for v in look.face.centre_px],
                              "height_px": round(look.face.height_px, 1),
                              "box_px": [int(v) for v in look.face.box_px],
                              "score": round(look.face.score, 3)}
            record["command_deg"] = [round(float(v), 3) for v in np.rad2deg(look.command_rad)]
        if out is not None:
            stem = name if index is None else f"{name}_{index:05d}"
            target = out / f"{stem}_follow.png"
            _, png = cv2.imencode(".png", cv2.cvtColor(draw_look(frame, look),
                                                       cv2.COLOR_RGB2BGR))
            with atomic_path(target) as tmp:
                tmp.write_bytes(png.tobytes())
            record["overlay"] = str(target)
        print(json.dumps(record), flush=True)


def _cmd_datasets_import(args: argparse.Namespace) -> None:
    from ..config import load_config
    from ..datasets import load, save
    from ..head_recording import import_recording

    config = load_config(args.config)
    if not args.out.endswith(".npz"):
        raise FileError(f"{args.out}: expected a file name ending in .npz")
    template = None
    if args.template is not None:
        from ..agent.faces import face_template

        template = face_template(load(args.template).face)
    fw = config.world.face_window
    # drawn at the first image: a missing folder or a bad table is refused with no bar
    with LazyBar(desc="images", unit="image", disable=args.quiet) as bar:
        ds, missed = import_recording(args.folder, face=args.face, template=template,
                                      face_size_px=(fw.width_px, fw.height_px),
                                      min_score=(config.detector.face_min_score
                                                 if args.face == "template" else None),
                                      progress=bar.update_to)
    for m in missed:
        print(f"jointattention: warning: row {m.row} ({m.image}): no face found; left out",
              file=sys.stderr)
    print(f"{len(ds)} of {len(ds) + len(missed)} rows imported; {len(missed)} without a face")
    print(save(ds, args.out))


def add_import(dsub) -> None:
    """Register ``datasets import`` on the ``datasets`` subparsers."""
    q = dsub.add_parser(
        "import", help="data sets from a folder of recorded camera images",
        description="Read FOLDER/recording.csv (columns image, pan_rad, tilt_rad, "
                    "command_pan_rad, command_tilt_rad; optionally target_x_m, target_y_m, "
                    "target_z_m) and its images; find the caregiver's face in each, cut its "
                    "window and write the data sets to --out. Rows whose face is not found "
                    "are listed and left out (docs/real-head.md).")
    q.add_argument("folder", metavar="FOLDER", type=Path, help="the recording folder")
    add_config(q)
    q.add_argument("--face", choices=FACE_METHODS, default=DEFAULT_FACE,
                   help="face finder: BlazeFace (default: the shipped neural detector, "
                        "docs/results/faces/detectors.md), a template (the shipped data sets' mean "
                        "face) or OpenCV's Haar cascade")
    q.add_argument("--template", metavar="DATASETS.npz",
                   help="with --face template: the mean face of these data sets as the template")
    q.add_argument("--out", required=True, help="output data-set file, ending in .npz")
    q.add_argument("--quiet", action="store_true", help="no progress bar")
    q.set_defaults(func=_cmd_datasets_import, out_kind="file")


def add_commands(sub) -> None:
    """Register ``train`` and ``follow`` on the subparsers ``sub``."""
    p = sub.add_parser(
        "train", help="learn one cell and save the learned model",
        description="Learn one condition x seed (the fast world) and save the learned model "
                    "(weights, face statistics, robot, configuration; no pickle) to --out.")
    add_cell(p)
    p.add_argument("--out", required=True, help="the model file, ending in .npz")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_train, out_kind="file")

    p = sub.add_parser(
        "follow", help="apply a saved model to camera images: where to look",
        description="For each frame: find the caregiver's face, cut its window, and print the "
                    "learning module's command as a JSON line (command_deg: pan, tilt; null "
                    "if no face was found); with --out write the frame with the face window "
                    "and the command's line drawn (<name>_follow.png).")
    p.add_argument("model", metavar="MODEL", type=Path, help="a model file (train --out)")
    p.add_argument("images", metavar="IMAGE", nargs="*", type=Path, help="PNG, JPEG, ...")
    p.add_argument("--video", type=Path, help="a video file instead of images")
    p.add_argument("--camera", type=int_in(0, 1000), help="a camera index (OpenCV) instead")
    p.add_argument("--max-frames", type=int_in(1, MAX_FRAMES), default=1000,
                   help="with --video or --camera: at most this many frames (default: 1000)")
    p.add_argument("--theta-deg", "--theta", type=_theta, default=[0.0, 0.0],
                   metavar="PAN,TILT", help="the head angle of the frames, degrees "
                                            "(default: 0,0)")
    p.add_argument("--face", choices=FACE_METHODS, default=DEFAULT_FACE,
                   help="face finder: BlazeFace (default: the shipped neural detector, "
                        "docs/results/faces/detectors.md), the model's mean face (template) or "
                        "OpenCV's Haar cascade")
    p.add_argument("--min-score", type=float, metavar="S",
                   help="least score of a face (default: the finder's own; BlazeFace's 0.4 "
                        "suits the simulated caregivers, 0.6 photographs of people)")
    p.add_argument("--landmarks-only", action="store_true",
                   help="place BlazeFace's window by its landmarks alone, without the pixel "
                        "refinements learned on the simulated heads (for photographs of people)")
    p.add_argument("--out", help="folder for the overlay images (default: none written)")
    p.set_defaults(func=_cmd_follow, out_kind="folder")
