"""Configuration: defaults, validation with one clear error, presets and TOML round trips."""

from __future__ import annotations

import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from jointattention._fields import from_mapping
from jointattention.agent.gates import ConstantGate, SigmoidGate
from jointattention.config import (
    CameraConfig,
    ConditionConfig,
    Config,
    ExperimentConfig,
    WorldConfig,
    load_config,
    model_options,
    preset_names,
    to_toml,
)
from jointattention.errors import ConfigError
from jointattention.jobs.sweep import load_sweep
from jointattention.models.bootstrap import BootstrapOptions


def test_defaults_are_valid_and_match_the_paper():
    """The defaults build, with the paper's 30x25 face window."""
    cfg = Config()
    assert (cfg.world.face_window.width_px, cfg.world.face_window.height_px) == (30, 25)


def test_out_of_range_value_names_the_field():
    """A value outside its range raises ConfigError naming the field and the range."""
    with pytest.raises(ConfigError, match=r"fov_deg = 200.0: expected a value in \[5, 150\]"):
        CameraConfig(fov_deg=200.0)


def test_reversed_range_is_rejected():
    """A (low, high) pair given high first is an error naming the field."""
    with pytest.raises(ConfigError, match=r"head\.pan_limits_deg"):
        load_config_text("[world.head]\npan_limits_deg = [60, -60]\n")


def test_objects_must_be_nearer_than_the_caregiver():
    """Objects beyond the caregiver are refused (it could not turn to look at them)."""
    with pytest.raises(ConfigError, match="distance_range_m"):
        load_config_text("[world.objects]\ndistance_range_m = [0.5, 1.5]\n")


def test_unknown_key_and_wrong_type_are_errors(tmp_path):
    """Unknown settings and wrong types name the setting."""
    with pytest.raises(ConfigError, match=r"world\.camera\.fov: unknown setting"):
        load_config_text("[world.camera]\nfov = 40\n")
    with pytest.raises(ConfigError, match=r"world\.camera\.width_px = 'wide': expected int"):
        load_config_text('[world.camera]\nwidth_px = "wide"\n')


