"""A robot's path from recordings to gaze following, run on the simulated head.

1. Record as a robot's script would: look at the caregiver, save the camera image and the head
   angle; turn to the object the caregiver looks at and write the head angle change; one row of
   ``recording.csv`` per image. ``--look-away`` images look 50 degrees away from the caregiver
   (no face in them: the import must leave them out).
2. ``jointattention datasets import`` the folder (the rows without a face are reported).
3. ``jointattention train`` on the imported data sets, saving the model.
4. Load it with :class:`jointattention.GazeFollower` and follow: each image's face is found,
   its window cut and the command compared with the recorded one, on the poses learned from
   and on new poses of the same caregiver.

    python examples/recorded_head.py --poses 125 --steps 60000 --out runs/recorded_head
"""

from __future__ import annotations

import argparse
import csv
import json
import os
from pathlib import Path

import cv2
import numpy as np

from jointattention import GazeFollower
from jointattention.cli import main as cli
from jointattention.config import load_config
from jointattention.experiment.probes import angle_deg
from jointattention.world.gl import suggested_backend
from jointattention.world.simulator import World

# A program chooses its process's OpenGL backend (the library only reads MUJOCO_GL).
os.environ.setdefault("MUJOCO_GL", suggested_backend())


def record(world: World, folder: Path, poses: int, look_away: int = 2) -> list[dict]:
    """Render ``poses`` views of the caregiver, then ``look_away`` views without her."""
    folder.mkdir(parents=True, exist_ok=True)
    rows = []
    for i in range(poses + look_away):
        state = world.reset()
        theta = world.face_angle_rad
        if i >= poses:  # looking 50 degrees away: the caregiver is out of view
            theta = theta + np.deg2rad([50.0 if theta[0] < 0 else -50.0, 0.0])
        world.set_head_angle(theta)
        name = f"img_{i:04d}.png"
        cv2.imwrite(str(folder / name), cv2.cvtColor(world.render(), cv2.COLOR_RGB2BGR))
        command = world.kinematics.centring_angles(state.target_pos_m) - theta
        rows.append({"image": name, "pan_rad": theta[0], "tilt_rad": theta[1],
                     "command_pan_rad": command[0], "command_tilt_rad": command[1]})
    with open(folder / "recording.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    return rows


def follow(model: Path, folder: Path, rows: list[dict]) -> dict:
    """Median angle error of the follower's commands on a recording's caregiver images."""
    follower = GazeFollower.load(model)
    errors, no_face = [], 0
    for row in rows:
        image = cv2.cvtColor(cv2.imread(str(folder / row["image"])), cv2.COLOR_BGR2RGB)
        command = follower.command(image, [row["pan_rad"], row["tilt_rad"]])
        if command is None:
            no_face += 1
            continue
        recorded = np.array([row["command_pan_rad"], row["command_tilt_rad"]])
        errors.append(float(angle_deg(command, recorded)))
    errors = np.array(errors)
    return {"median_error_deg": round(float(np.median(errors)), 1),
            "within_20_deg": round(float(np.mean(errors <= 20)), 3), "no_face": no_face}


def main(argv: list[str] | None = None) -> dict:
    """Record, import, train, save, load and follow; print and return the errors."""
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--poses", type=int, default=125, help="caregiver poses recorded to learn")
    p.add_argument("--test-poses", type=int, default=60, help="new poses to follow")
    p.add_argument("--steps", type=int, default=60000, help="learning time, steps")
    p.add_argument("--objects", type=int, default=1, help="objects in the learning trials")
    p.add_argument("--look-away", type=int, default=2,
                   help="views away from the caregiver recorded to learn (no face in them)")
    p.add_argument("--seed", type=int, default=0, help="world seed (the caregiver)")
    p.add_argument("--out", type=Path, default=Path("runs/recorded_head"), help="folder")
    args = p.parse_args(argv)
    learn, test = args.out / "recording", args.out / "new_poses"
    with World(load_config().world, seed=args.seed) as world:  # one caregiver, new poses
        learn_rows = record(world, learn, args.poses, args.look_away)[:args.poses]
        test_rows = record(world, test, args.test_poses, 0)
    datasets = args.out / "datasets.npz"
    assert cli(["datasets", "import", str(learn), "--out", str(datasets), "--quiet"]) == 0
    faces_imported = len(np.load(datasets)["face"])
    config = args.out / "config.toml"
    config.write_text(f'seed = 0\ndatasets = "{datasets.resolve()}"\n\n[experiment]\n'
                      f"n_steps = {args.steps}\nn_seeds = 1\nbin_steps = {args.steps // 10}\n\n"
                      f'[[experiment.conditions]]\nname = "learn"\n'
                      f"n_objects = {args.objects}\n")
    model = args.out / "model.npz"
    assert cli(["train", "--config", str(config), "--condition", "learn", "--out", str(model),
                "--quiet"]) == 0
    result = {"rows": len(learn_rows) + args.look_away, "imported": faces_imported,
              "learned_poses": follow(model, learn, learn_rows),
              "new_poses": follow(model, test, test_rows)}
    print(json.dumps(result))
    return result


if __name__ == "__main__":
    main()
