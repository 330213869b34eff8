"""One frame of the robot's camera, facing a caregiver no data set of the package holds.

The README's ``follow`` command runs the shipped model on it (``camera_view.png``): the head
at rest (pan and tilt 0, ``follow``'s default ``--theta``), the caregiver of world seed
:data:`SEED` (a seed no data set of the repository uses) in the generalise preset's world.

Run from the repository: ``python docs/results/robot/camera_view.py [OUT.png]`` (a few seconds).
"""

from __future__ import annotations

import sys

import cv2
import numpy as np

from jointattention.config import load_config
from jointattention.world.simulator import World

SEED = 90_210


def main(out: str = "docs/results/robot/camera_view.png") -> None:
    """Render the frame into ``out``."""
    with World(load_config("generalise").world, seed=SEED) as world:
        world.reset()
        world.set_head_angle(np.zeros(2))
        cv2.imwrite(out, cv2.cvtColor(world.render(), cv2.COLOR_RGB2BGR))
    print(out)


if __name__ == "__main__":
    main(*sys.argv[1:])
