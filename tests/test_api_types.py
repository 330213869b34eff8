"""The Python API refuses arguments of the wrong type with one named error, as the CLI does."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import jointattention as ja
from jointattention.errors import ArgumentError

CONFIG = ja.load_config("quick")

# anything but a path (str or os.PathLike) and anything but a Config
NOT_A_PATH = st.one_of(st.none(), st.booleans(), st.integers(), st.floats(allow_nan=True),
                       st.binary(max_size=8), st.lists(st.integers(), max_size=3),
                       st.dictionaries(st.text(max_size=3), st.integers(), max_size=2),
                       st.just(""))
NOT_A_CONFIG = st.one_of(NOT_A_PATH, st.text(max_size=5).map(lambda s: ("config", s)),
                         st.builds(object))

PATH_ARGUMENTS = {  # function -> the call with the hostile value as its path argument
    "load_model": lambda v: ja.load_model(v),
    "load_datasets": lambda v: ja.load_datasets(v),
    "import_recording": lambda v: ja.import_recording(v),
    "write_report": lambda v: ja.write_report(v),
    "reproduce(out=)": lambda v: ja.reproduce(CONFIG, v),
    "run_experiment(out=)": lambda v: ja.run_experiment(CONFIG, v),
}
CONFIG_ARGUMENTS = {
    "reproduce": lambda v: ja.reproduce(v, "/nonexistent/never-written"),
    "run_experiment": lambda v: ja.run_experiment(v, "/nonexistent/never-written"),
    "train": lambda v: ja.train(v, "n5-sigmoid"),
    "run_cell": lambda v: ja.run_cell(v, CONFIG.experiment.conditions[0], 0),
    "measure_ceiling": lambda v: ja.measure_ceiling(v, 3),
}


@pytest.mark.parametrize("name", PATH_ARGUMENTS)
@given(value=NOT_A_PATH)
@settings(max_examples=30, deadline=None)
def test_a_path_argument_that_is_not_a_path_is_refused_by_name(name, value):
    """Each public function's path argument: a non-path is one ArgumentError naming it."""
    with pytest.raises(ArgumentError, match="expected a path") as err:
        PATH_ARGUMENTS[name](value)
    assert "\n" not in str(err.value)


@pytest.mark.parametrize("name", CONFIG_ARGUMENTS)
@given(value=NOT_A_CONFIG)
@settings(max_examples=30, deadline=None)
def test_a_config_argument_that_is_not_a_config_is_refused_by_name(name, value):
    """Each public function's configuration: anything but a Config is one ArgumentError.

    Refused first: the output place given cannot be made, which would be another error.
    """
    with pytest.raises(ArgumentError, match=r"^config .*: expected a Config"):
        CONFIG_ARGUMENTS[name](value)


MODEL = Path(__file__).parents[1] / "docs" / "results" / "robot" / "paper_n5_seed0.npz"  # shipped
OTHER_ARGUMENTS = {  # (call, the name its error must say); each a wrong kind, never run
    "reproduce(workers='2')": (lambda: ja.reproduce(CONFIG, "/nonexistent/x", workers="2"),
                               "workers"),
    "reproduce(workers=2.5)": (lambda: ja.reproduce(CONFIG, "/nonexistent/x", workers=2.5),
                               "workers"),
    "run_experiment(workers=True)": (
        lambda: ja.run_experiment(CONFIG, "/nonexistent/x", workers=True), "workers"),
    "import_recording(face_size_px=0)": (
        lambda: ja.import_recording("/nonexistent", face_size_px=0), "face_size_px"),
    "import_recording(face_size_px=(30, 0))": (
        lambda: ja.import_recording("/nonexistent", face_size_px=(30, 0)), "face_size_px"),
    "import_recording(face='x')": (lambda: ja.import_recording("/nonexistent", face="x"),
                                   "face"),
    "import_recording(template='x')": (
        lambda: ja.import_recording("/nonexistent", face="template", template="x"),
        "template"),
    "load_model(robot='x')": (lambda: ja.load_model(MODEL, robot="x"), "robot"),
    "save_model('x', ...)": (lambda: ja.save_model("x", "/nonexistent/m.npz", config=CONFIG,
                                                   condition="n5-sigmoid"), "agent"),
    "run_cell(condition='x')": (lambda: ja.run_cell(CONFIG, "x", 0), "condition"),
}


@pytest.mark.parametrize("name", OTHER_ARGUMENTS)
def test_an_argument_of_the_wrong_kind_is_one_named_error(name):
    """Workers, sizes, finders, robots, agents and conditions of the wrong kind: one line."""
    call, named = OTHER_ARGUMENTS[name]
    with pytest.raises(ja.JointAttentionError, match=rf"^{named}[ =:]") as err:
        call()
    assert "\n" not in str(err.value) and "expected" in str(err.value)
