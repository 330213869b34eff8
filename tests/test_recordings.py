"""Recorded folders: import, the robot's round trip, and malformed folders refused in one line."""

from __future__ import annotations

import importlib.util
import shutil
from pathlib import Path

import numpy as np
import pytest

from jointattention.agent.faces import face_window
from jointattention.cli import main
from jointattention.config import load_config
from jointattention.errors import FileError
from jointattention.head_recording import import_recording

EXAMPLE = Path(__file__).parent.parent / "examples" / "recorded_head.py"


def _example():
    spec = importlib.util.spec_from_file_location("recorded_head", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def recording(tmp_path_factory, gl_available):
    """A recording of 12 caregiver poses and 2 views away, with the true face windows."""
    if not gl_available:
        pytest.skip("no off-screen OpenGL (EGL or OSMesa) on this machine")
    from jointattention.world.recording import face_box
    from jointattention.world.simulator import World

    folder = tmp_path_factory.mktemp("rec") / "recording"
    world = World(load_config().world, seed=0)
    true_windows = []
    with world:
        original = world.render

        def render():  # keep the window the data sets' own function cuts, for comparison
            image = original()
            true_windows.append(face_window(image, *face_box(world), (30, 25)))
            return image

        world.render = render
        rows = _example().record(world, folder, 12)
    return folder, rows, np.array(true_windows)


@pytest.mark.parametrize(("face", "most"), [("blazeface", 12), ("template", 8)])
def test_import_finds_the_faces_and_reports_the_rest(recording, face, most):
    """Every caregiver view is imported, near the data sets' own window; views away are listed."""
    folder, rows, true_windows = recording
    ds, missed = import_recording(folder, face=face)
    assert [m.row for m in missed] == [13, 14]
    assert len(ds) == 12 and ds.meta["rows_without_face"] == [13, 14]
    np.testing.assert_allclose(ds.theta_face_rad[:, 0], [r["pan_rad"] for r in rows[:12]])
    diff = np.abs(ds.face.astype(float) - true_windows[:12]).mean()
    assert diff < most, diff  # grey levels; a window of another place differs by about 40


def test_cli_import_writes_a_valid_file_and_warns(recording, tmp_path, capsys):
    """The import command writes a loadable data-set file and names the rows left out."""
    folder, _, _ = recording
    out = tmp_path / "sets.npz"
    assert main(["datasets", "import", str(folder), "--out", str(out), "--quiet"]) == 0
    captured = capsys.readouterr()
    assert "12 of 14 rows imported; 2 without a face" in captured.out
    assert "row 13 (img_0012.png): no face found" in captured.err
    assert main(["datasets", "check", str(out)]) == 0


def test_import_keeps_who_the_caregiver_is(recording, tmp_path):
    """An optional caregiver column becomes the data sets' caregiver field (schema 2)."""
    folder, _, _ = recording
    lines = (folder / "recording.csv").read_text().splitlines()
    copy = tmp_path / "two"
    shutil.copytree(folder, copy)
    (copy / "recording.csv").write_text("\n".join(
        [lines[0] + ",caregiver"] + [f"{x},{i % 2}" for i, x in enumerate(lines[1:])]) + "\n")
    ds, _ = import_recording(copy)
    assert ds.caregiver.tolist() == [i % 2 for i in range(12)]


def test_datasets_cut_by_the_robots_finder(needs_gl):
    """--cut finder: windows cut around the found face, close to the head box's, all found."""
    from jointattention.world.recording import make_datasets

    box = make_datasets(load_config().world, 6, 0)
    found = make_datasets(load_config().world, 6, 0, cut="finder")
    assert len(found) == 6 and found.meta["without_face"] == []
    np.testing.assert_array_equal(found.command_rad, box.command_rad)
    diff = np.abs(found.face.astype(float) - box.face).mean()
    assert 0 < diff < 12, diff  # the same faces, cut a little differently (another place: ~40)


def _broken(folder: Path, tmp: Path) -> dict[str, Path]:
    """Copies of the recording, each broken in one way, and what the error must name."""
    cases = {}

    def copy(name: str, csv_text: str | None = None, **files: bytes) -> Path:
        dst = tmp / name
        shutil.copytree(folder, dst)
        if csv_text is not None:
            (dst / "recording.csv").write_text(csv_text)
        for file, data in files.items():
            (dst / file).write_bytes(data)
        return dst

    text = (folder / "recording.csv").read_text()
    header, first, *_ = text.splitlines()
    cases["'command_tilt_rad' is missing"] = copy(
        "a", text.replace(",command_tilt_rad", ""))
    cases["column 'colour' is unknown"] = copy("b", header + ",colour\n" + first + ",red\n")
    cases["row 1: column 'pan_rad' 'abc'"] = copy(
        "c", header + "\n" + first.replace(first.split(",")[1], "abc", 1) + "\n")
    cases["in [-pi, pi]"] = copy(
        "d", header + "\n" + first.replace(first.split(",")[2], "7.5", 1) + "\n")
    cases["'../x.png'"] = copy("e", header + "\n../x.png" + first[first.index(","):] + "\n")
    cases["is not a file"] = copy("f", header + "\nnope.png" + first[first.index(","):] + "\n")
    cases["corrupt image"] = copy("g", None, **{"img_0000.png": b"\x89PNG\r\n\x1a\nbroken"})
    cases["no rows"] = copy("h", header + "\n")
    cases["recording.csv"] = tmp / "empty_folder"
    cases["recording.csv"].mkdir()
    cases["no face found in any"] = copy("i", header + "\n" + text.splitlines()[-1] + "\n")
    cases["column 'caregiver' '-1'"] = copy("j", header + ",caregiver\n" + first + ",-1\n")
    cases["column 'image' is named twice"] = copy("k", header + "," + header + "\n" + first + ","
                                                  + first + "\n")
    cases["not a readable CSV table"] = copy("l", header + "\n" + first + ',"' + "x" * 200_000
                                             + '"\n')
    return cases


def test_malformed_folders_are_one_line_and_write_nothing(recording, tmp_path, capsys):
    """Each broken recording folder is one error line naming the problem; no file is written."""
    folder, _, _ = recording
    for expected, bad in _broken(folder, tmp_path).items():
        out = tmp_path / f"{bad.name}.npz"
        code = main(["datasets", "import", str(bad), "--out", str(out), "--quiet"])
        err = capsys.readouterr().err
        assert code == 2 and err.count("\n") == 1 and expected in err, (expected, err)
        assert not out.exists()
    with pytest.raises(FileError, match="not a folder"):
        import_recording(tmp_path / "missing")


def test_robot_round_trip_learns_to_follow(tmp_path, needs_gl):
    """Record, import, learn, save, load and follow: the learned poses are followed."""
    result = _example().main(["--poses", "30", "--test-poses", "10", "--steps", "8000",
                              "--out", str(tmp_path)])
    assert result["rows"] == 32 and result["imported"] == 30  # the 2 views away left out
    assert result["learned_poses"]["no_face"] == 0
    # 8000 steps on 30 poses: about 17 deg measured; chance is 90 deg
    assert result["learned_poses"]["median_error_deg"] < 35
    assert (tmp_path / "model.npz").is_file()


def test_the_closed_loop_shows_who_posed_the_data_sets(recording):
    """A robot's recording names no simulated caregiver: the closed loop shows the seed's own."""
    from jointattention.datasets import default_datasets
    from jointattention.jobs.closed_loop import caregivers_shown

    folder, _, _ = recording
    ds, _ = import_recording(folder)
    assert caregivers_shown(ds, load_config().world) is None
    shipped = caregivers_shown(default_datasets(), load_config().world)
    assert shipped is not None and len(shipped) == 1
