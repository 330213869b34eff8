"""Every file reader, fed hostile content: a documented error or a valid result, nothing else."""

from __future__ import annotations

import io
import itertools
import json

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import jointattention as ja
from jointattention._readers import read_json
from jointattention.errors import JointAttentionError
from jointattention.jobs.sweep import load_sweep

SETTINGS = settings(max_examples=60, deadline=None,
                    suppress_health_check=[HealthCheck.function_scoped_fixture,
                                           HealthCheck.too_slow])
_names = itertools.count()

# the members a model or data-set file has, with hostile arrays in them
MEMBERS = ("schema_version", "face", "theta_face_rad", "command_rad", "target_m", "meta", "w1",
           "b1", "w2", "b2", "face_mean", "face_m2", "face_n_seen", "caregiver")
ARRAYS = st.one_of(
    st.integers(-3, 10).map(np.array),
    st.floats(allow_nan=True, allow_infinity=True).map(np.array),
    st.text(max_size=40).map(np.array),
    st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=12).map(
        lambda v: np.array(v, dtype=float)),
    st.tuples(st.integers(0, 3), st.integers(0, 6), st.integers(0, 6)).map(
        lambda s: np.zeros(s, np.uint8)),
)
ARCHIVES = st.dictionaries(st.sampled_from(MEMBERS), ARRAYS, max_size=8)


def _npz(arrays: dict) -> bytes:
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    return buf.getvalue()


def _write(tmp, suffix: str, data: bytes | str):
    path = tmp / f"f{next(_names)}{suffix}"
    if isinstance(data, bytes):
        path.write_bytes(data)
    else:
        path.write_text(data, encoding="utf-8")
    return path


def _documented(call) -> None:
    """Run ``call``: a result, or one JointAttentionError line; any other exception fails."""
    try:
        call()
    except JointAttentionError as err:
        assert "\n" not in str(err)


@pytest.fixture(scope="module")
def tmp(tmp_path_factory):
    """A folder for this module's generated files."""
    return tmp_path_factory.mktemp("fuzz")


@given(content=st.one_of(st.binary(max_size=300), ARCHIVES.map(_npz)))
@SETTINGS
def test_a_hostile_model_file_is_refused_in_one_line(tmp, content):
    """load_model on random bytes or random archives of its members' names."""
    _documented(lambda: ja.load_model(_write(tmp, ".npz", content)))


@given(content=st.one_of(st.binary(max_size=300), ARCHIVES.map(_npz)))
@SETTINGS
def test_a_hostile_data_set_file_is_refused_in_one_line(tmp, content):
    """load_datasets on random bytes or random archives of its members' names."""
    _documented(lambda: ja.load_datasets(_write(tmp, ".npz", content)))


TOML_ISH = st.one_of(
    st.text(max_size=200),
    st.recursive(st.one_of(st.integers(), st.floats(), st.text(max_size=10), st.booleans()),
                 lambda inner: st.one_of(st.lists(inner, max_size=3),
                                         st.dictionaries(st.text(max_size=8), inner,
                                                         max_size=3)),
                 max_leaves=20).map(lambda v: f"x = {json.dumps(v)}\n"),
)


@given(text=TOML_ISH)
@SETTINGS
def test_a_hostile_configuration_file_is_refused_in_one_line(tmp, text):
    """load_config on random text and TOML-like text."""
    _documented(lambda: ja.load_config(_write(tmp, ".toml", text)))


@given(text=TOML_ISH)
@SETTINGS
def test_a_hostile_sweep_spec_is_refused_in_one_line(tmp, text):
    """load_sweep on random text and TOML-like text."""
    _documented(lambda: load_sweep(_write(tmp, ".toml", text)))


@given(text=st.one_of(st.text(max_size=200), st.recursive(
    st.one_of(st.integers(), st.floats(), st.text(max_size=10), st.none()),
    lambda inner: st.one_of(st.lists(inner, max_size=3),
                            st.dictionaries(st.text(max_size=8), inner, max_size=3)),
    max_leaves=30).map(json.dumps)))
@SETTINGS
def test_a_hostile_run_folder_json_is_refused_in_one_line(tmp, text):
    """read_json (versions.json, ceilings.json, ...) on random and JSON-like text."""
    _documented(lambda: read_json(_write(tmp, ".json", text), "a run folder's JSON"))


CSV_CELLS = st.one_of(st.text(max_size=12), st.floats(allow_nan=True).map(str),
                      st.sampled_from(["img.png", "../x.png", "", "nan", "1e308", "-4"]))


@given(header=st.lists(st.sampled_from(["image", "pan_rad", "tilt_rad", "command_pan_rad",
                                        "command_tilt_rad", "caregiver", "x"]), max_size=7),
       rows=st.lists(st.lists(CSV_CELLS, max_size=7), max_size=4))
@SETTINGS
def test_a_hostile_recording_table_is_refused_in_one_line(tmp, header, rows):
    """import_recording on a folder whose recording.csv is random columns and values."""
    folder = tmp / f"rec{next(_names)}"
    folder.mkdir()
    (folder / "recording.csv").write_text(
        "\n".join(",".join(r) for r in [header, *rows]) + "\n", encoding="utf-8")
    _documented(lambda: ja.import_recording(folder))
