"""Many caregivers: the data sets' caregiver field, recording K identities, learning from them."""

from __future__ import annotations

import csv
import dataclasses
import importlib.util
import subprocess
import sys
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

from jointattention.cli import main
from jointattention.config import WorldConfig, load_config
from jointattention.datasets import CaregiverDatasets, default_datasets, load, save
from jointattention.errors import DatasetError
from jointattention.experiment.cells import datasets_of, run_cell
from jointattention.world.recording import make_datasets, split_evenly

SCRIPT = Path(__file__).resolve().parents[1] / "scripts" / "caregivers.py"


@pytest.fixture(scope="module")
def four_people(gl_available) -> CaregiverDatasets:
    """Sixteen data sets posed by four caregivers (world seed 3)."""
    if not gl_available:
        pytest.skip("no off-screen OpenGL")
    return make_datasets(WorldConfig(), 16, seed=3, caregivers=4)


@pytest.fixture(scope="module")
def script():
    """scripts/caregivers.py as a module."""
    spec = importlib.util.spec_from_file_location("caregivers_script", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclass looks its module up
    try:
        spec.loader.exec_module(module)
        yield module
    finally:
        sys.modules.pop(spec.name, None)


def _small(caregiver=None) -> CaregiverDatasets:
    rng = np.random.default_rng(0)
    return CaregiverDatasets(rng.integers(0, 256, (6, 25, 30), dtype=np.uint8),
                             rng.uniform(-1, 1, (6, 2)), rng.uniform(-1, 1, (6, 2)),
                             rng.uniform(-1, 1, (6, 3)), {"note": "test"}, caregiver)


def _write(path, **arrays) -> None:
    base = {"schema_version": np.array(2), "face": np.zeros((3, 25, 30), np.uint8),
            "theta_face_rad": np.zeros((3, 2)), "command_rad": np.zeros((3, 2)),
            "caregiver": np.array([0, 1, 1])}
    base.update(arrays)
    np.savez(path, **{k: v for k, v in base.items() if v is not None})


def test_caregiver_field_round_trips_as_schema_version_2(tmp_path):
    """Data sets naming their caregivers save as version 2 and load back equal."""
    ds = _small(np.array([0, 0, 1, 1, 7, 7]))
    path = save(ds, tmp_path / "people.npz")
    assert int(np.load(path)["schema_version"]) == 2
    back = load(path)
    assert np.array_equal(back.caregiver, ds.caregiver) and back.n_caregivers == 3
    for key in ("face", "theta_face_rad", "command_rad", "target_m"):
        assert np.array_equal(getattr(back, key), getattr(ds, key))


def test_version_1_files_still_load(tmp_path):
    """The shipped version 1 file loads unchanged; data sets without caregivers save as 1."""
    with resources.as_file(resources.files("jointattention.data") / "caregiver_125.npz") as p, \
            np.load(p) as shipped:
        assert int(shipped["schema_version"]) == 1 and "caregiver" not in shipped
        face = shipped["face"]
    ds = default_datasets()
    assert len(ds) == 125 and ds.caregiver is None and ds.n_caregivers is None
    assert np.array_equal(ds.face, face)
    path = save(_small(), tmp_path / "one.npz")
    assert int(np.load(path)["schema_version"]) == 1
    assert load(path).caregiver is None


@pytest.mark.parametrize(
    ("arrays", "message"),
    [
        ({"caregiver": np.array([0.0, 1.0, 1.0])}, "field 'caregiver': expected integer array"),
        ({"caregiver": np.array([0, 1])}, r"field 'caregiver': expected integer array of shape "
                                          r"\(3,\)"),
        ({"caregiver": np.array([[0, 1, 1]])}, "field 'caregiver': expected integer array"),
        ({"caregiver": np.array([0, -1, 1])}, "field 'caregiver': expected identity indices "
                                              ">= 0, got -1"),
        ({"caregiver": np.array([True, False, True])}, "field 'caregiver': expected integer"),
        ({"caregiver": None}, "field 'caregiver' is missing; schema version 2"),
        ({"schema_version": np.array(1)}, "field 'caregiver' is not part of schema version 1 "
                                          r"\(it is a field of version 2\)"),
    ],
)
def test_malformed_caregiver_field_is_one_error_naming_it(tmp_path, arrays, message):
    """Each fault of the caregiver field is one DatasetError line naming the file and field."""
    path = tmp_path / "bad.npz"
    _write(path, **arrays)
    with pytest.raises(DatasetError, match=message) as info:
        load(path)
    assert str(path) in str(info.value) and "\n" not in str(info.value)


def test_in_memory_caregiver_field_is_checked():
    """CaregiverDatasets refuses a caregiver field of the wrong length or sign, naming it."""
    with pytest.raises(DatasetError, match="field 'caregiver'"):
        _small(np.array([0, 1, 2]))
    with pytest.raises(DatasetError, match="field 'caregiver': expected identity indices"):
        _small(np.array([0, 0, 0, -3, 1, 1]))


def test_split_is_even_and_contiguous():
    """N data sets split into K contiguous runs whose sizes differ by at most one."""
    who = split_evenly(10, 4)
    assert who.tolist() == [0, 0, 0, 1, 1, 1, 2, 2, 3, 3]
    assert np.bincount(split_evenly(2000, 16)).tolist() == [125] * 16


def test_k_caregivers_are_k_distinct_identities(four_people):
    """Four caregivers: four identities in the meta, and faces differ more across them."""
    ds = four_people
    assert ds.caregiver.tolist() == [0] * 4 + [1] * 4 + [2] * 4 + [3] * 4
    assert ds.n_caregivers == 4
    people = ds.meta["caregivers"]
    assert len(people) == 4 and len({repr(p) for p in people}) == 4
    f, c = ds.face.astype(float), ds.caregiver
    d = np.abs(f[:, None] - f[None]).mean(axis=(2, 3))
    same = d[(c[:, None] == c[None]) & ~np.eye(len(c), dtype=bool)]
    other = d[c[:, None] != c[None]]
    assert other.mean() > 1.15 * same.mean()


def test_one_caregiver_is_todays_recording(four_people, tmp_path):
    """K = 1 records exactly what was recorded before; identity 0 starts the same way."""
    today = make_datasets(WorldConfig(), 8, seed=3)
    one = make_datasets(WorldConfig(), 8, seed=3, caregivers=1)
    assert one.caregiver is None and one.meta == today.meta
    for key in ("face", "theta_face_rad", "command_rad", "target_m"):
        assert np.array_equal(getattr(one, key), getattr(today, key))
    assert np.array_equal(four_people.face[:4], today.face[:4])
    assert not np.array_equal(four_people.face[4:8], today.face[4:8])
    assert np.array_equal(make_datasets(WorldConfig(), 5, seed=0).face,
                          default_datasets().face[:5])
    a, b = tmp_path / "a.npz", tmp_path / "b.npz"
    assert main(["datasets", "make", "--n", "5", "--quiet", str(a)]) == 0
    assert main(["datasets", "make", "--n", "5", "--caregivers", "1", "--quiet", str(b)]) == 0
    assert a.read_bytes() == b.read_bytes()


def test_cli_records_and_checks_caregivers(tmp_path, needs_gl, capsys):
    """``datasets make --caregivers 3`` names three caregivers; ``check`` counts them."""
    out = tmp_path / "three.npz"
    assert main(["datasets", "make", "--n", "7", "--caregivers", "3", "--seed", "2", "--quiet",
                 str(out)]) == 0
    ds = load(out)
    assert ds.caregiver.tolist() == [0, 0, 0, 1, 1, 2, 2]
    assert main(["datasets", "check", str(out)]) == 0
    assert capsys.readouterr().out.strip().endswith(", 3 caregivers")


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--caregivers", "0"], "--caregivers: 0: expected an integer in [1, 1000]"),
        (["--caregivers", "1001"], "--caregivers: 1001: expected an integer in [1, 1000]"),
        (["--n", "2", "--caregivers", "3"], "--caregivers 3: expected at most --n (2)"),
    ],
)
def test_bad_caregiver_count_is_one_line(argv, message, tmp_path):
    """A caregiver count out of range is one error line, exit status 2 and no file."""
    proc = subprocess.run([sys.executable, "-m", "jointattention", "datasets", "make", *argv,
                           "x.npz"], capture_output=True, text=True, cwd=tmp_path)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], proc.stderr
    assert list(tmp_path.iterdir()) == []


