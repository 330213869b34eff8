"""The compiled engine: whole cells of learning in fast perception, without the Python loop.

It runs what :func:`~.cells.run_cell` runs step by step (scene sampling, projection and the fast
detector, Eq. 1-3, the gate, the learning module) as one compiled loop over trials. It calls
the same kernels as the step-by-step path (:mod:`~jointattention.world.kinematics`,
:mod:`~jointattention.world.fast`, :mod:`~jointattention.world.placement`,
:mod:`~jointattention.agent.attention`, :mod:`~jointattention.agent.learner`,
:mod:`~jointattention.agent.bootstrap`) and draws from the same random streams in the same
order, so both give byte-identical cells (``tests/test_compiled.py``).

It learns in place the arrays of a :class:`~jointattention.agent.bootstrap.BootstrapAgent`,
so the learned agent is the same object either way. It runs the bootstrap model with the
sigmoid or constant gate, every reading; anything else is refused (:func:`unsupported`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .._jit import jit
from ..agent.attention import attended_index, interest_argmax, visual_feedback_rad
from ..agent.bootstrap import (
    LEARNING_TARGETS,
    BootstrapAgent,
    BootstrapOptions,
    learning_samples,
    random_step,
    scale_angle_into,
    unit_step,
)
from ..agent.gates import ConstantGate, SigmoidGate, sigmoid_rate
from ..agent.learner import accumulate, forward, sgd_update, standardise, welford_update
from ..agent.models import MODELS, ModelOptions
from ..config import WorldConfig
from ..datasets import CaregiverDatasets
from ..errors import ConfigError
from ..world.fast import detect_into
from ..world.kinematics import HeadKinematics, rotation_matrix
from ..world.mjcf import HEAD_RADII_M
from ..world.placement import place_into, region_of
from .trial import END_FIRED, END_LIMIT, END_STEPS, RECORD

__all__ = ["CompiledCell", "pack_world", "unsupported"]

_VF, _LM, _RANDOM = 0, 1, 2  # the modules, as codes
# the records _run writes, one row each (the rest of trial.RECORD is computed from them)
_COLUMNS = ("learning_time", "n_steps", "n_lm_steps", "n_random_steps", "attended", "target",
            "end")
_OBJECT_DIRECTION = LEARNING_TARGETS.index("object_direction")
_EXECUTED_STEP = LEARNING_TARGETS.index("executed_step")


def unsupported(options: ModelOptions) -> str | None:
    """Why the compiled engine cannot run ``options``, as an error message (None if it can)."""
    if type(options) is not BootstrapOptions:
        what = f"model kind {MODELS.name_of(options)!r}"
    elif type(options.gate) not in (SigmoidGate, ConstantGate):
        what = f"gate kind {options.gate.label!r}"
    else:
        return None
    return (f"experiment.engine = 'compiled' does not run {what}; expected the bootstrap model "
            "with a sigmoid or constant gate, or experiment.engine = 'python'")


class _World(NamedTuple):
    """The world as the compiled loop takes it."""

    n_objects: int
    region: np.ndarray  # place_into's object region
    offset_m: np.ndarray
    limits_rad: np.ndarray  # pan lo, pan hi, tilt lo, tilt hi
    focal_px: float
    width_px: int
    height_px: int
    face_radius_m: float
    theta_face_rad: np.ndarray  # (K, 2) per data set
    target_m: np.ndarray  # (K, 3)
    face_m: np.ndarray  # (K, 3)
    faces: np.ndarray  # (K, pixels) float
    shuffle_faces: bool


class _Robot(NamedTuple):
    """The agent's mechanisms and options as the compiled loop takes them."""

    weights: np.ndarray  # Eq. 1's (a1, a2, a3)
    gain_rad_per_px: float
    d_th_px: float
    step_rad: float
    max_steps: int
    gate_constant: bool
    gate_a: float  # the constant rate, or the sigmoid's midpoint
    gate_b: float  # the sigmoid's width
    gate_per_trial: bool
    vf_fallback_lm: bool
    learning_target: int  # its index in LEARNING_TARGETS
    theta_mid_rad: np.ndarray
    theta_half_rad: np.ndarray
    min_std: float
    learning_rate: float
    momentum: float


