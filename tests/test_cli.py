"""The command line: help everywhere, the documented outputs, one-line errors."""

from __future__ import annotations

import re
import subprocess
import sys

import pytest

from jointattention.cli import build_parser, main

COMMANDS = [[], ["reproduce"], ["render"], ["datasets"], ["datasets", "make"],
            ["datasets", "check"], ["bench"], ["config"], ["sweep"], ["report"], ["parity"],
            ["detect"], ["gaze"]]


@pytest.mark.parametrize("command", COMMANDS, ids=lambda c: " ".join(c) or "top")
def test_every_command_has_help(command, capsys):
    """``--help`` works on every command and describes it."""
    with pytest.raises(SystemExit) as info:
        build_parser().parse_args([*command, "--help"])
    assert info.value.code == 0
    assert "usage: jointattention" in capsys.readouterr().out


def test_module_entry_point_runs():
    """``python -m jointattention --version`` works."""
    out = subprocess.run([sys.executable, "-m", "jointattention", "--version"],
                         capture_output=True, text=True, check=True).stdout
    assert out.startswith("jointattention ")


def test_render_writes_pictures(tmp_path, needs_gl):
    """``render`` writes the robot's view and the face-window sheet as PNGs."""
    assert main(["render", "--seed", "2", "--out", str(tmp_path)]) == 0
    for name in ("robot_view.png", "face_windows.png"):
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_datasets_make_then_check(tmp_path, needs_gl, capsys):
    """``datasets make`` writes a file that ``datasets check`` accepts."""
    out = tmp_path / "sets.npz"
    assert main(["datasets", "make", "--n", "4", "--seed", "1", "--quiet", str(out)]) == 0
    assert main(["datasets", "check", str(out)]) == 0
    assert "4 data sets, face windows 30x25" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["datasets", "check", "missing.npz"], "missing.npz: cannot read it (no such file"),
        (["render", "--config", "nonexistent"], "nonexistent: no such preset"),
        (["datasets", "make", "--n", "0", "x.npz"], "--n: 0: expected an integer in [1, 100000]"),
        (["sweep", "nospec.toml"], "nospec.toml: cannot read it (no such file or directory)"),
        (["report", "norun"], "norun: not a run folder"),
    ],
)
def test_bad_input_is_one_line_without_traceback(argv, message, tmp_path, monkeypatch):
    """User errors print one line naming the problem and exit with status 2."""
    monkeypatch.chdir(tmp_path)
    proc = subprocess.run([sys.executable, "-m", "jointattention", *argv],
                          capture_output=True, text=True)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], proc.stderr
    assert list(tmp_path.iterdir()) == []


def test_config_prints_toml_that_reads_back(tmp_path, capsys):
    """``config`` prints TOML that loads as the same configuration."""
    from jointattention.config import Config, load_config

    assert main(["config"]) == 0
    path = tmp_path / "c.toml"
    path.write_text(capsys.readouterr().out)
    assert load_config(path) == Config()


def test_reproduce_writes_figures_and_resumes(tmp_path, capsys):
    """``reproduce`` writes the figures and tables; a second call finds every cell done.

    On a tiny configuration: the figures, tables and trial table.
    """
    cfg = tmp_path / "tiny.toml"
    cfg.write_text(
        "[experiment]\nn_steps = 300\nn_seeds = 2\nbin_steps = 100\nn_ceiling_trials = 50\n"
        '[[experiment.conditions]]\nname = "n5-sigmoid"\nn_objects = 5\n'
        '[[experiment.conditions]]\nname = "n5-const1.0"\nn_objects = 5\n'
        'model = { gate = { kind = "constant", rate = 1.0 } }\n')
    out = tmp_path / "run"
    argv = ["reproduce", "--config", str(cfg), "--out", str(out), "--workers", "1"]
    assert main(argv) == 0
    for name in ("fig4a_success.png", "fig4b_gate.png", "fig5_gates.png", "table.md",
                 "table.csv", "ceilings.json", "config.toml", "versions.json",
                 "claims.md", "timing.json"):
        assert (out / name).exists(), name
    assert not (out / "trials.csv").exists()  # only on request: a large run's is a gigabyte
    assert "n5-const1.0" in (out / "table.md").read_text()
    capsys.readouterr()
    assert main([*argv, "--trials-csv"]) == 0
    captured = capsys.readouterr()
    assert "4 of 4 cells already done" in captured.out + captured.err
    assert (out / "trials.csv").read_text().startswith("condition,seed,trial,")


