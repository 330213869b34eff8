"""The robot's socket patches: each eye cut around the socket it finds, wherever the window was."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from jointattention import evaluate, load_model
from jointattention.agent.eye_sockets import _drawn_eye, eye_patches, socket_bank
from jointattention.config import load_config
from jointattention.experiment.cells import datasets_of
from jointattention.world.options import EyeWindowConfig
from jointattention.world.recording import make_datasets

SPAN, WIDTH_PX, HEIGHT_PX, PATCH_PX = 2.67, 128, 48, 24


def drawn_window(shift_px: tuple[float, float], iris_px: tuple[float, float]) -> np.ndarray:
    """A window of two drawn eyes on skin, ``shift_px`` off their places, irises at ``iris_px``."""
    import cv2

    per_eye = WIDTH_PX / SPAN
    radius_px = 0.19 * per_eye
    eye = _drawn_eye(radius_px, *iris_px)
    canvas = np.full((HEIGHT_PX, WIDTH_PX), 0.5, np.float32)
    n = eye.shape[0]
    for centre_x in ((WIDTH_PX - per_eye) / 2, (WIDTH_PX + per_eye) / 2):
        x0, y0 = centre_x - (n - 1) / 2 - 0.5, (HEIGHT_PX - n) / 2
        move = np.float32([[1, 0, x0 + shift_px[0]], [0, 1, y0 + shift_px[1]]])
        placed = cv2.warpAffine(eye, move, (WIDTH_PX, HEIGHT_PX), flags=cv2.INTER_LINEAR,
                                borderMode=cv2.BORDER_REPLICATE)  # the eye's ground, 0.5
        canvas += placed - 0.5
    return (60 + 150 * canvas).astype(np.float32)


def dark_centroid(patch: np.ndarray) -> np.ndarray:
    """Where the darkest third of a patch lies (x, y px): the iris, in a patch of one eye."""
    grey = patch.astype(float)
    weight = np.clip(np.percentile(grey, 30) - grey, 0, None)
    ys, xs = np.mgrid[0:grey.shape[0], 0:grey.shape[1]]
    return np.array([(xs * weight).sum(), (ys * weight).sum()]) / weight.sum()


def test_the_patches_are_two_squares_side_by_side():
    """eye_patches keeps (patch, 2 * patch) grey levels, each eye in the middle of its own."""
    patches = eye_patches(drawn_window((0, 0), (0, 0)), SPAN, PATCH_PX)
    assert patches.shape == (PATCH_PX, 2 * PATCH_PX) and patches.dtype == np.uint8
    middle = (PATCH_PX - 1) / 2
    for side in (patches[:, :PATCH_PX], patches[:, PATCH_PX:]):  # each socket in the middle
        assert np.hypot(*(dark_centroid(side) - middle)) < 0.5


@settings(max_examples=25, deadline=None)
@given(st.floats(-5, 5), st.floats(-3, 3))
def test_a_moved_window_moves_the_iris_in_its_patch_by_under_a_pixel(dx, dy):
    """Shifting the window by up to a tenth of an eye distance leaves the iris in the patch."""
    iris = (2.0, -1.0)
    still = eye_patches(drawn_window((0, 0), iris), SPAN, PATCH_PX)
    moved = eye_patches(drawn_window((dx, dy), iris), SPAN, PATCH_PX)
    for side in (slice(0, PATCH_PX), slice(PATCH_PX, None)):
        shift = dark_centroid(moved[:, side]) - dark_centroid(still[:, side])
        # the window itself moved up to 5.8 px; 1,500 random shifts moved the iris 0.51 px at most
        assert np.hypot(*shift) < 0.75


def test_the_iris_moves_in_its_patch_as_the_eye_turns():
    """Irises further right in their sockets lie further right in the patches."""
    xs = [dark_centroid(eye_patches(drawn_window((0, 0), (dx, 0)), SPAN, PATCH_PX)[:, :PATCH_PX])[0]
          for dx in (-3.0, 0.0, 3.0)]
    assert xs[0] < xs[1] - 1 < xs[2] - 2


def test_a_window_without_eyes_is_cut_at_its_middle():
    """A flat half-window (no socket to find) keeps the patch at its centre, without error."""
    flat = np.full((HEIGHT_PX, WIDTH_PX), 120.0, np.float32)
    np.testing.assert_array_equal(eye_patches(flat, SPAN, PATCH_PX), 120)


def test_the_bank_scales_with_the_window():
    """A window of more pixels per eye distance draws bigger eyes, as many."""
    small, big = socket_bank(30.0), socket_bank(60.0)
    assert len(small) == len(big) and big[0].shape[0] > 1.8 * small[0].shape[0]


@pytest.fixture(scope="module")
def people_windows():
    """Twelve scenes of four people: patches and windows, placed exactly and off by 0.1."""
    people = load_config("people").world

    def record(sd: float, patch_px: int):
        eyes = EyeWindowConfig(width_px=WIDTH_PX, height_px=HEIGHT_PX, span=SPAN,
                               placement_sd=sd, socket_patch_px=patch_px)
        return make_datasets(dataclasses.replace(people, eye_window=eyes), 12, seed=5,
                             caregivers=4).eyes

    return record(0.0, PATCH_PX), record(0.1, PATCH_PX), record(0.0, 0), record(0.1, 0)


def test_recorded_sets_keep_the_patches(people_windows):
    """With socket_patch_px, data sets keep the two patches in place of the window."""
    patches = people_windows[0]
    assert patches.shape == (12, PATCH_PX, 2 * PATCH_PX) and patches.std() > 5
    assert EyeWindowConfig(width_px=WIDTH_PX, height_px=HEIGHT_PX,
                           socket_patch_px=PATCH_PX).kept_size_px == (2 * PATCH_PX, PATCH_PX)


def test_a_finders_error_moves_the_iris_far_less_in_the_patch(people_windows):
    """A window off by 0.1 eye distances moves the iris a third as far in the patch as in it."""
    exact, misplaced, window, moved = people_windows

    def shifts(a, b, width):
        return np.median([np.hypot(*(dark_centroid(x[:, :width]) - dark_centroid(y[:, :width])))
                          for x, y in zip(a, b, strict=True)])

    in_patch, in_window = shifts(exact, misplaced, PATCH_PX), shifts(window, moved, WIDTH_PX // 2)
    assert in_window > 2 and in_patch < in_window / 3  # measured: 0.8 px against 4.4 px


def test_a_model_of_socket_patches_is_saved_loaded_and_evaluated(tmp_path, socket_run):
    """A model learned from socket patches keeps their size, and evaluate reads them."""
    run, model = socket_run
    back = load_model(model.save(tmp_path / "m.npz"))
    assert back.robot.eye_size_px == (24, 12)
    ds = datasets_of(run)
    assert ds.eyes.shape[1:] == (12, 24)
    np.testing.assert_array_equal(back.lm_command(ds.view(0), ds.theta_face_rad[0]),
                                  model.lm_command(ds.view(0), ds.theta_face_rad[0]))
    assert 0.0 <= evaluate(back, ds, n_objects=3, n_trials=20).success <= 1.0
