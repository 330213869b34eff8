"""docs/results/faces/photos.png: `follow` on photographs that packages ship, with BlazeFace.

    python docs/results/faces/photos.py [--out docs/results/faces/photos.png]

The shipped generalising model (docs/results/generalise/population_n10.npz) follows scikit-image's
astronaut and coffee (no face), matplotlib's Grace Hopper and two of lfw_subset's faces (4x
enlarged amid grey, as `jointattention faces` shows them): the face window (green, placed by
the landmarks alone: refine=False, as for people), BlazeFace's landmarks (yellow), the window
as the model sees it and its command (red). The model learned simulated caregivers only: its
commands for real people are not validated, and mean nothing here; the pipeline is what is
shown.
"""

import argparse
import os
from pathlib import Path

import cv2
import numpy as np
from skimage import data

from jointattention import GazeFollower
from jointattention.deploy.overlay import draw_look
from jointattention.jobs.face_finders import hopper_photo, lfw_view
from jointattention.world.gl import suggested_backend

# A program chooses its process's OpenGL backend (the library only reads MUJOCO_GL).
os.environ.setdefault("MUJOCO_GL", suggested_backend())

HERE = Path(__file__).resolve().parent
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--out", type=Path, default=HERE / "photos.png")
args = parser.parse_args()
SIDE_PX = 360
follower = GazeFollower.load(HERE.parent / "generalise" / "population_n10.npz", min_score=0.6,
                             refine=False)
faces = data.lfw_subset()
lfw = [lfw_view(faces[i]) for i in (0, 7)]
photos = [data.astronaut(), hopper_photo(), *lfw, data.coffee()]
tiles = []
for photo in photos:
    look = follower.look(photo, np.zeros(2))
    tile = draw_look(photo, look)
    scale = SIDE_PX / max(tile.shape[:2])
    tile = cv2.resize(tile, (round(tile.shape[1] * scale), round(tile.shape[0] * scale)),
                      interpolation=cv2.INTER_AREA)
    canvas = np.full((SIDE_PX, SIDE_PX, 3), 255, np.uint8)
    canvas[:tile.shape[0], :tile.shape[1]] = tile
    tiles.append(canvas)
    print("face" if look else "no face", None if look is None else
          np.round(np.rad2deg(look.command_rad), 1))
out = args.out
cv2.imwrite(str(out), cv2.cvtColor(np.hstack(tiles), cv2.COLOR_RGB2BGR))
print(out)