def test_bad_sources_are_errors(tmp_path):
    """A missing file, bad TOML and an unknown preset each give one ConfigError."""
    with pytest.raises(ConfigError, match="cannot read"):
        load_config(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("seed = = 3")
    with pytest.raises(ConfigError, match="not valid TOML"):
        load_config(bad)
    with pytest.raises(ConfigError, match="no such preset"):
        load_config("no-such-preset")


def test_presets_load():
    """Every shipped preset loads."""
    assert "default" in preset_names()
    for name in preset_names():
        assert isinstance(load_config(name), Config)


def test_the_rendered_preset_renders_its_view_as_fast_camera():
    """The rendered preset's camera is FAST_CAMERA's, as its bench row and docs name it."""
    from jointattention.world.options import FAST_CAMERA

    camera = load_config("rendered").world.camera
    assert {key: getattr(camera, key) for key in FAST_CAMERA} == dict(FAST_CAMERA)


@settings(max_examples=30, deadline=None)
@given(
    seed=st.integers(0, 2**31),
    fov=st.floats(20, 120),
    width=st.integers(32, 1024),
    n=st.integers(1, 12),
)
def test_toml_round_trip(tmp_path_factory, seed, fov, width, n):
    """A configuration written as TOML reads back equal."""
    cfg = Config(seed=seed, world=WorldConfig(camera=CameraConfig(fov_deg=fov, width_px=width)),
                 experiment=ExperimentConfig(conditions=(ConditionConfig(n_objects=n),)))
    path = tmp_path_factory.mktemp("cfg") / "c.toml"
    path.write_text(to_toml(cfg))
    assert load_config(path) == cfg


def test_a_condition_changes_the_run_model_field_by_field():
    """A condition's model table changes only what it names.

    A new gate kind starts from its own defaults; the same kind keeps the run's parameters.
    """
    cfg = load_config_text(
        "[model]\nlearning_rate = 0.001\n[model.gate]\nmidpoint_steps = 5000.0\n"
        "[[experiment.conditions]]\nname = 'c'\nn_objects = 3\n"
        "model = { gate = { kind = 'constant', rate = 0.7 }, vf_fallback = 'lm' }\n"
        "[[experiment.conditions]]\nname = 's'\nn_objects = 3\n"
        "model = { gate = { width_steps = 10.0 } }\n")
    c, s = (model_options(cfg, x) for x in cfg.experiment.conditions)
    assert c == BootstrapOptions(learning_rate=0.001, vf_fallback="lm", gate=ConstantGate(0.7))
    assert s.gate == SigmoidGate(midpoint_steps=5000.0, width_steps=10.0)
    assert load_config_text(to_toml(cfg)) == cfg


def test_bad_model_settings_name_the_field():
    """Bad model settings and duplicate condition names each give one error naming the field.

    An unknown gate kind, a rate out of range, an unknown model option and a duplicate condition
    name.
    """
    cases = [
        ("[model.gate]\nkind = 'step'\n", r"model\.gate\.kind = 'step': expected one of"),
        ("[[experiment.conditions]]\nname = 'a'\nmodel = { gate = { kind = 'constant', "
         "rate = 2.0 } }\n", r"experiment\.conditions\[0\]\.model\.gate\.rate = 2\.0"),
        ("[[experiment.conditions]]\nname = 'a'\nmodel = { n_hiden = 3 }\n",
         r"experiment\.conditions\[0\]\.model\.n_hiden: unknown setting"),
        ("[model]\nkind = 'nonesuch'\n", r"model\.kind = 'nonesuch': expected one of"),
        ("[[experiment.conditions]]\nname = 'a'\n[[experiment.conditions]]\nname = 'a'\n",
         r"experiment\.conditions\[1\]\.name = 'a': expected distinct"),
    ]
    for text, message in cases:
        with pytest.raises(ConfigError, match=message):
            load_config_text(text)


def test_non_finite_numbers_are_refused():
    """NaN and infinity fail the range checks with the field named."""
    with pytest.raises(ConfigError, match=r"model\.learning_rate = nan: expected a finite"):
        load_config_text("[model]\nlearning_rate = nan\n")
    with pytest.raises(ConfigError, match=r"world\.camera\.fov_deg = inf"):
        load_config_text("[world.camera]\nfov_deg = inf\n")


@settings(max_examples=60, deadline=None)
@given(
    names=st.lists(st.from_regex(r"[A-Za-z0-9][A-Za-z0-9_.,=+-]{0,11}", fullmatch=True),
                   min_size=1, max_size=3, unique=True),
    rate=st.floats(0, 1),
    lr=st.floats(1e-6, 1.0),
    kind=st.sampled_from(["sigmoid", "constant"]),
)
def test_conditions_round_trip_through_toml(names, rate, lr, kind):
    """Any safe condition names and model changes written as TOML read back equal."""
    gate = {"kind": kind, "rate": rate} if kind == "constant" else {"kind": kind}
    conditions = tuple(ConditionConfig(name=n, model={"gate": gate, "learning_rate": lr})
                       for n in names)
    cfg = Config(experiment=ExperimentConfig(conditions=conditions))
    assert load_config_text(to_toml(cfg)) == cfg


def test_configurations_of_version_0_1_still_load():
    """Version 0.1.0's configurations load as the same configuration in today's form.

    Gate and learning settings were in [agent] and in conditions; old run folders resume.
    """
    old = load_config_text(
        "[agent]\ngate_midpoint_steps = 25000.0\nlearning_rate = 0.001\ngate_rate = 0.8\n"
        "[[experiment.conditions]]\nname = 'c'\nn_objects = 5\ngate = 'constant'\n"
        "[[experiment.conditions]]\nname = 't'\nn_objects = 5\ngate_per = 'trial'\n")
    new = load_config_text(
        "[model]\nlearning_rate = 0.001\n[model.gate]\nmidpoint_steps = 25000.0\n"
        "[[experiment.conditions]]\nname = 'c'\nn_objects = 5\n"
        "model = { gate = { kind = 'constant', rate = 0.8 } }\n"
        "[[experiment.conditions]]\nname = 't'\nn_objects = 5\nmodel = { gate_per = 'trial' }\n")
    assert old == new


def test_strings_survive_the_toml_round_trip():
    """Quotes, backslashes, newlines and non-ASCII text in a string are written as valid TOML."""
    cfg = Config(datasets='a "b" \\ c\nd é\x7f')
    assert load_config_text(to_toml(cfg)) == cfg


@pytest.mark.parametrize("name", ["../../x", "/abs", "a/b", "a\nb", ".hidden", "", "x" * 81,
                                  "a b", "nul\x00", "é"])
def test_condition_names_that_are_not_safe_file_names_are_refused(name):
    """A condition name that could leave the run folder or break a file name is one error."""
    with pytest.raises(ConfigError, match=r"conditions\[0\]\.name = .*expected a name"):
        from_mapping(Config, {"experiment": {"conditions": [{"name": name}]}})


def load_config_text(text: str) -> Config:
    """The configuration of a TOML text."""
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / "c.toml"
        p.write_text(text)
        return load_config(p)


def test_loading_every_preset_imports_no_engine_and_no_world():
    """load_config loads no numba, MuJoCo, OpenCV or matplotlib, and of the world its options."""
    code = (
        "import sys\n"
        "from jointattention.config import load_config, preset_names\n"
        "for name in preset_names():\n"
        "    load_config(name)\n"
        "heavy = [m for m in ('numba', 'mujoco', 'cv2', 'matplotlib') if m in sys.modules]\n"
        "world = sorted(m for m in sys.modules if m.startswith('jointattention.world.'))\n"
        "assert not heavy, heavy\n"
        "assert world == ['jointattention.world.options', 'jointattention.world.variation']\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


def test_a_world_object_count_of_version_0_3_is_dropped_warning_if_it_mattered():
    """[world.objects] n_objects loads: 5 (every saved run has it) silently, 3 with a warning."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert load_config({"world": {"objects": {"n_objects": 5}}}) == load_config()
    with pytest.warns(DeprecationWarning, match="world.objects.n_objects = 3 is no longer read"):
        assert load_config({"world": {"objects": {"n_objects": 3}}}) == load_config()


DOCS = Path(__file__).resolve().parents[1] / "docs"
SWEEP_KEYS = {"base", "set", "grid", "conditions"}


@pytest.mark.parametrize("path", sorted(DOCS.rglob("*.toml")),
                         ids=lambda p: str(p.relative_to(DOCS)))
def test_every_configuration_and_sweep_spec_in_the_docs_loads(path):
    """Each TOML file under docs/ loads as the sweep spec or configuration its command takes."""
    if set(tomllib.loads(path.read_text())) <= SWEEP_KEYS:
        assert all(c.experiment.conditions for c in load_sweep(path).points.values())
    else:
        assert load_config(path).experiment.conditions
