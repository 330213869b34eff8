"""The compiled engine: the same cells as the step-by-step path; kernels true to the equations.

The kernels are checked against plain numpy formulas of the paper's equations.
"""

from __future__ import annotations

import dataclasses
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from jointattention import run_cell, run_experiment
from jointattention.agent.attention import attended_index, interest_argmax, visual_feedback_rad
from jointattention.agent.gates import SigmoidGate
from jointattention.config import ConditionConfig, Config, ExperimentConfig
from jointattention.errors import ArgumentError
from jointattention.experiment import evaluate as evaluate_module
from jointattention.experiment.cells import datasets_of
from jointattention.experiment.evaluate import frozen_success
from jointattention.jobs.learned import snapshots
from jointattention.models.bootstrap import BootstrapOptions
from jointattention.models.network.learner import LearningModule
from jointattention.world import fast
from jointattention.world.kinematics import HeadKinematics

READINGS = [  # each reading and gate of the bootstrap model, early enough to be quick
    ConditionConfig(name="sigmoid", n_objects=5),
    ConditionConfig(name="per-trial", n_objects=3, model={"gate_per": "trial"}),
    ConditionConfig(name="fallback-lm", n_objects=1, model={"vf_fallback": "lm"}),
    ConditionConfig(name="final", n_objects=10, model={"learning_target": "final_direction"}),
    ConditionConfig(name="executed", n_objects=5, model={"learning_target": "executed_step"}),
    ConditionConfig(name="const", n_objects=5, model={
        "gate": {"kind": "constant", "rate": 0.5}, "n_hidden": 4, "momentum": 0.0}),
    ConditionConfig(name="shuffled", n_objects=5, shuffle_faces=True),
    ConditionConfig(name="learn-from-vf", n_objects=5, model={"learn_from": "vf"}),
    ConditionConfig(name="passes", n_objects=3, model={"n_passes": 3, "vf_fallback": "lm"}),
    ConditionConfig(name="memory-from-vf", n_objects=5, model={
        "learner": "memory", "learn_from": "vf"}),
    ConditionConfig(name="sweep", n_objects=5, model={"vf_fallback": "sweep"}),
    ConditionConfig(name="memory", n_objects=5, model={"learner": "memory"}),
    ConditionConfig(name="memory-attended", n_objects=5, model={
        "learner": "memory", "memory": {"keep": "attended"}}),
    ConditionConfig(name="memory-forgets", n_objects=10, model={
        "learner": "memory", "vf_fallback": "sweep", "memory": {"capacity": 40}}),
    ConditionConfig(name="memory-final", n_objects=3, model={
        "learner": "memory", "learning_target": "final_direction", "gate_per": "trial"}),
    ConditionConfig(name="performance", n_objects=3, model={
        "gate": {"kind": "performance", "window_trials": 20.0, "full_agreement": 0.2}}),
    ConditionConfig(name="memory-performance", n_objects=5, model={
        "learner": "memory", "gate_per": "trial",
        "gate": {"kind": "performance", "window_trials": 20.0, "full_agreement": 0.2}}),
    ConditionConfig(name="memory-evidence", n_objects=5, model={
        "learner": "memory", "vf_fallback": "sweep", "gate": {"kind": "evidence"}}),
    ConditionConfig(name="memory-evidence-trial", n_objects=3, model={
        "learner": "memory", "gate_per": "trial",
        "gate": {"kind": "evidence", "floor_trials": 0.5, "half_trials": 2.0}}),
    ConditionConfig(name="teacher", n_objects=5, model={"kind": "teacher"}),
    ConditionConfig(name="teacher-performance", n_objects=3, model={
        "kind": "teacher",
        "gate": {"kind": "performance", "window_trials": 20.0, "full_agreement": 0.2}}),
    ConditionConfig(name="developmental", n_objects=5, model={
        "kind": "developmental", "criterion_start_deg": 40.0, "criterion_window_trials": 10.0,
        "criterion_shrink": 0.9, "blur_start_px": 3.0, "blur_sharp_steps": 2000.0}),
    ConditionConfig(name="developmental-shuffled", n_objects=3, shuffle_faces=True, model={
        "kind": "developmental", "criterion_level": 0.2, "blur_start_px": 0.5}),
    ConditionConfig(name="population", n_objects=5, model={
        "learner": "population", "vf_fallback": "sweep", "population": {"n_hidden": 16}}),
    ConditionConfig(name="population-attended-standardised", n_objects=10, model={
        "learner": "population", "population": {
            "n_hidden": 8, "keep": "attended", "standardise": True, "replay": 3,
            "replay_capacity": 30, "readout": "ratio", "features": "hog"}}),
    ConditionConfig(name="population-belief", n_objects=10, model={
        "learner": "population", "population": {"n_hidden": 16, "belief": 1.0}}),
    ConditionConfig(name="population-unfound", n_objects=10, model={
        "learner": "population", "population": {"n_hidden": 16, "belief": 1.0,
                                                 "unfound": True}}),
    ConditionConfig(name="population-performance", n_objects=3, shuffle_faces=True, model={
        "learner": "population", "gate_per": "trial", "learning_target": "final_direction",
        "population": {"n_hidden": 8, "average_rate": 0.0, "readout": "mode",
                       "features": "pixels"},
        "gate": {"kind": "performance", "window_trials": 20.0, "full_agreement": 0.2}}),
    ConditionConfig(name="rl", n_objects=3, model={"kind": "rl"}),
    ConditionConfig(name="rl-shuffled", n_objects=5, shuffle_faces=True, model={
        "kind": "rl", "n_directions": 8, "temperature": 0.5, "gamma": 0.5}),
]
CONFIG = Config(
    model=BootstrapOptions(gate=SigmoidGate(midpoint_steps=1500.0, width_steps=500.0)),
    experiment=ExperimentConfig(n_steps=3000, n_seeds=2, conditions=tuple(READINGS)))


