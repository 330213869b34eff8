"""Caregiver data sets: recording, round trip, validation with one clear error per fault."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from jointattention import datasets
from jointattention.config import WorldConfig
from jointattention.datasets import CaregiverDatasets, default_datasets, load, save
from jointattention.errors import DatasetError
from jointattention.world.recording import make_datasets


@pytest.fixture(scope="module")
def recorded(gl_available) -> CaregiverDatasets:
    """Twelve data sets recorded from a world."""
    if not gl_available:
        pytest.skip("no off-screen OpenGL")
    return make_datasets(WorldConfig(), 12, seed=5)


def _write(path, **arrays) -> None:
    base = {
        "schema_version": np.array(1),
        "face": np.zeros((3, 25, 30), np.uint8),
        "theta_face_rad": np.zeros((3, 2)),
        "command_rad": np.zeros((3, 2)),
    }
    base.update(arrays)
    np.savez(path, **{k: v for k, v in base.items() if v is not None})


def test_recorded_sets_round_trip(tmp_path, recorded):
    """Saved data sets load back equal, metadata included."""
    path = save(recorded, tmp_path / "sets.npz")
    back = load(path)
    for key in ("face", "theta_face_rad", "command_rad", "target_m"):
        assert np.array_equal(getattr(back, key), getattr(recorded, key))
    assert back.meta == json.loads(json.dumps(recorded.meta))


def test_recording_is_deterministic(recorded):
    """The same seed records the same bytes."""
    again = make_datasets(WorldConfig(), 12, seed=5)
    assert np.array_equal(again.face, recorded.face)
    assert np.array_equal(again.command_rad, recorded.command_rad)


def test_command_turns_the_head_from_the_face_to_the_target(recorded):
    """theta_face + command centres the recorded target; commands vary across sets."""
    from jointattention.world.kinematics import HeadKinematics

    kin = HeadKinematics.from_config(WorldConfig())
    for theta, cmd, target in zip(recorded.theta_face_rad, recorded.command_rad,
                                  recorded.target_m, strict=True):
        uv, _ = kin.project(target, theta + cmd)
        np.testing.assert_allclose(uv[0], kin.centre_px, atol=1e-6)
    assert np.std(recorded.command_rad, axis=0).min() > np.deg2rad(5)


def test_face_windows_differ_with_gaze(recorded):
    """Different targets give visibly different face windows (not one repeated image)."""
    faces = recorded.face.astype(float)
    diffs = [np.abs(faces[i] - faces[j]).mean() for i in range(4) for j in range(i + 1, 5)]
    assert min(diffs) > 1.0


def test_shipped_default_is_valid():
    """The package ships 125 valid data sets with 30x25 windows."""
    ds = default_datasets()
    assert len(ds) == 125 and ds.window_size_px == (30, 25)
    assert ds.face.std() > 10


@pytest.mark.parametrize(
    ("arrays", "message"),
    [
        ({"face": np.zeros((3, 25, 30), np.float32)}, "field 'face': expected uint8"),
        ({"face": np.zeros((3, 25), np.uint8)}, "field 'face': expected uint8 array of shape"),
        ({"face": np.zeros((0, 25, 30), np.uint8)}, "field 'face': expected at least one"),
        ({"theta_face_rad": np.zeros((3, 3))}, r"field 'theta_face_rad': expected float array "
                                                r"of shape \(3, 2\)"),
        ({"command_rad": np.zeros((2, 2))}, "field 'command_rad'"),
        ({"command_rad": np.full((3, 2), 7.0)}, "field 'command_rad': expected angles"),
        ({"command_rad": np.full((3, 2), np.nan)}, "field 'command_rad': expected finite"),
        ({"target_m": np.zeros((3, 2))}, "field 'target_m'"),
        ({"schema_version": np.array(3)}, "field 'schema_version': expected 1 or 2, got 3"),
        ({"schema_version": None}, "field 'schema_version' is missing"),
        ({"face": None}, "field 'face' is missing"),
        ({"extra": np.zeros(3)}, "field 'extra' is not part of schema version 1"),
        ({"meta": np.array("{not json")}, "field .meta.: expected JSON text"),
    ],
)
def test_malformed_sets_are_rejected_naming_the_field(tmp_path, arrays, message):
    """Each malformation gives one DatasetError naming the file and the field."""
    path = tmp_path / "bad.npz"
    _write(path, **arrays)
    with pytest.raises(DatasetError, match=message) as info:
        load(path)
    assert str(path) in str(info.value)


def test_missing_and_non_npz_files_are_rejected(tmp_path):
    """A missing file and a file that is not an archive are clear errors."""
    with pytest.raises(DatasetError, match="no such file"):
        load(tmp_path / "nope.npz")
    junk = tmp_path / "junk.npz"
    junk.write_text("hello")
    with pytest.raises(DatasetError, match=r"not a readable \.npz"):
        load(junk)


def test_pickled_objects_are_refused(tmp_path):
    """An object array (which would need pickle) is refused, not executed."""
    path = tmp_path / "pickled.npz"
    _write(path, face=np.array([object()] * 3, dtype=object))
    with pytest.raises(DatasetError, match=r"pickled\.npz"):
        load(path)


def test_failed_save_leaves_nothing_behind(tmp_path, monkeypatch):
    """An error while writing leaves neither the target file nor a temporary file."""
    ds = default_datasets()

    def boom(*args, **kwargs):
        raise OSError("disk full")

    monkeypatch.setattr(datasets.np, "savez_compressed", boom)
    with pytest.raises(OSError, match="disk full"):
        save(ds, tmp_path / "out.npz")
    assert list(tmp_path.iterdir()) == []


def test_save_wants_npz_suffix(tmp_path):
    """Saving to a name without .npz is refused before anything is written."""
    with pytest.raises(DatasetError, match=r"ending in \.npz"):
        save(default_datasets(), tmp_path / "out.dat")
    assert list(tmp_path.iterdir()) == []


def test_every_shipped_data_file_has_its_recorded_sha256():
    """jointattention.data.SHA256 names every shipped data file, each with its sum."""
    from jointattention import data
    from jointattention._readers import sha256_of, shipped_path

    folder = Path(data.__file__).parent
    shipped = {p.name for p in folder.iterdir() if p.suffix in (".npz", ".tflite")}
    assert set(data.SHA256) == shipped
    for name, digest in data.SHA256.items():
        assert sha256_of(shipped_path(name)) == digest
