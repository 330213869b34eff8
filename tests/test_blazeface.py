"""BlazeFace, the shipped face detector: it finds faces, places windows where data sets cut them."""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from jointattention._readers import read_image
from jointattention.agent.blazeface import BlazeFace, Detection
from jointattention.agent.face_calibration import SIDE_PX, Calibration
from jointattention.agent.finders import finder_for
from jointattention.config import load_config

PHOTO = Path(matplotlib.get_data_path()) / "sample_data" / "grace_hopper.jpg"


def test_finds_the_one_face_of_a_photograph_and_its_landmarks():
    """Grace Hopper's photograph: one face, her eyes above her mouth, inside the box."""
    found = BlazeFace().detect(read_image(PHOTO))
    assert len(found) == 1 and found[0].score > 0.8
    x, y, w, h = found[0].box_px
    marks = found[0].landmarks_px
    assert ((marks[:4, 0] > x) & (marks[:4, 0] < x + w) & (marks[:4, 1] > y)
            & (marks[:4, 1] < y + h)).all()
    assert marks[3, 1] > max(marks[0, 1], marks[1, 1])  # the mouth below the eyes
    assert marks[0, 0] < marks[1, 0]  # the person's right eye on the image's left


@pytest.mark.parametrize("image", [np.zeros((240, 320, 3), np.uint8),
                                   np.full((480, 640, 3), 128, np.uint8),
                                   np.random.default_rng(0).integers(0, 256, (240, 320, 3),
                                                                     dtype=np.uint8)])
def test_finds_no_face_where_there_is_none(image):
    """A black, a grey and a noise image hold no face."""
    assert finder_for("blazeface").find(image) == []


def test_finds_held_out_caregivers_where_their_heads_are(needs_gl):
    """30 views of 30 caregivers no calibration saw: all found, windows where data sets cut them."""
    from jointattention.world.face_views import face_views

    config = load_config("many-caregivers").world
    finder = finder_for("blazeface")
    errors, ratios = [], []
    for view in face_views(config, 30, 30, seed=5, stream="held-out"):
        faces = finder.find(view.image)
        assert faces, "a face was missed"
        errors.append(np.hypot(*(faces[0].centre_px - view.centre_px)) / view.height_px)
        ratios.append(faces[0].height_px / (1.15 * view.height_px))  # the data sets' window
    assert np.median(errors) < 0.1 and max(errors) < 0.25
    assert np.median(np.abs(np.log(ratios))) < 0.08 and np.max(np.abs(np.log(ratios))) < 0.3


@settings(max_examples=20, deadline=None)
@given(weights=st.lists(st.floats(-0.5, 0.5), min_size=39, max_size=39), seed=st.integers(0, 99))
def test_calibration_recovers_a_linear_map_of_the_landmarks(weights, seed):
    """Heads made from detections by a known landmark map give that map back."""
    rng = np.random.default_rng(seed)
    w = np.array(weights).reshape(13, 3)
    w[0, 2] += 2.0  # heads are taller than nothing
    n = 1 + SIDE_PX ** 2 + 20
    detections = [Detection(np.r_[rng.uniform(0, 200, 2), s, s], 0.9,
                            rng.uniform(0, 200, 2) + rng.normal(0, 0.3, (6, 2)) * s)
                  for s in rng.uniform(20, 80, n)]
    truth = Calibration(w, np.zeros((0, 1 + SIDE_PX ** 2, 3)), {})
    heads = [truth.head(d) for d in detections]
    grays = [np.zeros((8, 8), np.uint8)] * n
    fitted = Calibration.fit(grays, detections, [c for c, _ in heads], [h for _, h in heads],
                             {}, n_stages=1)
    np.testing.assert_allclose(fitted.weights, w, atol=1e-6)
    # blank images tell the refinement nothing: it moves no head
    for d, (c, h) in zip(detections[:5], heads[:5], strict=True):
        centre, height = fitted.head(d, grays[0])
        np.testing.assert_allclose(centre, c, atol=1e-6)
        assert height == pytest.approx(h, rel=1e-6)