def _engine(config: Config, engine: str) -> Config:
    return dataclasses.replace(config, experiment=dataclasses.replace(config.experiment,
                                                                      engine=engine))


@pytest.mark.parametrize("condition", READINGS, ids=lambda c: c.name)
def test_compiled_cells_equal_the_step_by_step_cells_byte_for_byte(condition):
    """Every reading and gate: the compiled engine writes the python engine's records."""
    compiled = run_cell(_engine(CONFIG, "compiled"), condition, 1)
    python = run_cell(_engine(CONFIG, "python"), condition, 1)
    assert compiled.keys() == python.keys()
    for key in compiled:
        assert compiled[key].dtype == python[key].dtype
        assert np.array_equal(compiled[key], python[key], equal_nan=True), key
    assert compiled["n_lm_steps"].sum() > 0 and compiled["fired"].any()


def test_compiled_agents_learn_the_same_weights_at_each_checkpoint():
    """Fig. 6/7's snapshots: the agents learned by both engines are equal, array by array."""
    snaps = {e: snapshots(_engine(CONFIG, e), "sigmoid", 0, [1000, 2000]) for e in
             ("compiled", "python")}
    assert snaps["compiled"].keys() == snaps["python"].keys() == {0, 1000, 2000, 3000}
    for t, agent in snaps["compiled"].items():
        other = snaps["python"][t]
        assert agent.learning_time_steps == other.learning_time_steps
        assert agent.learner.n_updates_ == other.learner.n_updates_
        for a, b in zip(agent.learner._params(), other.learner._params(), strict=True):
            assert np.array_equal(a, b)
    assert snaps["compiled"][3000].learner.n_updates_ > 0


def test_a_frozen_memory_under_the_evidence_gate_runs_the_same_trials_in_both_engines(
        monkeypatch):
    """Held-out trials of a frozen memory (recalls kept per face, compiled) = step by step."""
    condition = next(c for c in READINGS if c.name == "memory-evidence")
    agent = snapshots(CONFIG, condition.name, 0, [])[3000]
    ds = datasets_of(CONFIG)
    compiled = frozen_success(agent, ds, CONFIG, 5, 300, seed=3)
    monkeypatch.setattr(evaluate_module, "unsupported", lambda options: "step by step")
    assert frozen_success(agent, ds, CONFIG, 5, 300, seed=3) == compiled
    assert 0 < compiled < 1


def test_the_batched_learning_module_command_equals_the_single_one():
    """lm_commands (the diagnostics' probe) gives lm_command's outputs exactly."""
    agent = snapshots(_engine(CONFIG, "compiled"), "sigmoid", 0, [])[3000]
    ds = datasets_of(CONFIG)
    single = np.array([agent.lm_command(f, t) for f, t in zip(ds.face, ds.theta_face_rad,
                                                                strict=True)])
    assert np.array_equal(agent.lm_commands(ds.face, ds.theta_face_rad), single)


