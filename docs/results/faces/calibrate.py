"""Fit the BlazeFace calibration shipped in jointattention/data/blazeface_calibration.npz.

    python docs/results/faces/calibrate.py [OUT.npz] [--quick]

Renders 12,000 views of 128 caregivers of the many-caregiver world (stream "faces", seed 1: no
measurement of docs/results/faces/detectors.md uses it) and fits the map from BlazeFace's landmarks,
then from the pixels around the head, to the head's centre and height
(jointattention.agent.face_calibration.Calibration). About 3 min. ``--quick``: 640 views of 16
caregivers, enough for the fit (the tests' run).
"""

import argparse
import os

import cv2
from tqdm import tqdm

from jointattention.agent.blazeface import BlazeFace
from jointattention.agent.face_calibration import Calibration
from jointattention.config import load_config
from jointattention.world.face_views import face_views
from jointattention.world.gl import suggested_backend

# A program chooses its process's OpenGL backend (the library only reads MUJOCO_GL).
os.environ.setdefault("MUJOCO_GL", suggested_backend())

N, CAREGIVERS, SEED, STREAM = 12000, 128, 1, "faces"
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("out", nargs="?", default="src/jointattention/data/blazeface_calibration.npz")
parser.add_argument("--quick", action="store_true", help="640 views of 16 caregivers")
args = parser.parse_args()
out = args.out
if args.quick:
    N, CAREGIVERS = 640, 16
net = BlazeFace()
grays, found, centres, heights = [], [], [], []
views = face_views(load_config("many-caregivers").world, N, CAREGIVERS, SEED, stream=STREAM)
for view in tqdm(views, total=N, unit="view"):
    detections = net.detect(view.image)
    if detections:
        grays.append(cv2.cvtColor(view.image, cv2.COLOR_RGB2GRAY))
        found.append(detections[0])
        centres.append(view.centre_px)
        heights.append(view.height_px)
meta = {"command": "python docs/results/faces/calibrate.py", "world": "many-caregivers",
        "seed": SEED, "stream": STREAM, "views": N, "caregivers": CAREGIVERS, "found": len(found)}
Calibration.fit(grays, found, centres, heights, meta, n_stages=4).save(out)
print(f"{out}: fitted on {len(found)} of {N} views")
