"""Fit the BlazeFace calibration shipped in jointattention/data/blazeface_calibration.npz.

    python docs/faces/calibrate.py [OUT.npz]

Renders 1,000 views of 64 caregivers of the many-caregiver world (stream "faces", seed 0:
no measurement of docs/faces/detectors.md uses it) and fits the linear map from BlazeFace's
landmarks to the head's centre and height (jointattention.agent.blazeface.Calibration).
"""

import sys

from tqdm import tqdm

from jointattention.agent.blazeface import BlazeFace, Calibration
from jointattention.config import load_config
from jointattention.world.face_views import face_views

N, CAREGIVERS, SEED, STREAM = 1000, 64, 0, "faces"
out = sys.argv[1] if len(sys.argv) > 1 else "src/jointattention/data/blazeface_calibration.npz"
net = BlazeFace()
found, centres, heights = [], [], []
views = face_views(load_config("many-caregivers").world, N, CAREGIVERS, SEED, stream=STREAM)
for view in tqdm(views, total=N, unit="view"):
    detections = net.detect(view.image)
    if detections:
        found.append(detections[0])
        centres.append(view.centre_px)
        heights.append(view.height_px)
meta = {"command": "python docs/faces/calibrate.py", "world": "many-caregivers", "seed": SEED,
        "stream": STREAM, "views": N, "caregivers": CAREGIVERS, "found": len(found)}
Calibration.fit(found, centres, heights, meta).save(out)
print(f"{out}: fitted on {len(found)} of {N} views")