@pytest.mark.parametrize("backend", ["local", "ray"])
def test_compiled_runs_do_not_depend_on_workers_or_backend(tmp_path, backend):
    """One process, two workers and Ray give the same cells."""
    if backend == "ray":
        pytest.importorskip("ray")
    small = dataclasses.replace(CONFIG, experiment=dataclasses.replace(
        CONFIG.experiment, n_steps=1500, conditions=READINGS[:2]))
    one = run_experiment(small, tmp_path / "one", workers=1)
    two = run_experiment(small, tmp_path / "two", workers=2, backend=backend)
    for key in one:
        for col in one[key]:
            assert np.array_equal(one[key][col], two[key][col])


def _second_run(script: str) -> list[str]:
    """The words ``script`` prints in a second new process, the first having compiled."""
    # the first may compile (a fresh machine); the second must find the cache
    for _ in range(2):
        out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                             check=True).stdout.split()
    return out


def test_a_second_process_loads_the_compiled_engine_from_the_cache():
    """The engine is compiled once per machine: a new process finds it in the cache."""
    script = ("import dataclasses\n"
              "from jointattention import load_config, run_cell\n"
              "from jointattention.experiment.compiled._loop import loop_for\n"
              "from jointattention.models.network.module import NetworkModule\n"
              "c = load_config('quick')\n"
              "c = dataclasses.replace(c, experiment=dataclasses.replace(c.experiment, "
              "n_steps=50))\n"
              "run_cell(c, c.experiment.conditions[0], 0)\n"
              "loop = loop_for(NetworkModule.kernels)\n"
              "print(sum(loop.stats.cache_hits.values()), "
              "sum(loop.stats.cache_misses.values()))")
    assert _second_run(script) == ["1", "0"]


def test_a_loop_compiled_for_a_module_s_kernels_is_cached_under_its_own_name():
    """The loop for the population code's kernels is its own copy, and a new process loads it."""
    script = ("import dataclasses\n"
              "from jointattention import load_config, run_cell\n"
              "from jointattention.experiment.compiled._loop import loop_for, run_trials\n"
              "from jointattention.models.population.module import PopulationModule\n"
              "c = load_config('quick')\n"
              "c = dataclasses.replace(c, model=dataclasses.replace(c.model, "
              "learner='population'), experiment=dataclasses.replace(c.experiment, "
              "n_steps=50))\n"
              "run_cell(c, c.experiment.conditions[0], 0)\n"
              "loop = loop_for(PopulationModule.kernels)\n"
              "print(loop is not run_trials, loop.py_func.__qualname__ != 'run_trials', "
              "sum(loop.stats.cache_hits.values()), sum(loop.stats.cache_misses.values()))")
    assert _second_run(script) == ["True", "True", "1", "0"]


def test_each_set_of_module_kernels_gets_a_loop_named_for_it():
    """loop_for: one loop per set of kernels, named for them, kernels without a file too."""
    import numba

    from jointattention import ModuleKernels
    from jointattention.experiment.compiled._loop import loop_for, run_trials

    def stub(*args):
        return 0.0

    made = numba.njit(eval("lambda *args: 0.0"))  # no file: its code names the loop
    a, b = ModuleKernels(*[numba.njit(stub)] * 4), ModuleKernels(*[made] * 4)
    assert loop_for(a) is loop_for(a) and loop_for(a) is not run_trials
    names = {loop_for(k).py_func.__qualname__ for k in (a, b)}
    assert len(names) == 2 and all(n.startswith("run_trials_") for n in names)


def test_kernels_call_kernels_without_the_wrapper_for_python():
    """A kernel's callers call its wrapperless twin; from Python the kernel itself runs alike."""
    import numba

    from jointattention.world.kinematics import rotation_into, rotation_matrix

    twin = numba.typeof(rotation_into).dispatcher
    assert twin is not rotation_into
    assert twin.targetoptions["no_cpython_wrapper"]
    assert not rotation_into.targetoptions.get("no_cpython_wrapper", False)
    by_kernel = rotation_matrix(0.3, -0.2)  # calls the twin (or loads it so from the cache)
    by_python = np.empty((3, 3))
    rotation_into(0.3, -0.2, by_python)
    assert np.array_equal(by_kernel, by_python)


def test_a_constant_argument_compiles_no_version_of_its_own():
    """A kernel called with a constant (``0``) and with a variable compiles one machine code."""
    import numba
    from numba.core import types

    from jointattention.models.network._backprop import accumulate

    twin = numba.typeof(accumulate).dispatcher
    vector, matrix = types.float64[::1], types.float64[:, ::1]
    for first_input in (types.literal(0), types.int64):
        twin.get_call_template((vector, matrix, first_input, vector), {})
    assert (vector, matrix, types.int64, vector) in twin.signatures
    assert not any(isinstance(t, types.Literal) for sig in twin.signatures for t in sig)


