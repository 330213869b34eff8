"""Saved models: the round trip, the refusals of malformed files, and reproduce --save-models."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from jointattention.cli import main
from jointattention.config import load_config
from jointattention.datasets import default_datasets, save, scenes_sha256
from jointattention.deploy.saved import Robot, load_model
from jointattention.errors import ConfigError, FileError
from jointattention.experiment.training import model_path, train
from jointattention.jobs.reproduce import run_experiment

TINY = {"seed": 3, "experiment": {"n_steps": 4000, "n_seeds": 2, "bin_steps": 1000,
                                  "n_ceiling_trials": 20,
                                  "conditions": [{"name": "n1", "n_objects": 1}]}}


@pytest.fixture(scope="module")
def saved(tmp_path_factory) -> tuple[object, Path]:
    """A model learned for 4000 steps, and the file it was saved to."""
    model = train(load_config(TINY), "n1", 1)
    path = tmp_path_factory.mktemp("model") / "m.npz"
    return model, model.save(path)


def _rewrite(src: Path, dst: Path, **changes) -> Path:
    """A copy of a model file with members replaced (None: removed)."""
    with np.load(src) as z:
        arrays = {k: z[k] for k in z.files}
    for key, value in changes.items():
        if value is None:
            arrays.pop(key)
        else:
            arrays[key] = value
    np.savez(dst, **arrays)
    return dst


def _meta(path: Path) -> dict:
    with np.load(path) as z:
        return json.loads(str(z["meta"]))


def test_round_trip_gives_the_same_commands(saved):
    """A loaded model commands exactly what the learned agent did, with its robot and steps.

    It keeps the digest of its data sets' scenes and who posed them.
    """
    model, path = saved
    loaded = load_model(path)
    ds = default_datasets()
    before = model.agent.lm_commands(ds.face, ds.theta_face_rad)
    after = loaded.agent.lm_commands(ds.face, ds.theta_face_rad)
    np.testing.assert_array_equal(before, after)
    assert loaded.robot == Robot.of(load_config(TINY))
    assert loaded.agent.learning_time_steps == model.agent.learning_time_steps >= 4000
    assert loaded.condition == "n1" and len(loaded.datasets_sha256) == 64
    assert loaded.scenes_sha256 == model.scenes_sha256 == scenes_sha256(ds)
    assert loaded.caregivers == model.caregivers and len(loaded.caregivers) == 1


def test_file_holds_no_pickle(saved):
    """Every member of the archive loads without pickle: loading it cannot run code."""
    _, path = saved
    with np.load(path, allow_pickle=False) as z:
        assert all(not z[k].dtype.hasobject for k in z.files)
        assert set(z.files) >= {"w1", "face_mean", "meta"}


def _cases(path: Path, tmp: Path):
    meta = _meta(path)
    robot_fov = {**meta, "robot": {**meta["robot"], "fov_deg": 55.0}}
    wrong_kind = {**meta, "model": {**meta["model"], "kind": "oracle"}}
    bad_config = {**meta, "config": "[[[ not toml"}
    bad_people = {**meta, "caregivers": ["big"]}
    return {
        "meta.caregivers[0]": _rewrite(path, tmp / "m.npz",
                                       meta=np.array(json.dumps(bad_people))),
        "schema_version": _rewrite(path, tmp / "a.npz", schema_version=np.array(9)),
        "w1": _rewrite(path, tmp / "b.npz", w1=np.zeros((3, 5))),
        "b2": _rewrite(path, tmp / "c.npz", b2=np.array([np.nan, 0.0])),
        "w2": _rewrite(path, tmp / "k.npz", w2=np.full_like(np.load(path)["w2"], 1e308)),
        "face_mean": _rewrite(path, tmp / "l.npz", face_mean=-np.load(path)["face_mean"] * 1e9),
        "face_m2": _rewrite(path, tmp / "d.npz", face_m2=None),
        "meta.robot.fov_deg": _rewrite(path, tmp / "e.npz",
                                       meta=np.array(json.dumps(robot_fov))),
        "meta.model.kind": _rewrite(path, tmp / "f.npz", meta=np.array(json.dumps(wrong_kind))),
        "meta.config": _rewrite(path, tmp / "g.npz", meta=np.array(json.dumps(bad_config))),
        "meta": _rewrite(path, tmp / "h.npz", meta=np.array("{not json")),
        "extra": _rewrite(path, tmp / "i.npz", extra=np.zeros(2)),
        "pickled": _rewrite(path, tmp / "j.npz", b1=np.array([{"a": 1}], dtype=object)),
    }


def test_malformed_files_are_refused_naming_the_field(saved, tmp_path):
    """Each malformed model file is one FileError line that names what is wrong."""
    _, path = saved
    for field, bad in _cases(path, tmp_path).items():
        with pytest.raises(FileError) as err:
            load_model(bad)
        message = str(err.value)
        assert "\n" not in message and str(bad) in message
        expected = {"pickled": "pickle", "extra": "'extra'"}.get(field, f"'{field}'")
        assert expected in message, (field, message)


def test_a_model_of_another_robot_is_refused(saved):
    """load_model(robot=...) refuses a model learned on another body, naming the field."""
    _, path = saved
    other = Robot.of(load_config({"world": {"camera": {"fov_deg": 60.0}}}))
    with pytest.raises(FileError, match=r"meta\.robot\.fov_deg"):
        load_model(path, robot=other)
    assert load_model(path, robot=Robot.of(load_config(TINY))).condition == "n1"


def test_models_that_are_not_saved_are_refused_before_learning():
    """Training refuses the memory learner at once, not after learning."""
    config = load_config({**TINY, "model": {"learner": "memory"}})
    with pytest.raises(ConfigError, match="learner = 'backprop'"):
        train(config, "n1")


def test_reproduce_saves_the_models_train_makes(saved, tmp_path):
    """With --save-models, reproduce writes each cell's model, equal to train's (2 workers)."""
    model, _ = saved
    config = load_config(TINY)
    run_experiment(config, tmp_path / "run", workers=2, save_models=True)
    path = model_path(tmp_path / "run" / "models", "n1", 1)
    again = load_model(path)
    np.testing.assert_array_equal(again.agent.learner.w1_, model.agent.learner.w1_)
    np.testing.assert_array_equal(again.agent.faces.mean_, model.agent.faces.mean_)
    assert model_path(tmp_path / "run" / "models", "n1", 0).is_file()


def test_a_resumed_run_saves_the_models_it_lacks(tmp_path):
    """Cells finished without --save-models are run again when the models are asked for."""
    config = load_config({**TINY, "experiment": {**TINY["experiment"], "n_seeds": 1}})
    run_experiment(config, tmp_path / "run")
    models = tmp_path / "run" / "models"
    assert not models.exists()
    run_experiment(config, tmp_path / "run", save_models=True)
    assert model_path(models, "n1", 0).is_file()


def test_cli_train_and_follow(saved, tmp_path, capsys, needs_gl):
    """The follow command prints one JSON line per image with a command, and writes the overlay."""
    import cv2

    from jointattention.world.simulator import World

    _, path = saved
    with World(load_config(TINY).world, seed=0) as world:
        world.reset()
        world.set_head_angle(world.face_angle_rad)
        theta_deg = np.rad2deg(world.face_angle_rad)
        cv2.imwrite(str(tmp_path / "view.png"), cv2.cvtColor(world.render(), cv2.COLOR_RGB2BGR))
    code = main(["follow", str(path), str(tmp_path / "view.png"), "--theta",
                 f"{theta_deg[0]:.3f},{theta_deg[1]:.3f}", "--out", str(tmp_path / "out")])
    assert code == 0
    record = json.loads(capsys.readouterr().out.strip())
    assert record["face"] is not None and record["face"]["score"] > 0.5
    x, y, w, h = record["face"]["box_px"]
    cx, cy = record["face"]["centre_px"]
    assert w > 0 and h > 0 and x <= cx <= x + w and y <= cy <= y + h
    assert np.hypot(*record["command_deg"]) == pytest.approx(load_config(TINY).agent.lm_step_deg,
                                                            abs=1e-3)  # rounded in the JSON
    assert (tmp_path / "out" / "view_follow.png").is_file()
    assert main(["follow", str(path), str(tmp_path / "view.png"), "--landmarks-only"]) == 0
    plain = json.loads(capsys.readouterr().out.strip())
    assert plain["face"]["centre_px"] != record["face"]["centre_px"]  # not refined
    video = cv2.VideoWriter(str(tmp_path / "v.avi"), cv2.VideoWriter_fourcc(*"MJPG"), 5,
                            (320, 240))
    for _ in range(3):
        video.write(cv2.imread(str(tmp_path / "view.png")))
    video.release()
    assert main(["follow", str(path), "--video", str(tmp_path / "v.avi"), "--theta",
                 f"{theta_deg[0]:.3f},{theta_deg[1]:.3f}"]) == 0
    lines = [json.loads(x) for x in capsys.readouterr().out.splitlines()]
    assert [x["frame"] for x in lines] == [0, 1, 2]
    assert all(x["face"] is not None and x["command_deg"] is not None for x in lines)


def test_cli_follow_refuses_bad_input_in_one_line(saved, tmp_path, capsys):
    """A bad model, angle or image is one error line, and no overlay is written."""
    _, path = saved
    (tmp_path / "junk.npz").write_bytes(b"PK not a zip")
    (tmp_path / "junk.png").write_bytes(b"\x89PNG\r\n\x1a\n broken")
    cases = [[str(tmp_path / "junk.npz"), str(tmp_path / "junk.png")],
             [str(path), str(tmp_path / "junk.png")],
             [str(path), str(tmp_path / "junk.png"), "--theta", "200,0"],
             [str(path), str(tmp_path / "junk.png"), "--min-score", "1.5"],
             [str(path)],
             [str(path), "--video", str(tmp_path / "junk.png")]]
    for args in cases:
        code = main(["follow", *args, "--out", str(tmp_path / "out")])
        err = capsys.readouterr().err
        assert code == 2 and err.count("\n") == 1 and "Traceback" not in err, err
        assert not (tmp_path / "out").exists()


def test_follow_on_a_damaged_video_prints_only_its_own_lines(saved, tmp_path, capfd):
    """A video cut in half gives the frames before the cut, and FFmpeg's complaints stay out."""
    import cv2

    _, path = saved
    noise = np.random.default_rng(0).integers(0, 256, (240, 320, 3), dtype=np.uint8)
    video = cv2.VideoWriter(str(tmp_path / "v.avi"), cv2.VideoWriter_fourcc(*"MJPG"), 5,
                            (320, 240))
    for _ in range(5):
        video.write(noise)
    video.release()
    data = (tmp_path / "v.avi").read_bytes()
    (tmp_path / "cut.avi").write_bytes(data[: len(data) // 2])
    assert main(["follow", str(path), "--video", str(tmp_path / "cut.avi")]) == 0
    out, err = capfd.readouterr()
    assert err == "" and 1 <= len(out.splitlines()) < 5


def test_follow_on_a_truncated_jpeg_is_one_line_without_libjpeg_noise(saved, tmp_path, capfd):
    """A JPEG cut in half: one error line on stderr, nothing from libjpeg, nothing written."""
    import cv2

    _, path = saved
    noise = np.random.default_rng(1).integers(0, 256, (240, 320, 3), dtype=np.uint8)
    data = cv2.imencode(".jpg", noise)[1].tobytes()
    (tmp_path / "cut.jpg").write_bytes(data[: len(data) // 2])
    assert main(["follow", str(path), str(tmp_path / "cut.jpg"), "--out",
                 str(tmp_path / "out")]) == 2
    out, err = capfd.readouterr()
    assert out == "" and err.count("\n") == 1 and "cut.jpg" in err, err
    assert not (tmp_path / "out").exists()


def test_follow_with_no_camera_is_one_clear_line(saved, capfd):
    """--camera N where there is none: one error line, and OpenCV's own lines stay out."""
    _, path = saved
    assert main(["follow", str(path), "--camera", "7"]) == 2
    out, err = capfd.readouterr()
    assert out == "" and err.count("\n") == 1 and "camera 7" in err, err


def test_closed_loop_runs_a_saved_model_through_images(saved, tmp_path, capsys, needs_gl):
    """The closed loop finds the face in every rendered start image and prints its table."""
    from jointattention.jobs.closed_loop import closed_loop

    model, path = saved
    before = model.agent.learner.w1_.copy()
    result = closed_loop(model, 1, 6, seed=1)
    assert result.faces_found == 1.0 and result.n_trials == 6
    for value in (result.rendered_success, result.rendered_box_face_success,
                  result.rendered_dataset_face_success, result.fast_success):
        assert 0 <= value <= 1
    assert 0 <= result.image_error_deg <= 180 and 0 <= result.dataset_error_deg <= 180
    np.testing.assert_array_equal(model.agent.learner.w1_, before)  # following learns nothing
    assert main(["closed-loop", str(path), "--objects", "1", "--trials", "2",
                 "--out", str(tmp_path / "cl.md")]) == 0
    assert "| 1 | 2 |" in (tmp_path / "cl.md").read_text()


def test_closed_loop_on_other_caregivers_shows_each_trials_caregiver(saved, needs_gl,
                                                                    monkeypatch):
    """--datasets of two unseen caregivers: each trial renders the one who posed its data set."""
    from jointattention.jobs import closed_loop as cl
    from jointattention.world.recording import HELD_OUT, caregivers_of, make_datasets

    model, _ = saved
    ds = make_datasets(model.config.world, 4, 0, caregivers=2, stream=HELD_OUT)
    people = [repr(c) for c in caregivers_of(ds, model.config.world)]
    shown = []
    real_show = cl.RenderedScenes.show

    def show(self, fast, face_m):
        shown.append(repr(self.world.caregiver))
        return real_show(self, fast, face_m)

    monkeypatch.setattr(cl.RenderedScenes, "show", show)
    result = cl.closed_loop(model, 1, 6, seed=2, datasets=ds)
    assert result.n_trials == 6 and result.faces_found == 1.0
    assert len(shown) == 18 and set(shown) == set(people)  # both, and no one else


def test_a_wrong_window_or_angle_is_refused_before_the_kernels(saved):
    """lm_command refuses windows of another size or type and bad angles; nothing crashes.

    Run in a subprocess: a kernel reading past its arrays would end it with a signal.
    """
    import subprocess
    import sys

    _, path = saved
    code = f"""
import numpy as np
from jointattention.deploy.saved import load_model
from jointattention.errors import ArgumentError
m = load_model({str(path)!r})
w, h = m.robot.face_size_px
cases = [(np.zeros((1000, 1000)), (0, 0)), (np.zeros((40, 40)), (0, 0)),
         (np.zeros((10, 10)), (0, 0)), (np.zeros((h, w, 3)), (0, 0)),
         (np.full((h, w), np.nan), (0, 0)), (np.zeros((h, w), object), (0, 0)),
         (np.zeros((h, w)), (np.nan, 0)), (np.zeros((h, w)), (0, 0, 0)), (np.zeros((h, w)), "ab")]
for window, theta in cases:
    try:
        m.lm_command(window, theta)
        print("accepted")
    except ArgumentError as err:
        print("refused", str(err).split(":")[0])
print("ok", np.hypot(*m.lm_command(np.zeros((h, w), np.uint8), (0.1, -0.1))) > 0)
"""
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=600)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    assert lines[:6] == ["refused face_window"] * 6
    assert lines[6:9] == ["refused theta_rad"] * 3 and lines[9] == "ok True"


def test_a_model_s_data_sets_are_found_beside_it_and_checked_by_content(tmp_path,
                                                                        monkeypatch):
    """model_datasets: beside the model file first; the same scenes re-rendered are taken.

    Other scenes are refused, and a model file of before (no scenes digest) takes only the
    same bytes.

    (closed-loop loads the model's data sets through it.)
    """
    import shutil

    from jointattention.datasets import shipped_file
    from jointattention.experiment.training import model_datasets

    folder = tmp_path / "robot"
    folder.mkdir()
    shutil.copy(shipped_file(), folder / "sets.npz")
    monkeypatch.chdir(folder)
    config = load_config({**TINY, "datasets": "sets.npz",
                          "experiment": {**TINY["experiment"], "n_steps": 1000}})
    path = train(config, "n1").save(folder / "m.npz")
    monkeypatch.chdir(tmp_path)  # elsewhere: "sets.npz" is only beside the model
    model = load_model(path)
    assert len(model_datasets(model, path)) == len(default_datasets())
    shipped = default_datasets()
    # The same scenes rendered on another machine: a few grey levels apart, other bytes.
    save(dataclasses.replace(shipped, face=shipped.face ^ np.uint8(1),
                             theta_face_rad=shipped.theta_face_rad + 1e-13), folder / "sets.npz")
    assert np.array_equal(model_datasets(model, path).face, shipped.face ^ np.uint8(1))
    old = dataclasses.replace(model, scenes_sha256=None)  # a model file of before: the bytes
    with pytest.raises(FileError, match="other content"):
        model_datasets(old, path)
    save(dataclasses.replace(shipped, command_rad=shipped.command_rad[::-1].copy()),
         folder / "sets.npz")
    with pytest.raises(FileError, match="other scenes"):
        model_datasets(model, path)


def test_a_developmental_model_that_would_end_blurred_is_refused_before_learning(capsys):
    """train: n_steps below blur_sharp_steps is one error line before any learning.

    (train saves nothing: only a check made before learning can refuse it.)
    """
    config = {**TINY, "experiment": {**TINY["experiment"], "n_steps": 1_000_000, "conditions": [
        {"name": "dev", "n_objects": 1,
         "model": {"kind": "developmental", "blur_sharp_steps": 2_000_000}}]}}
    with pytest.raises(ConfigError, match=r"blur_sharp_steps = 2e\+06"):
        train(load_config(config), "dev")


@pytest.mark.parametrize("min_score", [float("nan"), 1.5, -2, "0.5", True])
def test_a_follower_refuses_a_min_score_that_is_not_a_correlation(saved, min_score):
    """GazeFollower(min_score=...) outside [-1, 1] (NaN would disable the face check): refused."""
    from jointattention.deploy.follower import GazeFollower
    from jointattention.errors import ArgumentError

    with pytest.raises(ArgumentError, match="min_score"):
        GazeFollower.load(saved[1], min_score=min_score)


def test_a_model_s_recorded_data_sets_are_recorded_again_with_progress(tmp_path, needs_gl,
                                                                       monkeypatch):
    """On a machine without them, model_datasets records them once, saying how far it is."""
    from jointattention.experiment.training import model_datasets

    monkeypatch.setenv("JOINTATTENTION_CACHE", str(tmp_path / "here"))
    config = load_config({**TINY, "recording": {"caregivers": 2, "poses_per_caregiver": 3,
                                                "seed": 1},
                          "experiment": {**TINY["experiment"], "n_steps": 1000,
                                         "held_out": {"n_trials": 10, "n_checkpoints": 1}}})
    model = train(config, "n1")
    monkeypatch.setenv("JOINTATTENTION_CACHE", str(tmp_path / "elsewhere"))  # a new machine
    counts = []
    assert len(model_datasets(model, progress=counts.append)) == 6 and counts[-1] == 6
    model_datasets(model, progress=counts.append)
    assert len(counts) == 6  # kept: not recorded again


ROBOT_DOCS = Path(__file__).resolve().parents[1] / "docs" / "results" / "robot"


def _drawn_again(shipped: Path, tmp_path: Path, *args: str) -> tuple[np.ndarray, str]:
    """camera_view.py ``args`` run again: its frame's difference from ``shipped``, its stdout."""
    import subprocess
    import sys

    import cv2

    drawn = tmp_path / f"view{shipped.suffix}"
    said = subprocess.run([sys.executable, str(ROBOT_DOCS / "camera_view.py"), str(drawn), *args],
                          check=True, capture_output=True, text=True, timeout=300).stdout
    return np.abs(cv2.imread(str(drawn)).astype(int) - cv2.imread(str(shipped)).astype(int)), said


def _follows(model: Path, frame: Path, tmp_path: Path, capsys, *args: str) -> None:
    """``follow model frame args`` finds a face, prints a command and writes its overlay."""
    assert main(["follow", str(model), str(frame), *args, "--out", str(tmp_path / "follow")]) == 0
    record = json.loads(capsys.readouterr().out.strip())
    assert record["face"]["score"] > 0.5 and record["command_deg"] is not None
    assert (tmp_path / "follow" / f"{frame.stem}_follow.png").is_file()


def test_the_readme_follow_command_finds_the_face_in_the_shipped_frame(tmp_path, capsys,
                                                                       needs_gl):
    """The README's follow command, on the shipped camera_view.png, finds a face and a command.

    The frame is what docs/results/robot/camera_view.py draws (the same bytes where the renderer is
    this machine's; compared as an image elsewhere, to a few grey levels).
    """
    frame = ROBOT_DOCS / "camera_view.png"
    diff, _ = _drawn_again(frame, tmp_path)
    assert np.mean(diff) < 2.0
    _follows(ROBOT_DOCS.parent / "generalise" / "population_n10.npz", frame, tmp_path, capsys)


def test_the_people_model_follows_in_the_shipped_fovea_frame(tmp_path, capsys, needs_gl):
    """The shipped people-world model reads face and eyes in fovea_view_people.jpg: a command.

    camera_view.py --people draws the frame (compared as an image, to a few grey levels) and
    names the head angle that follow --theta takes.
    """
    frame = ROBOT_DOCS / "fovea_view_people.jpg"
    diff, said = _drawn_again(frame, tmp_path, "--people")
    assert diff.shape == (960, 1280, 3) and np.mean(diff) < 2.0
    theta = said.split("follow ")[1].split()[0]
    _follows(ROBOT_DOCS.parent / "people" / "sockets_net_n10.npz", frame, tmp_path, capsys,
             theta)


SHIPPED_MODEL = (Path(__file__).resolve().parents[1] / "docs" / "results" / "generalise"
                 / "population_n10.npz")
RECORD_SCENES = """
import json, sys
import numpy as np
from jointattention.datasets import scenes_sha256
from jointattention.deploy.saved import load_model
from jointattention.world import recording
from jointattention.world.simulator import World

model = load_model(sys.argv[1])
world, r = model.config.world, model.config.recording
few = recording.make_datasets(world, 6, r.seed, caregivers=3)  # rendered, as recorded
out = {"few": scenes_sha256(few), "few_faces": few.face.tolist()}
if sys.argv[2] == "all":  # the binding is of scenes alone: the images are left black here
    shape = (world.camera.height_px, world.camera.width_px, 3)
    World.render = lambda self: np.zeros(shape, np.uint8)
    every = recording.make_datasets(world, r.caregivers * r.poses_per_caregiver, r.seed,
                                    caregivers=r.caregivers)
    out["all"] = scenes_sha256(every)
print(json.dumps(out))
"""


def _record_scenes(env: dict[str, str], which: str) -> dict:
    """RECORD_SCENES run in a fresh process with ``env`` added to this one's environment."""
    import os
    import subprocess
    import sys

    src = str(Path(__file__).resolve().parents[1] / "src")
    proc = subprocess.run([sys.executable, "-c", RECORD_SCENES, str(SHIPPED_MODEL), which],
                          capture_output=True, text=True, timeout=600,
                          env={**os.environ, "PYTHONPATH": src, **env})
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(proc.stdout.splitlines()[-1])


def test_the_shipped_model_binds_to_data_sets_recorded_in_another_environment(needs_gl):
    """Recordings in processes of other threads, hash seeds and locales bind alike.

    The scenes digest of a few caregivers agrees between the two, and the shipped model's
    training scenes, drawn again in the second, are those it recorded (issue 61: the bytes of
    a recording differ between machines, its scenes must not).
    """
    first = _record_scenes({"OMP_NUM_THREADS": "1", "PYTHONHASHSEED": "0", "LC_ALL": "C",
                            "MUJOCO_GL": "egl"}, "few")
    second = _record_scenes({"OMP_NUM_THREADS": "2", "PYTHONHASHSEED": "4242",
                             "LC_ALL": "C.UTF-8", "TZ": "Pacific/Auckland",
                             "MUJOCO_GL": "egl"}, "all")
    assert first["few"] == second["few"]
    # the faces are rendered, not hashed: near alike (another OpenGL may differ a little)
    faces = [np.array(r["few_faces"], np.int16) for r in (first, second)]
    assert faces[0].shape == faces[1].shape and np.abs(faces[0] - faces[1]).mean() < 8
    assert second["all"] == load_model(SHIPPED_MODEL).scenes_sha256
