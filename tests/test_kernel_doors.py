"""Every public function that hands arrays to a compiled kernel checks them first.

A kernel reads its arrays by the sizes it is given; a wrong shape that reached one would read
past an array and could end the interpreter with a signal. So the calls run in a subprocess,
and each wrong shape must come back as one ``ArgumentError`` naming the argument.
"""

from __future__ import annotations

import subprocess
import sys
import textwrap

SCRIPT = textwrap.dedent("""
    import numpy as np
    from hypothesis import given, settings, strategies as st
    from hypothesis.extra import numpy as hnp

    from jointattention.agent.attention import most_interesting
    from jointattention.agent.detections import Detections
    from jointattention.models.population.features import face_features
    from jointattention.agent.face_standardiser import FaceStandardiser
    from jointattention.models.network.learner import LearningModule
    from jointattention.models.memory.episodic import EpisodicMemory
    from jointattention.models.memory.options import MemoryOptions
    from jointattention.models.population.code import PopulationCode
    from jointattention.models.population.options import PopulationOptions
    from jointattention.agent.protocol import Body
    from jointattention.config import load_config, model_options
    from jointattention.errors import ArgumentError
    from jointattention.world.fast import FastScene
    from jointattention.world.kinematics import HeadKinematics

    W, H = 10, 10
    BODY = Body((320, 240), ((-1.0, 1.0), (-0.8, 0.6)), (W, H))
    FACE, THETA = np.full((H, W), 90.0), np.zeros(2)
    rng = np.random.default_rng(0)

    def agent(model):
        config = load_config({"model": model, "experiment": {"engine": "python"}})
        a = model_options(config, config.experiment.conditions[0]).build(config.agent, BODY, rng)
        a.begin_trial(FACE, THETA)
        return a

    agents = {name: agent(model) for name, model in {
        "bootstrap": {"kind": "bootstrap"},
        "memory": {"kind": "bootstrap", "learner": "memory"},
        "population": {"kind": "bootstrap", "learner": "population"},
        "teacher": {"kind": "teacher"}, "developmental": {"kind": "developmental"},
        "rl": {"kind": "rl"}}.items()}
    standardiser = FaceStandardiser().partial_fit(FACE.ravel())
    net = LearningModule(H * W + 2, rng=rng)
    memory = EpisodicMemory(H * W, MemoryOptions(), ((-1, 1), (-0.8, 0.6)), rng)
    population = PopulationCode(12, PopulationOptions(), rng)
    kin = HeadKinematics.from_config(load_config("quick").world)
    col = np.ones(3)

    # (door, argument name, the call with the hostile value, a good value)
    DOORS = []
    for name, a in agents.items():
        DOORS += [
            (f"{name}.lm_command", "face_window", lambda v, a=a: a.lm_command(v, THETA), FACE),
            (f"{name}.lm_command", "theta_rad", lambda v, a=a: a.lm_command(FACE, v), THETA),
            (f"{name}.lm_commands", "face_windows",
             lambda v, a=a: a.lm_commands(v, np.zeros((2, 2))), np.stack([FACE, FACE])),
            (f"{name}.lm_commands", "thetas_rad",
             lambda v, a=a: a.lm_commands(np.stack([FACE, FACE]), v), np.zeros((2, 2))),
            (f"{name}.begin_trial", "face_window", lambda v, a=a: a.begin_trial(v, THETA), FACE),
        ]
    DOORS += [
        ("FaceStandardiser.partial_fit", "faces", standardiser.partial_fit, FACE.ravel()),
        ("FaceStandardiser.transform", "faces", standardiser.transform, FACE.ravel()),
        ("LearningModule.predict", "X", net.predict, np.zeros((3, H * W + 2))),
        ("LearningModule.partial_fit", "Y",
         lambda v: net.partial_fit(np.zeros((3, H * W + 2)), v), np.zeros((3, 2))),
        ("EpisodicMemory.code", "face_window", memory.code, FACE),
        ("EpisodicMemory.recall", "code", memory.recall, np.zeros(MemoryOptions().code_dims)),
        ("EpisodicMemory.predict", "X", memory.predict, np.zeros((2, H * W))),
        ("EpisodicMemory.partial_fit", "Y",
         lambda v: memory.partial_fit(np.zeros((2, H * W)), v), np.zeros((2, 2))),
        ("PopulationCode.probabilities", "x", population.probabilities, np.zeros(12)),
        ("PopulationCode.teach", "x", lambda v: population.teach(v, [0.5]), np.zeros(12)),
        ("PopulationCode.predict", "X", population.predict, np.zeros((2, 12))),
        ("face_features", "faces", face_features, FACE),
        ("Detections", "edge",
         lambda v: most_interesting(Detections(np.zeros((3, 2)), col, v, col, (320, 240)),
                                    (1, 1, 1)), col),
        ("FastScene", "object_pos_m",
         lambda v: FastScene(kin, v, np.full(3, 0.05), 0, col).observe(THETA),
         np.array([[0, 1.0, 0], [0.2, 1.0, 0], [-0.2, 1.0, 0]])),
        ("HeadKinematics.project_spheres", "points_m",
         lambda v: kin.project_spheres(v, 0.05, THETA), np.array([[0, 1.0, 0]])),
        ("HeadKinematics.centring_angles", "point_m", kin.centring_angles, np.array([0, 1.0, 0])),
    ]

    # any window size is a window to face_features; NaN is an edge the kernels rank last
    BADS = {"face_features": (np.zeros((2, 2, 2, 2)), "x", np.full((H, W), np.nan)),
            "Detections": (np.ones(4), "x", np.ones((3, 1)))}

    hostile = st.one_of(
        hnp.arrays(st.sampled_from([np.float64, np.int64, np.uint8, np.bool_, np.complex128]),
                   hnp.array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=120),
                   elements=None),
        st.sampled_from(["ab", None, 3, {"a": 1}, [[1, 2], [3]], [1.0, float("nan")]]))

    def judge(door, arg, call, value):
        try:
            call(value)
        except ArgumentError as err:
            return str(err).startswith(arg + ":") or str(err).startswith(arg + " ")
        return True  # a shape the door accepts; the kernel ran and the interpreter lives

    for door, arg, call, good in DOORS:
        call(good)  # the right shape works
        @settings(max_examples=40, deadline=None, database=None, derandomize=True)
        @given(hostile)
        def check(value):
            assert judge(door, arg, call, value), (door, arg, value)
        check()
        bads = BADS.get(door, (np.resize(good, np.array(np.shape(good)) + 7), "x",
                               np.full(np.shape(good), np.nan)))
        for bad in bads:
            try:
                call(bad)
                print("accepted", door, arg)
            except ArgumentError as err:
                print("refused", door, str(err).split(":")[0].split(" ")[0] == arg)
    print("doors", len(DOORS))
""")


def test_wrong_shapes_never_reach_a_kernel():
    """Each public door to a kernel refuses wrong shapes, types and NaN in one named line."""
    proc = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True,
                          timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    lines = proc.stdout.splitlines()
    assert lines[-1] == f"doors {len(lines) // 3}" and len(lines) // 3 >= 40
    assert all(line.startswith("refused ") and line.endswith(" True") for line in lines[:-1]), [
        line for line in lines[:-1] if not line.endswith(" True")]