def test_learning_from_several_caregivers_in_both_engines(four_people, tmp_path):
    """A run whose datasets file holds four caregivers learns alike in both engines."""
    path = save(four_people, tmp_path / "four.npz")
    cells = {}
    for engine in ("compiled", "python"):
        config = load_config({"datasets": str(path), "experiment": {
            "n_steps": 400, "bin_steps": 200, "engine": engine}})
        assert datasets_of(config).n_caregivers == 4
        cells[engine] = run_cell(config, config.experiment.conditions[0], 0)
    a, b = cells["compiled"], cells["python"]
    assert len(a["success"]) > 10
    assert np.all(np.isfinite(a["lm_error_deg"]))
    for key in a:
        assert np.array_equal(a[key], b[key], equal_nan=True), key


def test_caregivers_script_quick_mode(script, tmp_path, needs_gl, capsys):
    """scripts/caregivers.py --quick writes its table, CSV and plot; a re-run reuses records."""
    out, cache = tmp_path / "out", tmp_path / "cache"
    argv = ["--quick", "--out", str(out), "--cache", str(cache), "--setup", "paper",
            "--setup", "wide:n_hidden=12"]
    assert script.main(argv) == 0
    assert "recorded" in capsys.readouterr().out
    with open(out / "results.csv") as f:
        rows = list(csv.DictReader(f))
    assert [(r["setup"], r["K"], r["control"]) for r in rows] == [
        (s, k, c) for s in ("paper", "wide") for k, c in (("1", "False"), ("2", "False"),
                                                          ("1", "True"))]
    assert all(0 <= float(r["median_unseen_deg"]) <= 180 for r in rows)
    assert [r["n_datasets"] for r in rows[:3]] == ["6", "12", "12"]
    table = (out / "table.md").read_text()
    assert "| paper | 2 | 12 |" in table and "scripts/caregivers.py --quick" in table
    assert (out / "unseen.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    stamps = {p: p.stat().st_mtime_ns for p in cache.iterdir()}
    assert len(stamps) == 4  # held out, K = 1, K = 2, the one-identity control
    assert script.main([*argv, "--setup", "again:n_steps=200"]) == 0
    assert "recorded" not in capsys.readouterr().out
    assert {p: p.stat().st_mtime_ns for p in cache.iterdir()} == stamps


def test_caregivers_script_refuses_bad_setups(script, tmp_path, capsys):
    """A misspelt model option or a held-out seed equal to the training seed is refused."""
    base = ["--quick", "--out", str(tmp_path / "o"), "--cache", str(tmp_path / "c")]
    assert script.main([*base, "--setup", "x:n_hiden=3"]) == 2
    assert "n_hiden: unknown setting" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        script.main([*base, "--held-out-seed", "0"])
    assert not (tmp_path / "c").exists() and not (tmp_path / "o").exists()


def test_setups_parse_dotted_model_options(script):
    """A setup's dotted keys become nested [model] tables; n_steps is the learning time."""
    setup = script.parse_setup("const:gate.kind=constant,gate.rate=0.7,n_steps=5000", 300000)
    assert setup == script.Setup("const", 5000, {"gate": {"kind": "constant", "rate": 0.7}})
    config = script.cell_config(setup, Path("x.npz"))
    model = next(c for c in config.experiment.conditions if c.name == "n5-sigmoid").model
    assert model.to_dict() == {"gate": {"kind": "constant", "rate": 0.7}}
    assert config.experiment.n_steps == 5000 and config.datasets == "x.npz"
    assert dataclasses.replace(setup, model={}).changes == "n_steps=5000"