def test_reproduce_prints_a_short_summary_not_the_claims(tmp_path, capsys):
    """``reproduce`` ends with a few summary lines; the claims table stays in claims.md.

    The lines name the claims that hold, the folder's size, the figures, the tables and the
    report's command; the quick preset's smoke-run warning comes first.
    """
    from jointattention.config import load_config, to_toml

    text = to_toml(load_config("quick")).replace("n_steps = 60000", "n_steps = 400")
    text = text.replace("n_seeds = 3", "n_seeds = 2").replace("bin_steps = 5000",
                                                              "bin_steps = 100")
    cfg = tmp_path / "small.toml"
    cfg.write_text(text.replace("n_ceiling_trials = 2000", "n_ceiling_trials = 50"))
    out = tmp_path / "run"
    assert main(["reproduce", "--config", str(cfg), "--out", str(out), "--workers", "1"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) <= 8, lines
    assert not any(line.startswith("|") for line in lines)  # no table
    text = "\n".join(lines)
    assert re.search(r"\d+ of 24 claims hold \(the paper's \d+ of 17; this project's own "
                     r"targets \d+ of 7\)", text), text
    assert re.search(r"[0-9.]+ [kM]B on disk", text) and "fig4a_success.png" in text
    assert f"jointattention report {out}" in text


def test_the_quick_preset_says_it_is_a_smoke_run(tmp_path, capsys):
    """The quick preset's summary says it is a smoke run; a refused run prints none of it."""
    from jointattention.config import preset_about

    assert "smoke run" in preset_about("quick") and "fail" in preset_about("quick")
    assert main(["reproduce", "--preset", "quick", "--out", str(tmp_path / "run"),
                 "--max-cells", "1"]) == 2  # refused before any work
    captured = capsys.readouterr()
    assert "smoke run" not in captured.out + captured.err


def test_every_preset_has_a_one_line_summary_and_reproduce_lists_them(capsys):
    """Each preset's file opens with one summary line; ``reproduce --help`` names every preset."""
    from jointattention.config import preset_about, preset_names

    with pytest.raises(SystemExit):
        build_parser().parse_args(["reproduce", "--help"])
    helptext = " ".join(re.sub(r"-\n\s*", "-", capsys.readouterr().out).split())
    for name in preset_names():
        about = preset_about(name)
        assert about.endswith(".") and 20 <= len(about) <= 100, (name, about)
        assert name in helptext, name
    assert main(["config", "--list"]) == 0
    listed = capsys.readouterr().out.splitlines()
    assert [line.split()[0] for line in listed] == preset_names()


def test_bench_estimates_every_preset():
    """The wall-time estimate covers each preset at the rate of its engine, perception or learner.

    The rendered preset is scaled by the rendered rate only; the memory learner's cells (the
    beyond preset) by the memory rate, the reinforcement learner's (models) and the population
    learner's (generalise) by their own.
    """
    from jointattention.config import preset_names
    from jointattention.jobs.estimates import preset_estimates

    rates = {"compiled": 1e5, "python": 1e4, "rendered": 50.0, "memory": 1e4, "rl": 1e4,
             "population": 1e4}
    fast = preset_estimates({**rates, "compiled": 2e5, "memory": 2e4, "rl": 2e4,
                             "population": 2e4}, 2)
    slow = preset_estimates(rates, 2)
    assert [r[0].split(":")[0] for r in slow] == [f"preset {n}" for n in preset_names()]
    for (name, a, unit), (_, b, _) in zip(slow, fast, strict=True):
        expected = 1.0 if name.startswith("preset rendered") else 2.0
        assert unit == "min" and a == pytest.approx(expected * b) and a > 0
    beyond = dict((r[0].split(":")[0], r[1]) for r in slow)["preset beyond"]
    faster_memory = dict((r[0].split(":")[0], r[1]) for r in preset_estimates(
        {**rates, "memory": 2e4}, 2))["preset beyond"]
    assert faster_memory < beyond


def test_the_estimates_read_each_rate_by_its_row_s_name_wherever_it_is_printed():
    """agent_rates finds each kind's rate by its row's name: the bench's order does not matter."""
    from jointattention.jobs.bench import AGENT_RATE_ROWS
    from jointattention.jobs.estimates import agent_rates

    rows = [(name, float(i + 1), "steps/s") for i, name in enumerate(AGENT_RATE_ROWS.values())]
    expected = {kind: float(i + 1) for i, kind in enumerate(AGENT_RATE_ROWS)}
    extra = [("agent steps, rendered mode, another view", 7.0, "steps/s"), ("a ratio", 3.0, "x")]
    assert agent_rates(rows) == expected
    assert agent_rates(extra[:1] + rows[::-1] + extra[1:]) == expected
    with pytest.raises(KeyError):
        agent_rates(rows[1:])


def test_the_bench_writes_every_row_and_the_environments_table(tmp_path):
    """With --out the bench writes every row to bench.csv, the environments' rows as Markdown."""
    import csv

    from jointattention.jobs.bench import write_bench

    env = [("JointAttentionFace-v2 steps, one env (gym.make)", 81234.5, "steps/s"),
           ("one env / CartPole-v1 (aim: 0.5)", 0.6234, "x")]
    rows = [("render robot view (320x240, 5 objects)", 512.3, "frames/s"), *env]
    paths = write_bench(tmp_path / "out", rows, env, "jointattention bench --only environments")
    assert [p.name for p in paths] == ["bench.csv", "environments.md"]
    with open(paths[0], newline="") as f:
        back = list(csv.reader(f))
    assert back[0] == ["figure", "value", "unit"]
    assert [(n, float(v), u) for n, v, u in back[1:]] == rows  # 6 digits keep these
    table = paths[1].read_text()
    assert "| JointAttentionFace-v2 steps, one env (gym.make) | 81,234 steps/s |" in table
    assert "| one env / CartPole-v1 (aim: 0.5) | 0.62x |" in table
    assert "`jointattention bench --only environments`" in table
    (tmp_path / "out" / "environments.md").unlink()
    assert [p.name for p in write_bench(tmp_path / "out", rows[:1], [], "b")] == ["bench.csv"]


def test_paired_rates_time_two_forms_in_turns():
    """Each of two environments gets its steps/s, a vector's counting all its sub-environments."""
    gym = pytest.importorskip("gymnasium")
    from jointattention.jobs.env_bench import _paired_rates

    native = {"vectorization_mode": "vector_entry_point"}
    one, four = _paired_rates(gym.make("CartPole-v1"), gym.make_vec("CartPole-v1", 4, **native),
                              50, rounds=2)
    assert one > 0 and four > 0


def test_gaze_refuses_an_unknown_condition(capsys):
    """`gaze --condition` with a name the preset lacks: one line naming the choices."""
    assert main(["gaze", "--preset", "quick", "--condition", "n7", "--out", "/nonexistent"]) == 2
    err = capsys.readouterr().err
    assert "expected one of n1-sigmoid" in err and err.count("\n") == 1


def test_the_readme_commands_run_in_a_fresh_shell_after_its_activation_line():
    """The README activates .venv before its first command; then a new shell finds the command.

    The shell starts with an empty environment, as a new terminal would after ``make demo``.
    """
    from pathlib import Path

    readme = (Path(__file__).resolve().parent.parent / "README.md").read_text()
    activate = readme.index("\n. .venv/bin/activate")
    assert activate < readme.index("\njointattention ")  # before the first command line
    if sys.prefix == sys.base_prefix:
        pytest.skip("the tests run outside a venv")
    done = subprocess.run(
        ["env", "-i", "HOME=/tmp", "PATH=/usr/bin:/bin", "bash", "--noprofile", "--norc", "-c",
         f". {Path(sys.prefix) / 'bin' / 'activate'} && jointattention config --list"],
        capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("ablation ")


def test_reproduce_from_python_shows_the_cli_s_progress_when_asked(tmp_path, capsys):
    """``reproduce(progress=True)`` draws the cell bar and the phase lines on stderr.

    Anything else that is not a callable is refused before any file is written.
    """
    from jointattention import load_config, reproduce
    from jointattention.errors import JointAttentionError

    config = load_config({"experiment": {
        "n_steps": 200, "n_seeds": 1, "bin_steps": 100, "n_ceiling_trials": 20,
        "conditions": [{"name": "n3-sigmoid", "n_objects": 3}]}})
    with pytest.raises(JointAttentionError, match="progress"):
        reproduce(config, tmp_path / "refused", progress="yes")
    assert not (tmp_path / "refused").exists()
    result = reproduce(config, tmp_path / "run", progress=True)
    err = capsys.readouterr().err
    assert "cells" in err and "writing the tables and figures" in err
    assert result.summary().splitlines()[1].startswith(f"{sum(c.holds for c in result.claims)} "
                                                      f"of {len(result.claims)} claims hold")