class _State(NamedTuple):
    """The learned state (the agent's own arrays) and the counters, changed in place."""

    w1: np.ndarray
    b1: np.ndarray
    w2: np.ndarray
    b2: np.ndarray
    v1: np.ndarray
    vb1: np.ndarray
    v2: np.ndarray
    vb2: np.ndarray
    mean: np.ndarray
    m2: np.ndarray
    counters: np.ndarray  # learning time, faces seen, updates, records


def pack_world(world: WorldConfig, ds: CaregiverDatasets, target_m, face_m, n_objects: int,
               shuffle_faces: bool) -> _World:
    """The world, the data sets and the condition as the compiled loop takes them.

    ``target_m`` and ``face_m`` (K, 3) are where each data set's target and face are.
    """
    kin = HeadKinematics.from_config(world)
    region, offset, limits = region_of(world)
    return _World(int(n_objects), region, offset, limits, float(kin.focal_px), kin.width_px,
                  kin.height_px, HEAD_RADII_M[2], np.ascontiguousarray(ds.theta_face_rad, float),
                  np.ascontiguousarray(target_m, float), np.ascontiguousarray(face_m, float),
                  ds.face.reshape(len(ds), -1).astype(float), bool(shuffle_faces))


@jit
def _gate_rate(robot, t):
    """The gate's rate of choosing the learning module at learning time ``t``."""
    if robot.gate_constant:
        return robot.gate_a
    return sigmoid_rate(float(t), robot.gate_a, robot.gate_b)


