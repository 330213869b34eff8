"""``jointattention detect`` on a real photograph shipped by an installed package."""

from __future__ import annotations

import os
from pathlib import Path

import cv2
import matplotlib
import numpy as np

from jointattention.cli import main

PHOTO = Path(matplotlib.get_data_path()) / "sample_data" / "grace_hopper.jpg"


def test_detect_draws_a_face_and_regions_on_a_real_photograph(tmp_path, capsys):
    """Grace Hopper's photograph: a face, colour and edge regions, and an overlay PNG.

    Matplotlib's photograph: one face found by the Haar cascade, in the upper middle of the picture,
    some bright-colour and edge-rich regions, and an overlay PNG of the photograph's size that
    differs from it.
    """
    assert main(["detect", str(PHOTO), "--out", str(tmp_path)]) == 0
    line = capsys.readouterr().out
    assert "1 faces" in line and "0 bright-colour" not in line and "0 edge-rich" not in line
    out = cv2.imread(str(tmp_path / "grace_hopper_detected.png"))
    photo = cv2.imread(str(PHOTO))
    assert out.shape == photo.shape
    assert np.mean(np.any(out != photo, axis=2)) > 0.05


def test_found_face_is_where_the_face_is():
    """The face box's centre lies in the middle third across and the upper half down."""
    from jointattention.agent.faces import FaceFinder
    from jointattention.config import Config
    from jointattention.figures.detect import find_all

    photo = cv2.cvtColor(cv2.imread(str(PHOTO)), cv2.COLOR_BGR2RGB)
    h, w = photo.shape[:2]
    found = find_all(photo, Config(), FaceFinder("haar", heights_px=(24, min(h, w))))
    (face,) = found.faces
    x, y = face.centre_px
    assert w / 3 < x < 2 * w / 3 and y < h / 2


def test_detect_refuses_a_non_image_and_writes_nothing(tmp_path, capsys):
    """A photograph beside a text file: one error naming the file, nothing written.

    No overlay of either is written.
    """
    bad = tmp_path / "notes.png"
    bad.write_text("not a picture")
    out = tmp_path / "out"
    assert main(["detect", str(PHOTO), str(bad), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "notes.png: not an image" in err and err.count("\n") == 1
    assert not out.exists() or not os.listdir(out)
