"""Sweeps: the spec, identical results on every backend, and resuming after an interrupt."""

from __future__ import annotations

import numpy as np
import pytest

from jointattention.errors import ConfigError
from jointattention.experiment import results
from jointattention.jobs.sweep import load_sweep, run_sweep

SPEC = """
base = "quick"
[set]
"experiment.n_seeds" = 2
"experiment.n_steps" = 500
"experiment.bin_steps" = 100
[grid]
"model.learning_rate" = [0.0003, 0.003]
"model.n_hidden" = [3]
[[conditions]]
name = "n3"
n_objects = 3
"""


def _spec(tmp_path, text=SPEC):
    path = tmp_path / "spec.toml"
    path.write_text(text)
    return path


def _cells(out):
    return {p.relative_to(out): results.load_cell(p) for p in sorted(out.rglob("*.npz"))}


def _same(a, b):
    assert a.keys() == b.keys()
    for k in a:
        for col in a[k]:
            assert np.array_equal(a[k][col], b[k][col]), (k, col)


def test_spec_makes_the_grid_product(tmp_path):
    """Each grid point is the base with the set and grid values applied."""
    sweep = load_sweep(_spec(tmp_path))
    assert list(sweep.points) == ["learning_rate=0.0003,n_hidden=3",
                                  "learning_rate=0.003,n_hidden=3"]
    cfg = sweep.points["learning_rate=0.003,n_hidden=3"]
    assert cfg.model.learning_rate == 0.003 and cfg.model.n_hidden == 3
    assert cfg.experiment.n_seeds == 2 and [c.name for c in cfg.experiment.conditions] == ["n3"]


def test_grid_values_given_by_name_name_their_points(tmp_path):
    """A table of values by name sets each value (a whole section too) and names the point."""
    sweep = load_sweep(_spec(tmp_path, SPEC.replace(
        '"model.n_hidden" = [3]',
        '"world.eye_window" = { face = { width_px = 0, height_px = 0 }, '
        'eyes = { width_px = 24, height_px = 8 } }')))
    assert list(sweep.points) == [f"learning_rate={r},eye_window={w}"
                                  for r in ("0.0003", "0.003") for w in ("face", "eyes")]
    cfg = sweep.points["learning_rate=0.003,eye_window=eyes"]
    assert cfg.world.eye_window.width_px == 24 and cfg.world.eye_window.height_px == 8
    assert not sweep.points["learning_rate=0.003,eye_window=face"].world.eye_window.enabled
    assert sweep.values["learning_rate=0.003,eye_window=eyes"] == (0.003, "eyes")


@pytest.mark.parametrize(("text", "match"), [
    ('base = "quick"\nseeds = 3\n', "seeds: unknown key"),
    ('[grid]\n"model.learning_rate" = 0.1\n', "expected a non-empty list"),
    ('[grid]\n"model.learning_rate" = {}\n', "or a table of values by name"),
    ('[grid]\n"model.learning_rat" = [0.1]\n', "learning_rat: unknown setting"),
    ('[grid]\n"agnt.learning_rate" = [0.1]\n', "no section 'agnt'"),
    ('[set]\n"model.n_hidden" = "many"\n', "expected int"),
    ("[grid\n", "not valid TOML"),
])
def test_bad_specs_are_refused(tmp_path, text, match):
    """A bad spec raises one ConfigError naming the setting and what was expected."""
    with pytest.raises(ConfigError, match=match):
        load_sweep(_spec(tmp_path, text))


def test_local_and_ray_backends_give_identical_cells(tmp_path):
    """One process, two worker processes and local Ray write identical cells.

    And the same summary.
    """
    sweep = load_sweep(_spec(tmp_path))
    serial = run_sweep(sweep, tmp_path / "serial", workers=1)
    run_sweep(sweep, tmp_path / "pool", workers=2)
    on_ray = run_sweep(sweep, tmp_path / "ray", workers=2, backend="ray")
    _same(_cells(tmp_path / "serial"), _cells(tmp_path / "pool"))
    _same(_cells(tmp_path / "serial"), _cells(tmp_path / "ray"))
    assert serial == on_ray and len(serial) == 2
    assert (tmp_path / "ray" / "summary.md").read_text() == \
        (tmp_path / "serial" / "summary.md").read_text()


def test_an_interrupted_sweep_resumes_without_loss(tmp_path):
    """An interrupted sweep keeps its cells and resumes without loss.

    Interrupted after two cells, the re-run does only the other two and ends with the same cells as
    an uninterrupted sweep.
    """
    sweep = load_sweep(_spec(tmp_path))
    done = []

    def interrupt(message):
        if not message.endswith("already done"):
            done.append(message)
            if len(done) == 2:
                raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_sweep(sweep, tmp_path / "half", progress=interrupt)
    assert len(_cells(tmp_path / "half")) == 2
    assert not list((tmp_path / "half").rglob("*.tmp*"))  # nothing half-written
    messages = []
    run_sweep(sweep, tmp_path / "half", progress=messages.append)
    assert messages[0] == "2 of 4 cells already done" and len(messages) == 3
    run_sweep(sweep, tmp_path / "whole")
    _same(_cells(tmp_path / "half"), _cells(tmp_path / "whole"))


def test_unknown_backend_and_stray_address_are_refused(tmp_path):
    """--backend must be local or ray, and --address goes with Ray only."""
    sweep = load_sweep(_spec(tmp_path))
    with pytest.raises(ConfigError, match="expected one of local, ray"):
        run_sweep(sweep, tmp_path / "x", backend="dask")
    with pytest.raises(ConfigError, match="expected --backend ray"):
        run_sweep(sweep, tmp_path / "y", address="10.0.0.1:6379")
    assert not (tmp_path / "x").exists() and not (tmp_path / "y").exists()
