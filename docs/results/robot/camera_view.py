"""One frame of the robot's camera, facing a caregiver no data set of the package holds.

The README's ``follow`` command runs the shipped model on it (``camera_view.png``): the head
at rest (pan and tilt 0, ``follow``'s default ``--theta``), the caregiver of world seed
:data:`SEED` (a seed no data set of the repository uses) in the generalise preset's world.

With ``--people``, the frame for the shipped people-world model, which reads the eyes too
(``docs/results/people/sockets_net_n10.npz``): the same seed's caregiver in that model's world
(``docs/results/people/sockets_net.toml``), the head turned to the face as a robot that found
it would be, seen through the fovea (``zoom`` times the camera's size: the frames such a model
takes), as a JPEG. It prints the head angle to give ``follow --theta``, and where her target
lies from there, to compare with the direction of ``follow``'s command.

Run from the repository: ``python docs/results/robot/camera_view.py [OUT.png] [--people]`` (a
few seconds).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import cv2
import numpy as np

from jointattention.config import load_config
from jointattention.world.simulator import World

SEED = 90_210
HERE = Path(__file__).parent
PEOPLE = HERE.parent / "people" / "sockets_net.toml"


def main() -> None:
    """Render the frame into the file named."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", help="the PNG to write (default: camera_view.png, "
                        "or fovea_view_people.jpg with --people, beside this script)")
    parser.add_argument("--people", action="store_true",
                        help="the people-world model's frame: its fovea's, facing the face")
    args = parser.parse_args()
    out = args.out or str(HERE / ("fovea_view_people.jpg" if args.people else "camera_view.png"))
    world_config = load_config(str(PEOPLE) if args.people else "generalise").world
    with World(world_config, seed=SEED) as world:
        world.reset()
        if not args.people:
            world.set_head_angle(np.zeros(2))
            image = world.render()
        else:
            # whole degrees, as follow --theta takes them back
            theta = np.deg2rad(np.round(np.rad2deg(world.face_angle_rad)))
            world.set_head_angle(theta)
            kin = world.kinematics
            image = world.render_zoomed(world_config.eye_window.zoom)
            pan, tilt = np.rad2deg(theta) + 0.0  # no "-0"
            print(f"head at pan {pan:.0f} deg, tilt {tilt:.0f} deg: follow "
                  f"--theta={pan:.0f},{tilt:.0f}")  # "=": a negative pan is no option
            to_target = np.rad2deg(kin.centring_angles(world.state.target_pos_m) - theta)
            print(f"her target: pan {to_target[0]:+.1f} deg, tilt {to_target[1]:+.1f} deg from "
                  "there (what only the experimenter knows; the command's direction is the "
                  "model's guess at it)")
    # JPEG as a camera writes it (quality 90): the sensor noise makes a PNG of the fovea 2 MB
    cv2.imwrite(out, cv2.cvtColor(image, cv2.COLOR_RGB2BGR), [cv2.IMWRITE_JPEG_QUALITY, 90])
    print(out)


if __name__ == "__main__":
    main()