@jit
def _run(until_steps, max_trials, world, robot, state, trials_rng, shuffle_rng, gate_rng,
         move_rng, records) -> int:
    """Trials until the learning time reaches ``until_steps``; -1 if objects cannot be placed.

    Each trial is :func:`~.cells.random_scene`, a :class:`~.trial.SceneTrial` and
    :func:`~.trial.run_trial` of a bootstrap agent, in that order of random draws.
    """
    n, n_pix = world.n_objects, world.faces.shape[1]
    n_hidden = len(state.b1)
    w, h = world.width_px, world.height_px
    cx, cy = (w - 1) / 2, (h - 1) / 2
    pos, rad = np.empty((n, 3)), np.empty(n)
    uv, depth, area = np.empty((n, 2)), np.empty(n), np.empty(n)
    centre, seen_area, seen_edge = np.empty((n, 2)), np.empty(n), np.empty(n)
    ids, motion = np.empty(n, dtype=np.int64), np.zeros(n)
    face_x, face_acc, acc = np.empty(n_pix), np.empty(n_hidden), np.empty(n_hidden)
    hid, out, x_full = np.empty(n_hidden), np.empty(2), np.empty(n_pix + 2)
    scaled = np.empty(2)
    thetas, steps = np.empty((robot.max_steps, 2)), np.empty((robot.max_steps, 2))
    y = np.empty((robot.max_steps, 2))
    a1, a2, a3 = robot.weights[0], robot.weights[1], robot.weights[2]
    c = state.counters
    while c[0] < until_steps and c[3] < max_trials:
        start = c[0]
        # the scene (cells.random_scene, FastScene.sample)
        k = trials_rng.integers(0, len(world.faces))
        pos[0], rad[0] = world.target_m[k], trials_rng.uniform(world.region[6], world.region[7])
        if place_into(trials_rng, pos, rad, 1, world.face_m[k], world.face_radius_m,
                      world.region, world.offset_m, world.limits_rad) < n:
            return -1
        order = trials_rng.permutation(n)
        obj_pos, obj_rad = pos[order], rad[order]
        target = np.argmin(order)
        edge = trials_rng.uniform(0.0, 1.0, n)
        face = world.faces[shuffle_rng.integers(0, len(world.faces))
                           if world.shuffle_faces else k]
        # the agent begins (BootstrapAgent.begin_trial)
        c[1] += 1
        welford_update(face, state.mean, state.m2, c[1])
        standardise(face, state.mean, state.m2, c[1], robot.min_std, face_x)
        face_acc[:] = 0.0
        accumulate(face_x, state.w1, 0, face_acc)
        trial_module = -1
        if robot.gate_per_trial:
            trial_module = _LM if gate_rng.random() < _gate_rate(robot, c[0]) else _VF
        # the trial (SceneTrial, run_trial)
        pan, tilt = world.theta_face_rad[k, 0], world.theta_face_rad[k, 1]
        n_steps, n_lm, n_random, end, attended, seen = 0, 0, 0, -1, -1, -1
        limit_hit = False
        while True:
            m = detect_into(obj_pos, obj_rad, edge, rotation_matrix(pan, tilt), world.offset_m,
                            world.focal_px, w, h, uv, depth, area, centre, seen_area,
                            seen_edge, ids)
            seen = attended_index(centre[:m], cx, cy, robot.d_th_px)
            if seen >= 0:
                attended, end = ids[seen], END_FIRED
            elif limit_hit:
                end = END_LIMIT
            elif n_steps >= robot.max_steps:
                end = END_STEPS
            if end >= 0:
                break
            # the agent acts (BootstrapAgent.act)
            module = trial_module
            if module < 0:
                module = _LM if gate_rng.random() < _gate_rate(robot, c[0]) else _VF
            i = -1
            if module == _VF:
                i = interest_argmax(seen_area[:m], seen_edge[:m], motion[:m], a1, a2, a3)
                if i < 0:
                    module = _LM if robot.vf_fallback_lm else _RANDOM
            if module == _VF:
                d_pan, d_tilt = visual_feedback_rad(centre[i, 0], centre[i, 1], cx, cy,
                                                    robot.gain_rad_per_px)
            elif module == _LM:
                acc[:] = face_acc
                scale_angle_into(pan, tilt, robot.theta_mid_rad, robot.theta_half_rad, scaled, 0)
                accumulate(scaled, state.w1, n_pix, acc)
                forward(acc, state.b1, state.w2, state.b2, hid, out)
                d_pan, d_tilt = unit_step(out[0], out[1], robot.step_rad)
            else:
                d_pan, d_tilt = random_step(move_rng, robot.step_rad)
            thetas[n_steps, 0], thetas[n_steps, 1] = pan, tilt
            steps[n_steps, 0], steps[n_steps, 1] = d_pan, d_tilt
            c[0] += 1
            n_lm += module == _LM
            n_random += module == _RANDOM
            # the head moves, stopping at its joint limits (SceneTrial.step)
            want_pan, want_tilt = pan + d_pan, tilt + d_tilt
            pan = min(max(want_pan, world.limits_rad[0]), world.limits_rad[1])
            tilt = min(max(want_tilt, world.limits_rad[2]), world.limits_rad[3])
            n_steps += 1
            limit_hit = pan != want_pan or tilt != want_tilt
        # the agent learns (BootstrapAgent.end_trial)
        if end == END_FIRED and n_steps > 0:
            aim = np.array([pan, tilt])
            if robot.learning_target == _OBJECT_DIRECTION:
                v_pan, v_tilt = visual_feedback_rad(centre[seen, 0], centre[seen, 1], cx, cy,
                                                    robot.gain_rad_per_px)
                aim[0], aim[1] = pan + v_pan, tilt + v_tilt
            keep = learning_samples(thetas[:n_steps], steps[:n_steps], aim,
                                    robot.learning_target == _EXECUTED_STEP, y[:n_steps])
            x_full[:n_pix] = face_x
            for s in range(n_steps):
                if keep[s]:
                    scale_angle_into(thetas[s, 0], thetas[s, 1], robot.theta_mid_rad,
                                     robot.theta_half_rad, x_full, n_pix)
                    sgd_update(x_full, y[s], state.w1, state.b1, state.w2, state.b2, state.v1,
                               state.vb1, state.v2, state.vb2, robot.learning_rate,
                               robot.momentum)
                    c[2] += 1
        r = c[3]
        records[0, r], records[1, r], records[2, r], records[3, r] = start, n_steps, n_lm, n_random
        records[4, r], records[5, r], records[6, r] = attended, target, end
        c[3] += 1
    return 0


