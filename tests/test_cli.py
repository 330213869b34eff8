"""The command line: help everywhere, the documented outputs, one-line errors."""

from __future__ import annotations

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
                 "table.csv", "trials.csv", "ceilings.json", "config.toml", "versions.json",
                 "claims.md", "timing.json"):
        assert (out / name).exists(), name
    assert "n5-const1.0" in (out / "table.md").read_text()
    capsys.readouterr()
    assert main(argv) == 0
    captured = capsys.readouterr()
    assert "4 of 4 cells already done" in captured.out + captured.err


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


def test_gaze_refuses_an_unknown_condition(capsys):
    """`gaze --condition` with a name the preset lacks: one line naming the choices."""
    assert main(["gaze", "--preset", "quick", "--condition", "n7", "--out", "/nonexistent"]) == 2
    err = capsys.readouterr().err
    assert "expected one of n1-sigmoid" in err and err.count("\n") == 1
