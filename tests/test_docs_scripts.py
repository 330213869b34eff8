"""Every script under docs/ runs, small, and writes its output, so none rots unseen.

Each test runs one script in a subprocess in its quick mode (``--quick``, or a short run to
read), writing into a temporary folder; none may touch the files the manual includes. The
guard at the end lists every ``docs/**/*.py``: each is run here, run by another test file, or
excluded with its reason.
"""

from __future__ import annotations

import ast
import dataclasses
import fcntl
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"

# Scripts under docs/ that another test file runs, and that file.
RUN_ELSEWHERE = {
    "results/people/head_pose_bound.py": "test_people_docs.py",
    "results/people/ladder.py": "test_people_docs.py",
    "results/people/novelty.py": "test_people_docs.py",
    "results/people/record.py": "test_people_docs.py",
    "results/people/robustness.py": "test_people_docs.py",
    "results/people/socket_net.py": "test_socket_net.py",
    "results/people/taught_bound.py": "test_people_docs.py",
    "results/people/taught_closed_loop.py": "test_people_docs.py",
    "results/robot/camera_view.py": "test_saved_models.py",
}
# Scripts under docs/ that no test runs, and why.
NOT_RUN = {
    "griffe_roles.py": "a griffe extension, not a script: mkdocs.yml loads it and `make docs` "
                       "(mkdocs build --strict) runs it on every docstring",
}


def _run(script: str, *args: str | Path, cwd: Path, env: dict | None = None) -> str:
    """Run docs/``script`` with ``args`` from ``cwd``; its stdout. No file beside it changes."""
    folder = (DOCS / script).parent
    before = {p: p.stat().st_mtime_ns for p in folder.iterdir() if p.is_file()}
    proc = subprocess.run([sys.executable, str(DOCS / script), *map(str, args)], cwd=cwd,
                          capture_output=True, text=True, timeout=600,
                          env=None if env is None else {**os.environ, **env})
    assert proc.returncode == 0, proc.stderr
    after = {p: p.stat().st_mtime_ns for p in folder.iterdir() if p.is_file()}
    assert after == before, f"{script} changed the files beside it"
    return proc.stdout


def _rows(path: Path, start: str) -> list[str]:
    """The table rows of a Markdown file that start with ``start``."""
    return [r for r in path.read_text().splitlines() if r.startswith(start)]


def _short_run(out: Path, engine: str = "compiled", trials_csv: bool = False) -> Path:
    """A short run of the models preset into ``out``: two conditions, 2 seeds, 2,000 steps."""
    from jointattention.config import load_config
    from jointattention.jobs.reproduce import reproduce

    models = load_config("models")
    small = load_config({"experiment": {"held_out": {"n_trials": 20, "n_checkpoints": 1}}})
    conditions = tuple(c for c in models.experiment.conditions
                       if c.name in ("paper-n5", "developmental-n5"))
    experiment = dataclasses.replace(models.experiment, n_steps=2000, n_seeds=2, bin_steps=1000,
                                     n_ceiling_trials=100, conditions=conditions, engine=engine,
                                     held_out=small.experiment.held_out)
    reproduce(dataclasses.replace(models, experiment=experiment), out, trials_csv=trials_csv)
    return out


