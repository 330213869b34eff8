"""Saved models, frozen, on unseen caregivers of worlds widened one group at a time.

Usage::

    python docs/results/people/robustness.py MODEL [MODEL ...]
        [--out docs/results/people/robustness.md]

For each model and each group of the world (stature, distance, face shape, face colours, the
head's share of a gaze turn, pose noise, lighting, room, sensor) the model's own world is
widened in that group alone to the ``people`` preset's ranges, and in every group at once
(the people world itself), and last set in every group as in each other world the "follow
anyone" aims name (the default world, the ``generalise`` preset's, and the
``many-caregivers`` preset's); 32 caregivers x 25 poses are recorded from held-out seed 5151
(no training set and no other file of the repository uses it), and the model is measured
frozen on them with 5 and 10 objects (:func:`jointattention.evaluate`): its fraction of the
set's ceiling, the median angle error, the share of identities above 10°, and how new the
caregivers are (each one's distance to the nearest the model learned from, over their
spacing; :mod:`jointattention.world.novelty`). The rows name each model by its file. The
robot's camera and face window stay the model's own; a world equal to the model's own (a
group the model's world already has at the people world's ranges) has no row.
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from pathlib import Path

import jointattention as ja
from jointattention._files import write_text
from jointattention.config import WorldConfig, load_config
from jointattention.experiment.held_out import held_out_datasets

SEED, N_CAREGIVERS, N_POSES, N_TRIALS = 5151, 32, 25, 4000
# Each group: the fields of [world.<section>] it widens (a whole section: None).
GROUPS = {
    "stature": {"caregiver": ("height_spread_m",)},
    "distance": {"caregiver": ("distance_m", "distance_spread_m")},
    "face shape": {"caregiver": ("head_scale_range",),
                   "identity": ("head_width_range", "head_depth_range", "head_height_range",
                                "hair_volume_range", "hairline_range_m", "eye_spacing_range",
                                "eye_height_range_m", "eye_size_range", "nose_size_range",
                                "mouth_width_range", "brow_thickness_range")},
    "skin, hair and eye colours": {"identity": (
        "skin_palette", "skin_brightness_range", "hair_palette", "hair_brightness_range",
        "iris_range")},
    "head's share of a gaze turn": {"caregiver": ("head_turn_fraction", "head_turn_spread")},
    "pose noise": {"caregiver": ("pose_noise_deg", "pose_noise_spread_deg")},
    "lighting": {"lighting": None},
    "room": {"room": None},
    "sensor": {"sensor": None},
}

# The other worlds of the "follow anyone" aims: {row name: preset}.
OTHER_WORLDS = {"everything as in the default world": "generalise",
                "everything as in the many-caregivers world": "many-caregivers"}


def widened(world: WorldConfig, people: WorldConfig, group: dict) -> WorldConfig:
    """``world`` with ``group``'s fields set to ``people``'s (any other world's)."""
    for section, fields in group.items():
        ours, theirs = getattr(world, section), getattr(people, section)
        names = fields or [f.name for f in dataclasses.fields(theirs)]
        world = dataclasses.replace(world, **{section: dataclasses.replace(
            ours, **{name: getattr(theirs, name) for name in names})})
    return world


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("models", nargs="+", type=Path, metavar="MODEL")
    parser.add_argument("--caregivers", type=int, default=N_CAREGIVERS)
    parser.add_argument("--poses", type=int, default=N_POSES)
    parser.add_argument("--trials", type=int, default=N_TRIALS)
    parser.add_argument("--out", default="docs/results/people/robustness.md")
    args = parser.parse_args()
    start, people = time.perf_counter(), load_config("people").world
    others = {name: load_config(preset).world for name, preset in OTHER_WORLDS.items()}
    rows = ["| model | its caregivers differ in | objects | fraction of the ceiling | median "
            "error | identities above 10° | novelty, median (largest) |",
            "|---|---|---|---|---|---|---|"]
    for path in args.models:
        model = ja.load_model(path)
        own = model.config.world
        worlds = {"nothing (its own world)": own,
                  **{name: widened(own, people, g) for name, g in GROUPS.items()},
                  "everything at once (the people world)": own.with_people_of(people),
                  **{name: own.with_people_of(other) for name, other in others.items()}}
        for name, world in worlds.items():
            if name != "nothing (its own world)" and world == own:
                continue  # e.g. a model of the people world: no wider world to show
            ds = held_out_datasets(world, args.caregivers, args.poses, SEED)
            for n in (5, 10):
                e = ja.evaluate(model, ds, n_objects=n, n_trials=args.trials, seed=SEED)
                rows.append(f"| `{path}` | {name} | {n} | {e.fraction_of_ceiling:.2f} | "
                            f"{e.median_error_deg:.1f}° | {e.share_identities_over_10deg:.2f} | "
                            f"{e.novelty_median:.2f} ({e.novelty_max:.2f}) |")
    text = "\n".join([*rows, "", f"{args.caregivers} caregivers x {args.poses} poses per world "
                      f"(held-out seed {SEED}), {args.trials:,} trials of the model and of the "
                      "oracle each; `python docs/results/people/robustness.py "
                      f"{' '.join(map(str, args.models))}` "
                      f"({(time.perf_counter() - start) / 60:.1f} min)."]) + "\n"
    print(write_text(args.out, text))
    print(text)


if __name__ == "__main__":
    main()
