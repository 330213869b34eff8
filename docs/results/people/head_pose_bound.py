"""What a caregiver's head pose alone tells of where she looks: a bound on any head reader.

Usage::

    python docs/results/people/head_pose_bound.py [--scenes 30000]
        [--out docs/results/people/head_pose_bound.md]

For each world, draws scenes (no rendering) of 300 caregivers and, for each, the direction
from her face to her target in the robot's head angles (what the learners are taught). A
k-nearest-neighbour reader (k = 15, the circular mean of the neighbours' directions) that
knows her true head pose (yaw, pitch), the robot's head angle at her face and her distance (a
robot measures it by the face's apparent size) learns from 90% of the scenes and reads the
rest: its median error is what the head alone can tell, for a reader with plenty of data.
The same reader knowing her gaze (head and eyes) shows what the eyes add. Writes one row per world.
"""

from __future__ import annotations

import argparse
import dataclasses
import time

import numpy as np

from jointattention._files import write_text
from jointattention.config import load_config
from jointattention.rng import stream
from jointattention.world.identity import sample_caregiver
from jointattention.world.kinematics import HeadKinematics
from jointattention.world.scene import sample_scene

N_PEOPLE, K = 300, 15


def _worlds() -> dict:
    people = load_config("people").world
    cg = people.caregiver
    return {
        "default": load_config("default").world,
        "many-caregivers": load_config("many-caregivers").world,
        "people": people,
        "people, no pose noise": dataclasses.replace(people, caregiver=dataclasses.replace(
            cg, pose_noise_deg=0.0, pose_noise_spread_deg=0.0)),
        "people, every head share 0.8": dataclasses.replace(people, caregiver=dataclasses.replace(
            cg, head_turn_fraction=0.8, head_turn_spread=0.0)),
    }


def scenes(world, n: int, seed: int = 0) -> np.ndarray:
    """(n, 8): head yaw, pitch; gaze yaw, pitch; head angle at the face (2); distance; direction."""
    kin, rng = HeadKinematics.from_config(world), stream(seed, "head-pose-bound")
    people = [sample_caregiver(world, rng) for _ in range(N_PEOPLE)]
    rows = np.empty((n, 8))
    for i in range(n):
        s = sample_scene(world, rng, people[i % N_PEOPLE])
        face, target = kin.centring_angles(s.head_pos_m), kin.centring_angles(s.target_pos_m)
        rows[i] = (*s.head_yaw_pitch_rad, *(s.head_yaw_pitch_rad + s.eye_yaw_pitch_rad), *face,
                   np.linalg.norm(s.head_pos_m),
                   np.arctan2(target[1] - face[1], target[0] - face[0]))
    return rows


def knn_errors_deg(x: np.ndarray, direction: np.ndarray, n_train: int) -> np.ndarray:
    """The reader's angle errors on the rows after ``n_train`` (inputs scaled to unit s.d.)."""
    x = x / x.std(0)
    train, unit = x[:n_train], np.exp(1j * direction[:n_train])
    errors = []
    for row, truth in zip(x[n_train:], direction[n_train:], strict=True):
        near = np.argpartition(((train - row) ** 2).sum(1), K)[:K]
        errors.append(np.angle(unit[near].mean() * np.exp(-1j * truth)))
    return np.degrees(np.abs(errors))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=int, default=30_000)
    parser.add_argument("--out", default="docs/results/people/head_pose_bound.md")
    args = parser.parse_args()
    start, n_train = time.perf_counter(), int(0.9 * args.scenes)
    rows = ["| world | head pose: median error | 90th percentile | head and eyes: median "
            "| 90th percentile |", "|---|---|---|---|---|"]
    for name, world in _worlds().items():
        a = scenes(world, args.scenes)
        head = knn_errors_deg(a[:, [0, 1, 4, 5, 6]], a[:, 7], n_train)
        gaze = knn_errors_deg(a[:, [2, 3, 4, 5, 6]], a[:, 7], n_train)
        rows.append(f"| {name} | {np.median(head):.1f}° | {np.percentile(head, 90):.1f}° | "
                    f"{np.median(gaze):.1f}° | {np.percentile(gaze, 90):.1f}° |")
    text = "\n".join([*rows, "", f"{args.scenes:,} scenes of {N_PEOPLE} caregivers per world, "
                      f"read by a {K}-nearest-neighbour reader trained on 90% of them; `python "
                      "docs/results/people/head_pose_bound.py` "
                      f"({(time.perf_counter() - start) / 60:.1f} min)."]) + "\n"
    print(write_text(args.out, text))
    print(text)


if __name__ == "__main__":
    main()