@pytest.fixture(scope="session")
def short_run(tmp_path_factory, worker_id) -> Path:
    """A short compiled run of the models preset, with its trials.csv: one for all workers."""
    root = tmp_path_factory.getbasetemp()
    root = root if worker_id == "master" else root.parent  # the workers' common folder
    run, done = root / "docs-scripts-run" / "models", root / "docs-scripts-run.done"
    with open(root / "docs-scripts-run.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # the first worker runs it; the others wait, then read
        if not done.exists():
            _short_run(run, trials_csv=True)
            done.touch()
    return run


def test_evidence_writes_a_row_per_cell_and_checkpoint(tmp_path):
    """beyond/evidence.py --quick: 4 cells x 2 checkpoints, each with a share of faces right."""
    out = tmp_path / "evidence.md"
    _run("results/beyond/evidence.py", "--quick", "--out", out, cwd=tmp_path)
    rows = _rows(out, "| memory")
    assert len(rows) == 8
    assert all(0 <= float(r.split("|")[4]) <= 1 for r in rows)


def test_mean_vs_mode_writes_its_table_and_figure(tmp_path):
    """beyond/mean_vs_mode.py --quick: a row per object count, and the figure beside it."""
    out = tmp_path / "mean_vs_mode.md"
    _run("results/beyond/mean_vs_mode.py", "--quick", "--out", out, cwd=tmp_path)
    assert [r.split("|")[1].strip() for r in _rows(out, "| ")[1:]] == ["3", "5", "10"]
    assert out.with_suffix(".png").read_bytes()[:4] == b"\x89PNG"


def test_module_alone_writes_a_row_per_module(tmp_path):
    """beyond/module_alone.py --quick: the four modules, two checkpoints each."""
    out = tmp_path / "module_alone.md"
    _run("results/beyond/module_alone.py", "--quick", "--out", out, cwd=tmp_path)
    rows = _rows(out, "| ")[1:]
    assert [r.split("|")[1].strip() for r in rows] == [
        "paper", "memory", "memory, 32 neighbours", "population"]
    assert all(len(r.split("|")) == 6 for r in rows)


def test_saccade_ceiling_prints_both_ceilings(tmp_path):
    """beyond/saccade_ceiling.py --quick: the oracle stepping and moving far, at 5 and 10."""
    out = tmp_path / "ceiling.md"
    printed = _run("results/beyond/saccade_ceiling.py", "--quick", "--out", out, cwd=tmp_path)
    rows = _rows(out, "| 5 |") + _rows(out, "| 10 |")
    assert len(rows) == 2 and rows[0] in printed
    assert all(0 < float(c) <= 1 for r in rows for c in r.split("|")[2:4])


def test_saccade_trials_reads_a_run_s_trials(short_run, tmp_path):
    """beyond/saccade_trials.py on a short run's trials.csv: a row per condition."""
    printed = _run("results/beyond/saccade_trials.py", short_run / "trials.csv", cwd=tmp_path)
    assert {r.split("|")[1].strip() for r in printed.splitlines()
            if r.startswith("| ") and "-n5" in r} == {"paper-n5", "developmental-n5"}


def test_speed_summary_writes_a_row_per_condition_of_each_group(tmp_path):
    """beyond/speed_summary.py on the shipped learning_speed.csv: each group's rows, in order."""
    out = tmp_path / "speed_summary.md"
    _run("results/beyond/speed_summary.py", "--out", out, cwd=tmp_path)
    sys.path.insert(0, str(DOCS / "results" / "beyond"))
    try:
        from speed_summary import GROUPS
    finally:
        sys.path.pop(0)
    rows = [r.split("|")[1].strip() for r in _rows(out, "| memory")]
    assert rows == [name for conditions in GROUPS.values() for name in conditions]
    assert out.read_text() == (DOCS / "results" / "beyond" / "speed_summary.md").read_text()


def test_stuck_faces_writes_a_row_per_face_or_none(tmp_path):
    """beyond/stuck_faces.py --quick for one seed: rows of both conditions."""
    out = tmp_path / "stuck_faces.md"
    _run("results/beyond/stuck_faces.py", "7", "--quick", "--out", out, cwd=tmp_path)
    assert {r.split("|")[1].strip() for r in _rows(out, "| memory")} == {
        "memory-evidence-quick-leave-n10", "memory-evidence-quick-pass-n10"}


def test_wrong_recalls_writes_both_tables(tmp_path):
    """beyond/wrong_recalls.py --quick for one seed: three evidence bands, one wrong row."""
    out = tmp_path / "wrong_recalls.md"
    _run("results/beyond/wrong_recalls.py", "2", "--quick", "--out", out, cwd=tmp_path)
    rows = _rows(out, "| 2 |")
    assert len(rows) == 4
    assert [r.split("|")[2].strip() for r in rows[:3]] == ["0-1.5", "1.5-3", "3-inf"]


def test_compare_engines_finds_the_engines_byte_identical(short_run, tmp_path):
    """engines/compare_engines.py on short runs of both engines: every cell byte-identical."""
    python = _short_run(tmp_path / "models-python", engine="python")
    out = tmp_path / "engines.md"
    _run("results/engines/compare_engines.py", short_run, python, "--out", out, cwd=tmp_path)
    assert "4 of 4 cells are byte-identical" in out.read_text()
    assert len(_rows(out, "| paper-n5 |")) == 1


def test_calibrate_fits_a_calibration(tmp_path, needs_gl):
    """faces/calibrate.py --quick fits and saves a calibration from a few hundred views."""
    from jointattention.agent.face_calibration import Calibration

    out = tmp_path / "calibration.npz"
    _run("results/faces/calibrate.py", out, "--quick", cwd=tmp_path)
    assert Calibration.load(out).meta["views"] == 640


def test_photos_draws_the_five_photographs(tmp_path):
    """faces/photos.py: the follower's looks at five photographs, four with a face."""
    out = tmp_path / "photos.png"
    printed = _run("results/faces/photos.py", "--out", out, cwd=tmp_path)
    lines = printed.splitlines()
    assert sum(r.startswith("face") for r in lines) == 4 and lines.count("no face None") == 1
    assert out.read_bytes()[:4] == b"\x89PNG"


def test_caregivers_table_reads_a_run_s_held_out_measures(short_run, tmp_path):
    """generalise/caregivers.py on a short run: a row per condition, fractions of ceilings."""
    out = tmp_path / "caregivers.md"
    _run("results/generalise/caregivers.py", "--sweep", tmp_path, "--run", short_run, "--out", out,
         cwd=tmp_path)
    rows = _rows(out, "| paper-n5 |") + _rows(out, "| developmental-n5 |")
    assert len(rows) == 2 and all("nan" not in r for r in rows)


def test_summarise_writes_a_row_per_point_and_condition(short_run, tmp_path):
    """learn-fast/summarise.py on a short run as a one-point sweep: speed and held-out columns."""
    out = tmp_path / "ablation.md"
    _run("results/learn-fast/summarise.py", short_run.parent, "--out", out, cwd=tmp_path)
    rows = _rows(out, "| models | ")
    assert [r.split("|")[2].strip() for r in rows] == ["paper-n5", "developmental-n5"]
    # the novelty (last column) is NaN here: the models preset learns from the shipped sets
    assert all("nan" not in r.rsplit("|", 2)[0] and "(" in r.split("|")[7] for r in rows)


def test_summarise_with_ceilings_gives_the_success_its_fraction_is_of(short_run, tmp_path):
    """--ceilings adds the unseen success and its ceiling, whose ratio is the fraction shown."""
    out = tmp_path / "capture.md"
    _run("results/learn-fast/summarise.py", short_run.parent, "--out", out, "--ceilings",
         cwd=tmp_path)
    assert "their ceiling |" in out.read_text().splitlines()[0]
    for row in _rows(out, "| models | "):
        cells = [c.strip() for c in row.split("|")[1:-1]]
        fraction, success, ceiling = float(cells[6].split()[0]), float(cells[10]), float(cells[11])
        assert 0 < ceiling <= 1 and success == pytest.approx(fraction * ceiling, abs=2e-3)


def test_summarise_names_a_missing_cell_in_one_line(short_run, tmp_path):
    """learn-fast/summarise.py on a sweep with a cell missing: one error line, nothing written."""
    point = tmp_path / "sweep" / short_run.name
    shutil.copytree(short_run, point)
    next(iter(sorted((point / "cells").glob("*.npz")))).unlink()
    out = tmp_path / "ablation.md"
    proc = subprocess.run([sys.executable, str(DOCS / "results/learn-fast/summarise.py"),
                           str(point.parent), "--out", str(out)], cwd=tmp_path,
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert "cannot read it" in proc.stderr.splitlines()[-1] and not out.exists()


def test_fresh_measures_a_saved_model_on_fresh_caregivers(tmp_path, needs_gl):
    """generalise/fresh.py --quick on the shipped model: a row per set, a summary, its command."""
    models = tmp_path / "models"
    models.mkdir()
    shipped = DOCS / "results" / "generalise" / "population_n10.npz"
    (models / "shipped-10-0.npz").symlink_to(shipped)
    out = tmp_path / "fresh.md"
    _run("results/generalise/fresh.py", "--quick", "--models", models, "--objects", "10",
         "--training-seeds", "1", "--files", "shipped-{n}-{i}.npz", "--held-out-seeds", "2026",
         "--out", out, cwd=tmp_path, env={"JOINTATTENTION_CACHE": str(tmp_path / "cache")})
    rows = _rows(out, "| population-n10 |")
    assert len(rows) == 2 and all("nan" not in r for r in rows)
    assert rows[0].count("|") == 12  # with the novelty column
    assert "--files shipped-{n}-{i}.npz --held-out-seeds 2026" in out.read_text()  # its command


def test_fresh_records_the_caregivers_of_another_world(tmp_path, needs_gl):
    """fresh.py --world: the model among another world's caregivers, newer than its own."""
    models = tmp_path / "models"
    models.mkdir()
    (models / "m-10-0.npz").symlink_to(DOCS / "results" / "generalise" / "population_n10.npz")
    novelty = []
    for world in ([], ["--world", "people"]):
        out = tmp_path / f"fresh{len(world)}.md"
        _run("results/generalise/fresh.py", "--quick", "--models", models, "--objects", "10",
             "--training-seeds", "1", "--files", "m-{n}-{i}.npz", "--held-out-seeds", "2026",
             *world, "--out", out, cwd=tmp_path,
             env={"JOINTATTENTION_CACHE": str(tmp_path / "cache")})
        novelty.append(float(_rows(out, "| population-n10 |")[0].split("|")[-2].split(",")[0]))
    assert "--world people" in out.read_text()
    assert novelty[1] > 2 * novelty[0]  # the people world's caregivers lie far from its own


def test_fresh_refuses_an_unknown_world_before_recording(tmp_path):
    """fresh.py --world NAME that is no preset or file: one line naming it, nothing written."""
    out = tmp_path / "fresh.md"
    proc = subprocess.run([sys.executable, str(DOCS / "results/generalise/fresh.py"),
                           "--world", "no-such-world", "--out", str(out)], cwd=tmp_path,
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert "--world" in proc.stderr.splitlines()[-1] and not out.exists()


def test_lookup_writes_a_row_per_kind_of_face(tmp_path):
    """generalise/lookup.py --quick: training, new poses and unseen caregivers' rows."""
    out = tmp_path / "lookup.md"
    _run("results/generalise/lookup.py", "--quick", "--out", out, cwd=tmp_path)
    assert [r.split("|")[1].strip() for r in _rows(out, "| ")[1:]] == [
        "training", "new poses", "unseen caregivers"]


def test_eye_placement_writes_a_row_per_placement(tmp_path):
    """people/eye_placement.py --quick: each placement error, BlazeFace's and the follower's."""
    out = tmp_path / "eye_placement.md"
    _run("results/people/eye_placement.py", "--quick", "--out", out, "--models",
         tmp_path / "models", cwd=tmp_path)
    placed = [r.split("|")[3].strip() for r in _rows(out, "| ")[1:]]
    assert placed == [f"{sd:g} eye distances" for sd in (0, 0.01, 0.02, 0.03, 0.05, 0.08, 0.1)
                      ] + ["BlazeFace's eye landmarks, 4x view",
                           "BlazeFace's eye landmarks, a second look at the face",
                           "the gaze follower on the 4x view (face found and cut by BlazeFace "
                           "too)"]
    assert (tmp_path / "models" / "placement_sd_0_quick.npz").exists()


def test_axes_writes_a_row_per_condition_and_the_figure(tmp_path):
    """models/axes.py --quick: six conditions, both axes' errors, and axes.png beside."""
    out = tmp_path / "axes.md"
    _run("results/models/axes.py", "--quick", "--out", out, cwd=tmp_path)
    assert len(_rows(out, "| ")[1:]) == 6
    assert out.with_suffix(".png").read_bytes()[:4] == b"\x89PNG"


def test_errors_reads_a_run_s_diagnostics(short_run, tmp_path):
    """models/errors.py on a short run, at its own bins: a row per condition, no NaN."""
    out = tmp_path / "errors.md"
    _run("results/models/errors.py", short_run, "--times", "1000", "2000", "--out", out,
         cwd=tmp_path)
    rows = _rows(out, "| paper-n5 |") + _rows(out, "| developmental-n5 |")
    assert len(rows) == 2 and all("nan" not in r for r in rows)


def test_compare_modes_checks_a_rendered_run_against_the_fast_mode(tmp_path, needs_gl):
    """rendered/compare_modes.py on a short rendered run: its row, table and figure."""
    from jointattention.config import load_config
    from jointattention.jobs.reproduce import reproduce

    rendered = load_config("rendered")
    small = load_config({"experiment": {"held_out": {"n_trials": 20, "n_checkpoints": 1}}})
    experiment = dataclasses.replace(rendered.experiment, n_steps=600, n_seeds=1, bin_steps=300,
                                     n_ceiling_trials=100, held_out=small.experiment.held_out,
                                     conditions=rendered.experiment.conditions[:1])
    run = tmp_path / "rendered"
    reproduce(dataclasses.replace(rendered, experiment=experiment), run)
    out = tmp_path / "modes.md"
    _run("results/rendered/compare_modes.py", run, "--fast-seeds", "2", "--out", out, cwd=tmp_path)
    assert len(_rows(out, f"| {experiment.conditions[0].name} | ")) == 1
    assert out.with_suffix(".png").read_bytes()[:4] == b"\x89PNG"


@pytest.mark.rl
def test_ppo_defaults_writes_its_table_curves_and_figure(tmp_path):
    """rl/ppo_defaults.py --quick: a row per learner and environment, the CSV and the figure."""
    pytest.importorskip("stable_baselines3", reason="needs the rl extra: make test-rl")
    _run("results/rl/ppo_defaults.py", "--quick", "--out", tmp_path, cwd=tmp_path)
    assert len(_rows(tmp_path / "ppo_defaults.md", "| PPO")) == 5
    assert len(_rows(tmp_path / "ppo_defaults.md", "| own RL")) == 2
    assert (tmp_path / "ppo_defaults.csv").read_text().startswith("learner,environment")
    assert (tmp_path / "ppo_defaults.png").read_bytes()[:4] == b"\x89PNG"


def _run_here() -> set[str]:
    """The scripts this file runs: the first argument of each ``_run`` call in it."""
    tree = ast.parse(Path(__file__).read_text())
    return {node.args[0].value for node in ast.walk(tree)
            if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "_run"
            and isinstance(node.args[0], ast.Constant)}


def test_every_docs_script_is_run_or_excluded_with_a_reason():
    """Each docs/**/*.py is run here, run by the test file named, or excluded with a reason."""
    scripts = {p.relative_to(DOCS).as_posix() for p in DOCS.rglob("*.py")}
    here = _run_here()
    assert not here & (set(RUN_ELSEWHERE) | set(NOT_RUN))
    covered = here | set(RUN_ELSEWHERE) | set(NOT_RUN)
    assert not scripts - covered, f"neither run by a test nor excluded: {sorted(scripts - covered)}"
    assert not covered - scripts, f"no such script: {sorted(covered - scripts)}"
    for script, test_file in RUN_ELSEWHERE.items():
        assert Path(script).name in (ROOT / "tests" / test_file).read_text(), script
    assert all(len(reason) > 20 for reason in NOT_RUN.values())
