"""The robot's eye-socket network: where it puts the sockets, and how it is fitted and kept."""

from __future__ import annotations

import dataclasses
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from jointattention.agent.eye_sockets import eye_patches, sockets
from jointattention.agent.socket_net import SocketNet, shipped
from jointattention.config import load_config
from jointattention.errors import ArgumentError, ConfigError
from jointattention.world.options import EyeWindowConfig
from jointattention.world.recording import (
    HELD_OUT,
    eye_box,
    eye_window_at,
    make_datasets,
    sockets_in_window,
)
from jointattention.world.simulator import World

ROOT = Path(__file__).resolve().parents[1]
SOCKETS = load_config(str(ROOT / "docs/results/people/sockets.toml")).world.eye_window


def _world():
    """The people world with sockets.toml's window, placed exactly, kept whole."""
    return dataclasses.replace(load_config("people").world, eye_window=dataclasses.replace(
        SOCKETS, placement_sd=0.0, socket_patch_px=0))


@pytest.fixture(scope="module")
def unseen_windows(gl_available):
    """Eye windows of 8 unseen people x 3 poses, placed 0.1 eye distances off, and the truth."""
    if not gl_available:
        pytest.skip("no off-screen OpenGL (EGL or OSMesa) on this machine")
    place = np.random.default_rng(3)
    windows, truth = [], []
    for c in range(8):
        with World(_world(), seed=9100 + c, stream=HELD_OUT) as w:
            for _ in range(3):
                w.reset()
                w.set_head_angle(w.face_angle_rad)
                centre, distance = eye_box(w)
                error = place.normal(0.0, 0.1, 3)
                windows.append(eye_window_at(w, centre, distance, error))
                truth.append(sockets_in_window(w, centre, distance, error))
    return np.array(windows), np.array(truth)


def test_the_network_places_the_sockets_of_unseen_people_closer_than_the_bank(unseen_windows):
    """On unseen people's misplaced windows the network is within a pixel, the bank is not."""
    windows, truth = unseen_windows
    net = np.linalg.norm(shipped().predict(windows) - truth, axis=-1)
    bank = np.linalg.norm(np.array([sockets(w, SOCKETS.span) for w in windows]) - truth, axis=-1)
    assert np.median(net) < 1.0 and np.median(net) < np.median(bank) / 2


def test_the_sockets_move_with_the_window(unseen_windows):
    """A window cut 4 px further right puts both sockets about 4 px further left in it."""
    import cv2

    window = unseen_windows[0][0].astype(np.float32)
    moved = cv2.warpAffine(window, np.float32([[1, 0, -4], [0, 1, 0]]), window.shape[::-1],
                           borderMode=cv2.BORDER_REPLICATE)
    shift = shipped().predict(np.stack([moved, window]))
    np.testing.assert_allclose(shift[0] - shift[1], [[-4, 0], [-4, 0]], atol=0.75)


def test_patches_are_cut_around_the_network_s_sockets(unseen_windows):
    """finder='net' cuts two patches whose middles are the network's sockets."""
    window = unseen_windows[0][0]
    patches = eye_patches(window, SOCKETS.span, 24, "net")
    assert patches.shape == (24, 48) and patches.dtype == np.uint8
    x, y = shipped().predict(window[None])[0][1]
    import cv2

    right = cv2.getRectSubPix(window.astype(np.float32), (24, 24), (float(x), float(y)))
    np.testing.assert_array_equal(patches[:, 24:], np.clip(np.rint(right), 0, 255))


def test_a_window_of_another_size_is_one_error_line():
    """Windows of a size the network was not fitted for are refused, naming both sizes."""
    with pytest.raises(ArgumentError, match=r"expected \(n, 48, 128\)"):
        shipped().predict(np.zeros((2, 24, 96), np.uint8))


def test_an_unknown_finder_is_refused():
    """socket_finder accepts only the bank and the network."""
    with pytest.raises(ConfigError, match="socket_finder"):
        EyeWindowConfig(width_px=128, height_px=48, socket_patch_px=24, socket_finder="oracle")
    with pytest.raises(ValueError, match="expected one of bank, net"):
        sockets(np.zeros((48, 128)), 2.67, "oracle")


def test_a_saved_network_loads_to_the_same_sockets(tmp_path, unseen_windows):
    """Saving then loading gives the same weights, command and sockets."""
    net = shipped()
    net.save(tmp_path / "n.npz")
    back = SocketNet.load(tmp_path / "n.npz")
    assert back.command == net.command == "python docs/results/people/socket_net.py"
    np.testing.assert_array_equal(back.predict(unseen_windows[0][:3]),
                                  net.predict(unseen_windows[0][:3]))


def test_recorded_sets_keep_the_network_s_patches(needs_gl):
    """A world with socket_finder 'net' records the two patches in place of the window."""
    eyes = dataclasses.replace(SOCKETS, socket_finder="net")
    world = dataclasses.replace(load_config("people").world, eye_window=eyes)
    ds = make_datasets(world, 4, seed=5, caregivers=2)
    assert ds.eyes.shape == (4, 24, 48) and ds.eyes.std() > 5


@pytest.mark.rl
def test_the_fitting_script_fits_a_network_that_numpy_runs(tmp_path, needs_gl):
    """socket_net.py --quick records views, fits with PyTorch and writes a loadable network."""
    pytest.importorskip("torch")
    out, table = tmp_path / "net.npz", tmp_path / "net.md"
    proc = subprocess.run([sys.executable, str(ROOT / "docs/results/people/socket_net.py"),
                           "--quick", "--out", str(out), "--table", str(table)],
                          capture_output=True, text=True, timeout=600, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert SocketNet.load(out).window_px == (128, 48)
    assert "| socket network (socket_net) |" in table.read_text()


def test_recordings_by_the_network_are_cached_under_its_sum(monkeypatch):
    """A network fitted again (a new SHA-256) records anew; the bank's recordings keep theirs."""
    from jointattention import data
    from jointattention.experiment.dataset_cache import recorded_path

    people = load_config("people").world
    by = {finder: dataclasses.replace(people, eye_window=dataclasses.replace(
        SOCKETS, socket_finder=finder)) for finder in ("net", "bank")}
    before = {finder: recorded_path(world, 8, 1) for finder, world in by.items()}
    monkeypatch.setitem(data.SHA256, "eye_socket_net.npz", "0" * 64)
    assert recorded_path(by["net"], 8, 1) != before["net"]
    assert recorded_path(by["bank"], 8, 1) == before["bank"]
