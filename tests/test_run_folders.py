"""One run per folder: the lock, concurrent runs, and a start that was killed."""

from __future__ import annotations

import subprocess
import sys

import pytest

from jointattention import run_experiment
from jointattention._files import LOCK_NAME, folder_lock
from jointattention.cli import main
from jointattention.config import ConditionConfig, Config, ExperimentConfig, to_toml
from jointattention.errors import FileError

SMALL = Config(experiment=ExperimentConfig(
    n_steps=400, n_seeds=1, conditions=(ConditionConfig(name="a", n_objects=3),)))


def test_a_second_run_into_a_held_folder_is_refused_and_writes_nothing(tmp_path, capsys):
    """While one run holds the folder, another (API or CLI) is refused in one line."""
    out = tmp_path / "run"
    (tmp_path / "c.toml").write_text(to_toml(SMALL))
    with folder_lock(out):
        with pytest.raises(FileError, match="another run is writing into this folder"):
            run_experiment(SMALL, out)
        assert main(["reproduce", "--config", str(tmp_path / "c.toml"), "--out",
                     str(out)]) == 2
        assert sorted(p.name for p in out.iterdir()) == [LOCK_NAME]
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "another run is writing into this folder" in err[0]
    run_experiment(SMALL, out)  # the lock ends with its holder
    assert (out / "cells" / "a__seed000.npz").is_file()


def test_two_concurrent_runs_into_one_folder_one_is_refused(tmp_path):
    """Two reproduce processes started together into one new folder: exactly one runs."""
    cfg = tmp_path / "c.toml"
    cfg.write_text(to_toml(Config(experiment=ExperimentConfig(
        n_steps=60000, n_seeds=2, conditions=(ConditionConfig(name="a", n_objects=3),)))))
    argv = [sys.executable, "-m", "jointattention", "reproduce", "--config", str(cfg), "--out",
            str(tmp_path / "run"), "--workers", "1"]
    procs = [subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                              text=True) for _ in range(2)]
    codes = sorted(p.wait(600) for p in procs)
    errors = [p.stderr.read() for p in procs]
    assert codes == [0, 2], errors
    assert any("another run is writing into this folder" in e for e in errors)


def test_a_killed_start_and_stale_temporary_files_do_not_block_the_folder(tmp_path):
    """A folder holding only versions.json and a writer's .tmp file is taken as new."""
    out = tmp_path / "run"
    out.mkdir()
    (out / "versions.json").write_text("{}")
    (out / ".table.csv.abc123.tmp").write_text("half")
    run_experiment(SMALL, out)
    assert (out / "config.toml").is_file() and not list(out.glob(".*.tmp"))


def test_trials_csv_is_what_the_csv_module_writes(tmp_path):
    """trials.csv, written by a compiled loop, equals csv.writer's rows (quoting, signs, CR LF)."""
    import csv

    import numpy as np

    from jointattention.experiment.results import write_trials_csv
    from jointattention.experiment.trial import RECORD

    rng = np.random.default_rng(0)
    cells = {}
    for name, seed, n in (('odd, "name"', 3, 50), ("plain", 0, 0), ("plain", 12, 7)):
        cells[(name, seed)] = {k: rng.integers(-3, 10**12 if t is np.int64 else 90, n).astype(t)
                               for k, (t, _) in RECORD.items()}
    path = write_trials_csv(tmp_path, cells)
    with open(tmp_path / "expected.csv", "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(("condition", "seed", "trial", *RECORD))
        for (name, seed), rec in sorted(cells.items()):
            for i, row in enumerate(zip(*[rec[c].astype(int) for c in RECORD], strict=True)):
                writer.writerow((name, seed, i, *row))
    assert path.read_bytes() == (tmp_path / "expected.csv").read_bytes()


def test_an_output_written_by_another_command_is_refused_and_freed_after(tmp_path):
    """output_lock: one holder per path (however spelt); released, it leaves no file."""
    from jointattention._files import _lock_file, output_lock

    out = tmp_path / "table.md"
    (tmp_path / "alias").symlink_to(tmp_path)  # the same place by another name
    with output_lock(out):
        with (pytest.raises(FileError, match="another command is writing it"),
              output_lock(tmp_path / "alias" / "table.md")):
            pass
        with output_lock(tmp_path / "other.md"):  # another path: its own lock
            pass
    assert not _lock_file(out).exists()
    with output_lock(out):  # free again
        pass
    assert not out.exists()


def test_writes_follow_a_link_and_never_replace_a_fifo(tmp_path):
    """A link's target is written (the link stays); a FIFO is refused before and at writing."""
    import os

    from jointattention._files import check_writable, write_text

    (tmp_path / "real.md").write_text("old")
    (tmp_path / "link.md").symlink_to("real.md")
    check_writable(tmp_path / "link.md", "file")
    write_text(tmp_path / "link.md", "new")
    assert (tmp_path / "link.md").is_symlink() and (tmp_path / "real.md").read_text() == "new"
    os.mkfifo(tmp_path / "f.md")
    for call in (lambda: check_writable(tmp_path / "f.md", "file"),
                 lambda: write_text(tmp_path / "f.md", "x")):
        with pytest.raises(FileError, match="a FIFO"):
            call()
    assert not (tmp_path / "f.md").is_file()
    with pytest.raises(FileError, match="empty path"):
        check_writable("", "folder")
