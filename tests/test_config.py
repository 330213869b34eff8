"""Configuration: defaults, validation with one clear error, presets and TOML round trips."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from jointattention.config import (
    CameraConfig,
    Config,
    WorldConfig,
    load_config,
    preset_names,
    to_toml,
)
from jointattention.errors import ConfigError


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


@settings(max_examples=30, deadline=None)
@given(
    seed=st.integers(0, 2**31),
    fov=st.floats(20, 120),
    width=st.integers(32, 1024),
    n=st.integers(1, 12),
)
def test_toml_round_trip(tmp_path_factory, seed, fov, width, n):
    """A configuration written as TOML reads back equal."""
    cfg = Config(seed=seed, world=WorldConfig(
        camera=CameraConfig(fov_deg=fov, width_px=width),
        objects=WorldConfig().objects.__class__(n_objects=n),
    ))
    path = tmp_path_factory.mktemp("cfg") / "c.toml"
    path.write_text(to_toml(cfg))
    assert load_config(path) == cfg


def load_config_text(text: str) -> Config:
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / "c.toml"
        p.write_text(text)
        return load_config(p)