class CompiledCell:
    """One cell (a condition and a seed) learning in the compiled engine.

    Args:
        agent: the cell's untrained bootstrap agent (:func:`~.cells.make_agent`); it learns in
            place.
        world: the data sets, the world and the condition as :func:`pack_world` packs them.
        trials: the stream that draws each trial's data set and scene.
        shuffle: the stream that draws a random face (``shuffle_faces`` conditions).
        max_trials: the most trials the cell may hold.

    :meth:`run_until` learns up to a learning time; :meth:`records` are the trial records.
    """

    def __init__(self, agent: BootstrapAgent, world: _World, trials: np.random.Generator,
                 shuffle: np.random.Generator, max_trials: int):
        refusal = unsupported(agent.options)
        if refusal is not None:
            raise ConfigError(refusal)
        self.agent, self._world = agent, world
        self._trials, self._shuffle = trials, shuffle
        opts, shared = agent.options, agent.agent
        gate = opts.gate
        constant = isinstance(gate, ConstantGate)
        self._robot = _Robot(
            np.asarray(shared.interest_weights, dtype=float), float(shared.vf_gain_rad_per_px),
            float(shared.d_th_px(world.width_px)), float(agent.step_rad), int(shared.max_steps),
            constant, float(gate.rate if constant else gate.midpoint_steps),
            0.0 if constant else float(gate.width_steps), opts.gate_per == "trial",
            opts.vf_fallback == "lm",
            LEARNING_TARGETS.index(opts.learning_target),
            agent.theta_mid_rad, agent.theta_half_rad, float(agent.faces.min_std),
            float(opts.learning_rate), float(opts.momentum))
        learner, faces = agent.learner, agent.faces
        if faces.n_seen_ == 0:
            faces.mean_, faces.m2_ = np.zeros(world.faces.shape[1]), np.zeros(world.faces.shape[1])
        self._state = _State(
            learner.w1_, learner.b1_, learner.w2_, learner.b2_, *learner.velocity_,
            faces.mean_, faces.m2_,
            np.array([agent.learning_time_steps, faces.n_seen_, learner.n_updates_, 0]))
        self._records = np.zeros((len(_COLUMNS), max_trials), dtype=np.int64)

    def run_until(self, learning_time_steps: int) -> None:
        """Learn trial after trial until the learning time reaches ``learning_time_steps``."""
        if _run(learning_time_steps, self._records.shape[1], self._world, self._robot,
                self._state, self._trials, self._shuffle, self.agent.gate_rng,
                self.agent.move_rng, self._records) < 0:
            raise ConfigError(
                f"objects: could not place {self._world.n_objects} objects apart within the "
                "object region; expected fewer objects, a wider region or smaller gaps")
        c = self._state.counters
        self.agent.learning_time_steps = int(c[0])
        self.agent.faces.n_seen_, self.agent.learner.n_updates_ = int(c[1]), int(c[2])

    def records(self) -> dict[str, np.ndarray]:
        """The trial records so far (:data:`~.trial.RECORD`)."""
        r = self._records[:, : self._state.counters[3]]
        cols = dict(zip(_COLUMNS, r, strict=True))
        cols["success"] = cols["attended"] == cols["target"]
        cols["fired"] = cols["end"] == END_FIRED
        return {name: cols[name].astype(dtype) for name, (dtype, _) in RECORD.items()}