def _detector_caller(pos, radius, edge, rot, offset, centre, area, seen_edge, ids):
    """A kernel's call of the fast detector (compiled in the test, not cached)."""
    return fast.detect_into(pos, radius, edge, rot, offset, 300.0, 320, 240, centre, area,
                            seen_edge, ids)


def test_a_kernel_marked_inline_is_compiled_into_its_callers():
    """A kernel marked ``inline`` (the fast detector) has no call in its callers' code."""
    import re

    import numba

    from jointattention.world.kinematics import rotation_matrix

    def arrays():
        return (np.array([[0.0, 1.0, 0.0], [0.1, 1.0, 0.05], [2.0, -1.0, 0.0]]),
                np.full(3, 0.03), np.arange(3.0), rotation_matrix(0.05, 0.0), np.zeros(3),
                np.zeros((3, 2)), np.zeros(3), np.zeros(3), np.zeros(3, np.int64))

    by_python, by_kernel = arrays(), arrays()
    n_python = fast.detect_into(*by_python[:5], 300.0, 320, 240, *by_python[5:])
    caller = numba.njit(_detector_caller)
    assert caller(*by_kernel) == n_python == 2
    for a, b in zip(by_python, by_kernel, strict=True):
        assert np.array_equal(a, b)
    llvm = next(iter(caller.inspect_llvm().values()))
    assert not re.findall(r"call[^@\n]*@\S*detect_into", llvm)


KIN = HeadKinematics.from_config(Config().world)
points = st.tuples(st.floats(-0.6, 0.6), st.floats(0.2, 1.2), st.floats(-0.5, 0.5))
angles = st.tuples(st.floats(-1.0, 1.0), st.floats(-0.7, 0.6))


@settings(max_examples=60, deadline=None)
@given(points, st.floats(0.01, 0.1), angles)
def test_projection_agrees_with_the_pinhole_formula(point, radius, theta):
    """Projection: positions (to 1e-9; relative 1e-12 far off the image) and area, as numpy's."""
    p = np.array(point)
    uv, depth, area = KIN.project_spheres(p, radius, theta)
    rot = KIN.rotation(theta)
    cam = p @ rot - np.array(KIN.offset_m)  # (right, depth, up)
    assert depth[0] == pytest.approx(cam[1], abs=1e-12)
    if cam[1] <= 0:
        assert np.isnan(uv).all()
        return
    f = KIN.focal_px
    expected_uv = KIN.centre_px + f * np.array([cam[0], -cam[2]]) / cam[1]
    np.testing.assert_allclose(uv[0], expected_uv, rtol=1e-12, atol=1e-9)
    sin_b = radius / np.linalg.norm(cam)
    cos_a = cam[1] / np.linalg.norm(cam)
    denom = cos_a**2 - sin_b**2
    if denom > 0:  # semi-axes f sin b cos b / denom and f sin b / sqrt(denom)
        ellipse = np.pi * (f * sin_b * np.sqrt(1 - sin_b**2) / denom) * (f * sin_b
                                                                          / np.sqrt(denom))
        assert area[0] == pytest.approx(ellipse, rel=1e-9)


detections = st.integers(1, 10).flatmap(lambda n: st.tuples(
    st.lists(st.tuples(st.floats(0, 319), st.floats(0, 239)), min_size=n, max_size=n),
    st.lists(st.floats(0, 5000), min_size=n, max_size=n),
    st.lists(st.floats(0, 1), min_size=n, max_size=n)))


