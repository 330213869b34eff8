"""What the face features allow when the true direction is taught: the learner's own bound.

Usage::

    python docs/results/people/taught_bound.py [--epochs 12]
        [--out docs/results/people/taught_bound.md]

The bootstrap learners teach themselves from their evaluator, which with many objects mostly
finds distractors. Here the same network (:class:`jointattention.models.population.code.
PopulationCode`, the population learner's defaults, the mode read out) is taught the true
direction from each face to its caregiver's target instead, over ``epochs`` passes of a
run's training sets, and reads the directions of 32 unseen caregivers x 25 poses (held-out
seed 5151). Rows: the generalise preset's world (the default world, 128 caregivers), the
many-caregivers world of ``docs/results/generalise/wide.toml`` (256 caregivers), the people
preset's (256 caregivers), the people world with the 60x50 face window of
``docs/results/people/window.toml``, and the people world with an eye window
(``[world.eye_window]`` of 96 x 24 pixels from a fovea 4 times finer than the camera:
docs/world.md), placed exactly and with an eye finder's error, whose features
(:mod:`jointattention.models.population.features`, as the face window's) are added to the
input; last, the socket patches of ``docs/results/people/sockets.toml`` (a wider window placed
with an error of 0.1 eye distances, and a patch cut around each socket the robot finds), the
sockets found by the drawn-eye bank and then by the eye-socket network
(``socket_finder = "net"``, :mod:`jointattention.agent.socket_net`).
Writes the median and 90th-percentile angle errors.
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from pathlib import Path

import numpy as np

from jointattention._files import write_text
from jointattention.config import load_config
from jointattention.experiment.cells import datasets_of
from jointattention.experiment.held_out import held_out_datasets
from jointattention.models.population.code import PopulationCode
from jointattention.models.population.features import face_features
from jointattention.models.population.options import PopulationOptions
from jointattention.world.options import EyeWindowConfig

SEED, N_CAREGIVERS, N_POSES = 5151, 32, 25
EYES = {"width_px": 96, "height_px": 24, "zoom": 4.0}  # the eye window of the last rows
SOCKETS = dataclasses.asdict(  # the eye window of the last row, as that run keeps it
    load_config(str(Path(__file__).parent / "sockets.toml")).world.eye_window)
WIDE = str(Path(__file__).parents[1] / "generalise" / "wide.toml")
CONFIGS = {  # name: (configuration, its eye window or None)
    "default world (generalise preset)": ("generalise", None),
    "many-caregivers world (docs/results/generalise/wide.toml)": (WIDE, None),
    "people world (people preset)": ("people", None),
    "people world, 60x50 window": (str(Path(__file__).parent / "window.toml"), None),
    "people world, eye window 96x24 (4x fovea)": ("people", EYES),
    "people world, eye window placed with an error of 0.03 eye distances": (
        "people", {**EYES, "placement_sd": 0.03}),
    "people world, socket patches of a window placed with an error of 0.1": (
        "people", SOCKETS),
    "people world, the same window, the sockets found by the socket network": (
        "people", {**SOCKETS, "socket_finder": "net"}),
}


def inputs(ds, world) -> np.ndarray:
    """The input: the face's features, the eyes' if kept, then the head angle in [-1, 1]."""
    lo, hi = np.deg2rad([world.head.pan_limits_deg, world.head.tilt_limits_deg]).T
    scaled = (ds.theta_face_rad - (lo + hi) / 2) / ((hi - lo) / 2)
    eyes = [] if ds.eyes is None else [face_features(ds.eyes.astype(float))]
    return np.hstack([face_features(ds.face.astype(float)), *eyes, scaled])


def directions(ds) -> np.ndarray:
    """The direction (rad) of each data set's command: from the face to the target."""
    return np.arctan2(ds.command_rad[:, 1], ds.command_rad[:, 0])


def errors_deg(predicted: np.ndarray, truth: np.ndarray) -> np.ndarray:
    """The angle between each predicted direction and the true one, in degrees."""
    return np.degrees(np.abs(np.angle(np.exp(1j * (predicted - truth)))))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--epochs", type=int, default=12)
    parser.add_argument("--caregivers", type=int, default=N_CAREGIVERS,
                        help="unseen caregivers to read")
    parser.add_argument("--train-caregivers", type=int, default=0,
                        help="record this many training caregivers instead of the preset's")
    parser.add_argument("--out", default="docs/results/people/taught_bound.md")
    args = parser.parse_args()
    start = time.perf_counter()
    rows = ["| world | training sets | median error, unseen caregivers | 90th percentile |",
            "|---|---|---|---|"]
    for name, (source, eyes) in CONFIGS.items():
        config = load_config(source)
        if eyes:
            config = dataclasses.replace(config, world=dataclasses.replace(
                config.world, eye_window=EyeWindowConfig(**eyes)))
        if args.train_caregivers:  # a small run (the tests'): a few caregivers, four poses each
            config = dataclasses.replace(config, recording=dataclasses.replace(
                config.recording, caregivers=args.train_caregivers, poses_per_caregiver=4))
        train, held = datasets_of(config), held_out_datasets(config.world, args.caregivers,
                                                             N_POSES, SEED)
        x, y = inputs(train, config.world), directions(train)
        net = PopulationCode(x.shape[1], PopulationOptions(readout="mode"),
                             np.random.default_rng(0))
        order = np.random.default_rng(1)
        for _ in range(args.epochs):
            shuffled = order.permutation(len(x))
            net.partial_fit(x[shuffled], y[shuffled])
        e = errors_deg(net.predict(inputs(held, config.world)), directions(held))
        rows.append(f"| {name} | {len(x):,} | {np.median(e):.1f}° | {np.percentile(e, 90):.1f}° |")
    text = "\n".join([*rows, "", f"Taught the true directions, {args.epochs} passes; "
                      f"{args.caregivers} unseen caregivers x {N_POSES} poses (held-out seed "
                      f"{SEED}); `python docs/results/people/taught_bound.py` "
                      f"({(time.perf_counter() - start) / 60:.1f} min)."]) + "\n"
    print(write_text(args.out, text))
    print(text)


if __name__ == "__main__":
    main()