def test_the_refinement_brings_held_out_heads_closer(needs_gl):
    """On 40 held-out views the pixel refinements place heads nearer than the landmarks alone."""
    import cv2

    from jointattention.world.face_views import face_views

    shipped, net = Calibration.load(), BlazeFace(0.4)
    before, after = [], []
    for view in face_views(load_config("many-caregivers").world, 40, 40, seed=9,
                           stream="held-out"):
        d = net.detect(view.image)[0]
        gray = cv2.cvtColor(view.image, cv2.COLOR_RGB2GRAY)
        before.append(np.hypot(*(shipped.head(d)[0] - view.centre_px)))
        after.append(np.hypot(*(shipped.head(d, gray)[0] - view.centre_px)))
    assert np.median(after) < np.median(before)


def test_calibration_round_trips_through_a_file(tmp_path):
    """The shipped calibration saves and loads with its maps and how it was fitted."""
    shipped = Calibration.load()
    # the command as it was when the file was fitted: the script is now under docs/results/
    assert shipped.meta["command"] == "python docs/faces/calibrate.py"
    assert len(shipped.stages) >= 1
    shipped.save(tmp_path / "c.npz")
    again = Calibration.load(tmp_path / "c.npz")
    np.testing.assert_array_equal(again.weights, shipped.weights)
    np.testing.assert_array_equal(again.stages, shipped.stages)
    assert again.meta == shipped.meta


@pytest.mark.parametrize("bad", [0.0, 1.0, float("nan"), -0.2])
def test_a_score_that_is_not_a_probability_is_refused(bad):
    """min_score outside (0, 1) is one ValueError naming it."""
    with pytest.raises(ValueError, match="min_score"):
        BlazeFace(bad)


def test_the_faces_command_prints_and_writes_the_comparison(tmp_path, capsys, needs_gl):
    """`jointattention faces` measures every finder on held-out views and on photographs."""
    from jointattention.cli import main

    out = tmp_path / "detectors.md"
    assert main(["faces", "--n", "6", "--caregivers", "3", "--out", str(out)]) == 0
    text = out.read_text()
    assert text == capsys.readouterr().out
    row = next(line for line in text.splitlines() if line.startswith("| blazeface |"))
    found = int(row.split("(")[1].split("/")[0])
    assert 5 <= found <= 6  # BlazeFace finds (almost) every rendered face
    assert "| template |" in text and "| haar |" in text
    assert "lfw_subset" in text or "not measured" in text


def test_the_faces_command_refuses_more_caregivers_than_views(capsys):
    """--caregivers above --n is one error line."""
    from jointattention.cli import main

    assert main(["faces", "--n", "2", "--caregivers", "3"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--caregivers 3" in err


def test_a_long_thin_image_costs_no_square_of_its_long_side():
    """A 10 x 30,000 image is searched in little memory (it is shrunk before it is padded)."""
    import tracemalloc

    image = np.full((10, 30_000, 3), 128, np.uint8)
    net = BlazeFace()
    tracemalloc.start()
    try:
        assert net.detect(image) == []
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 20 * 2**20  # a square of the long side would be 2.7 GB


def test_landmarks_only_places_the_window_by_the_landmark_map_alone():
    """refine=False: the face is where the landmark map puts it; the default refines it."""
    photo = read_image(PHOTO)
    detection = BlazeFace(0.4).detect(photo)[0]
    centre, height = Calibration.load().head(detection)
    plain = finder_for("blazeface", refine=False).find(photo)[0]
    np.testing.assert_allclose(plain.centre_px, centre)
    assert plain.height_px == pytest.approx(1.15 * height)
    refined = finder_for("blazeface").find(photo)[0]
    assert not np.allclose(refined.centre_px, plain.centre_px)