@settings(max_examples=60, deadline=None)
@given(detections, st.tuples(st.floats(0, 2), st.floats(0, 2), st.floats(0, 2)))
def test_equations_1_2_3_agree_with_numpy(det, weights):
    """Eq. 1 (weighted argmax), 2 (gain times offset) and 3 (nearest within d_th) match numpy."""
    centre, area, edge = (np.array(x, dtype=float) for x in det)
    motion = np.zeros(len(area))
    a1, a2, a3 = weights
    score = a1 * area + a2 * edge + a3 * motion
    assert interest_argmax(area, edge, motion, a1, a2, a3) == int(np.argmax(score))
    c = np.array([159.5, 119.5])
    for i in range(len(area)):
        got = visual_feedback_rad(centre[i, 0], centre[i, 1], c[0], c[1], 0.0025)
        np.testing.assert_allclose(got, 0.0025 * np.array([centre[i, 0] - c[0],
                                                           c[1] - centre[i, 1]]), atol=1e-12)
    dist = np.hypot(*(centre - c).T)
    expected = int(np.argmin(dist)) if dist.min() < 53.3 else -1
    assert attended_index(centre, c[0], c[1], 53.3) == expected


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 12), st.floats(0, 0.9))
def test_forward_pass_and_one_update_agree_with_numpy(seed, n_hidden, momentum):
    """The learning module's forward pass and one update match numpy's to 1e-9."""
    rng = np.random.default_rng(seed)
    net = LearningModule(40, n_hidden, 2, learning_rate=0.01, momentum=momentum, rng=rng)
    x, y = rng.normal(size=(2, 40)), rng.normal(size=(2, 2))
    net.partial_fit(x[:1], y[:1])  # some momentum to carry
    w1, b1, w2, b2 = (p.copy() for p in net._params())
    v = [p.copy() for p in net.velocity_]
    h = np.tanh(w1 @ x[1] + b1)
    out = h @ w2 + b2
    np.testing.assert_allclose(net.predict(x[1:]), out[None], rtol=0, atol=1e-9)
    err = out - y[1]
    dh = (w2 @ err) * (1 - h**2)
    grads = [np.outer(dh, x[1]), dh, np.outer(h, err), err]
    net.partial_fit(x[1:], y[1:])
    for p, p0, v0, g in zip(net._params(), (w1, b1, w2, b2), v, grads, strict=True):
        np.testing.assert_allclose(p, p0 + (momentum * v0 - 0.01 * g), rtol=0, atol=1e-9)


def _two_modules(seed: int, n_hidden: int, momentum: float):
    rng = np.random.default_rng(seed)
    nets = [LearningModule(30, n_hidden, 2, learning_rate=0.02, momentum=momentum,
                           rng=np.random.default_rng(seed)) for _ in range(2)]
    x, y = rng.normal(size=(3, 30)), rng.normal(size=(3, 2))
    for net in nets:
        net.partial_fit(x, y)  # momentum to carry into the shared rows
    return nets, rng


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 9), st.floats(0, 0.95),
       st.integers(0, 12), st.integers(0, 30))
def test_rows_sharing_inputs_learn_as_row_by_row(seed, n_hidden, momentum, n_rows, n_shared):
    """Rows that share their first inputs, updated in closed form, match row by row to 1e-12."""
    (closed, one_by_one), rng = _two_modules(seed, n_hidden, momentum)
    X, Y = rng.normal(size=(n_rows, 30)), rng.normal(size=(n_rows, 2))
    X[:, :n_shared] = rng.normal(size=n_shared)
    closed.partial_fit(X, Y, shared_inputs=n_shared)
    for x, y in zip(X, Y, strict=True):
        one_by_one.partial_fit(x[None], y[None])
    assert closed.n_updates_ == one_by_one.n_updates_
    for a, b in zip(closed._params() + closed.velocity_,
                    one_by_one._params() + one_by_one.velocity_, strict=True):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)


def test_rows_sharing_nothing_learn_with_the_bits_of_row_by_row():
    """With no shared input, updating many rows at once gives the same bits as one by one."""
    (many, one_by_one), rng = _two_modules(3, 7, 0.5)
    X, Y = rng.normal(size=(9, 30)), rng.normal(size=(9, 2))
    many.partial_fit(X, Y)
    for x, y in zip(X, Y, strict=True):
        one_by_one.partial_fit(x[None], y[None])
    for a, b in zip(many._params() + many.velocity_,
                    one_by_one._params() + one_by_one.velocity_, strict=True):
        assert np.array_equal(a, b)


def test_rows_that_do_not_share_their_inputs_are_refused():
    """partial_fit refuses shared_inputs that the rows do not share, and changes nothing."""
    (net, _), rng = _two_modules(4, 7, 0.5)
    before = [p.copy() for p in net._params()]
    X = rng.normal(size=(2, 30))
    with pytest.raises(ArgumentError, match="rows differ in their first 5 inputs"):
        net.partial_fit(X, np.zeros((2, 2)), shared_inputs=5)
    with pytest.raises(ArgumentError, match="shared_inputs: 31; expected 0 to 30"):
        net.partial_fit(X, np.zeros((2, 2)), shared_inputs=31)
    assert all(np.array_equal(a, b) for a, b in zip(net._params(), before, strict=True))
