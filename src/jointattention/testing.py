"""``check_agent(options)``: the checks every model passes, for a model of your own.

In the spirit of Gymnasium's ``check_env`` and scikit-learn's ``check_estimator``: register a
model (``MODELS.register(name, Options)``), then ``check_agent(Options())`` runs it through
what the package expects of every model, and raises :class:`AgentCheckError` naming the first
check that fails. The package's tests run it on every registered model.

The checks, in order:

1. the options are a registered :class:`~jointattention.models.registry.ModelOptions`
   section with a label;
2. the agent it builds has the :class:`~jointattention.agent.protocol.Agent` methods, and one
   trial in the fast world moves the head by finite (pan, tilt) steps, each named by a module,
   while its learning time counts the steps;
3. the same seed, the same behaviour: two new agents of one seed make the same moves in the
   same first trial (every draw shows in a move, so a draw from global state is caught even
   when no trial succeeds), and two cells of one seed are byte-identical;
4. if the model declares that the compiled engine runs it (``compiled_refusal()`` is None),
   the compiled cell equals the step-by-step cell byte for byte;
5. if its agent can be frozen (a ``learning`` switch), the frozen copy changes nothing it
   learned over trials (its model-file members and its commands are unchanged);
6. if it declares that it can be saved (``save_refusal()`` is None) and the short run may be
   saved (:func:`~jointattention.deploy.saved.check_savable`), a model file of it loads to the
   same commands.
"""

from __future__ import annotations

import dataclasses
import tempfile
from pathlib import Path

import numpy as np

from .agent.protocol import freeze
from .config import ConditionConfig, Config
from .deploy.saved import check_savable, load_model, save_model
from .errors import ConfigError, JointAttentionError
from .experiment.cells import datasets_of, evaluator, make_agent, random_scene, run_cell
from .experiment.trial import SceneTrial, run_trial
from .models.registry import MODELS, ModelOptions
from .world.kinematics import HeadKinematics

__all__ = ["AgentCheckError", "check_agent"]

_PROTOCOL = ("begin_trial", "act", "end_trial")


class AgentCheckError(JointAttentionError, AssertionError):
    """A model failed one of :func:`check_agent`'s checks (the message names it)."""


def _require(ok: bool, kind: str, message: str) -> None:
    if not ok:
        raise AgentCheckError(f"model {kind!r}: {message}")


def _config(options: ModelOptions, n_steps: int, n_objects: int, seed: int,
            engine: str) -> Config:
    """A small run of one condition of ``options``' model in the fast world."""
    base = Config()
    experiment = dataclasses.replace(
        base.experiment, n_steps=n_steps, n_seeds=1, bin_steps=max(n_steps // 2, 1),
        engine=engine, conditions=(ConditionConfig(name="check", n_objects=n_objects),))
    return dataclasses.replace(base, seed=seed, model=options, experiment=experiment)


def _scene_trial(config: Config, condition: ConditionConfig, ds, rng):
    """A trial of the fast world in a scene drawn with ``rng``, and the caregiver's face."""
    kin = HeadKinematics.from_config(config.world)
    k, scene, _ = random_scene(config, ds, kin, condition.n_objects, rng)
    return SceneTrial(scene, ds.theta_face_rad[k], kinematics=kin,
                      max_steps=config.agent.max_steps, evaluate=evaluator(config)), ds.face[k]


def _first_trial(config: Config, condition: ConditionConfig, ds, kind: str):
    """A new agent of seed 0, its first trial in a scene of the run's seed, and its moves."""
    agent = make_agent(config, condition, 0, ds)
    missing = [m for m in _PROTOCOL if not callable(getattr(agent, m, None))]
    _require(not missing, kind, f"its agent has no {', '.join(missing)}")
    trial, face = _scene_trial(config, condition, ds, np.random.default_rng(config.seed))
    moves: list[tuple] = []
    act = agent.act

    def watched_act(detections, theta_rad):
        out = act(detections, theta_rad)
        moves.append(out)
        return out

    agent.act = watched_act
    try:
        result = run_trial(trial, agent, face)
    finally:
        del agent.act
    return agent, result, moves


def _same_moves(a: list[tuple], b: list[tuple]) -> bool:
    return len(a) == len(b) and all(
        np.array_equal(np.asarray(da), np.asarray(db), equal_nan=True) and ma == mb
        for (da, ma), (db, mb) in zip(a, b, strict=True))


def _same_cells(a: dict, b: dict) -> bool:
    return a.keys() == b.keys() and all(
        a[k].dtype == b[k].dtype and np.array_equal(a[k], b[k], equal_nan=True) for k in a)


def _learned_state(agent, faces: np.ndarray, thetas: np.ndarray) -> list[np.ndarray]:
    """What the agent learned: its model-file members and its commands on ``faces``."""
    state = []
    if hasattr(agent, "saved_arrays"):
        state += [np.array(v, copy=True) for v in agent.saved_arrays().values()]
    if hasattr(agent, "lm_commands"):
        state.append(np.asarray(agent.lm_commands(faces, thetas), dtype=float).copy())
    return state


def check_agent(options: ModelOptions, *, n_steps: int = 600, n_objects: int = 3,
                seed: int = 0) -> None:
    """Run the model of ``options`` through the checks (module docstring); None if it passes.

    Args:
        options: the model's options, registered in :data:`~jointattention.MODELS`.
        n_steps: learning time of the small cells the checks run.
        n_objects: objects in each trial.
        seed: the run's seed.

    Raises:
        AgentCheckError: naming the model and the first check that failed.
    """
    _require(isinstance(options, ModelOptions), type(options).__name__,
             "expected a ModelOptions section (a subclass with param fields)")
    try:
        kind = MODELS.name_of(options)
    except KeyError:
        raise AgentCheckError(f"{type(options).__name__}: not registered; expected "
                              "MODELS.register(name, Options) first") from None
    _require(isinstance(options.label, str) and bool(options.label), kind, "no label")
    config = _config(options, n_steps, n_objects, seed, "python")
    condition = config.experiment.conditions[0]
    ds = datasets_of(config)

    # 2. the protocol, one trial by hand
    agent, result, moves = _first_trial(config, condition, ds, kind)
    for dtheta, module in moves:
        step = np.asarray(dtheta)
        _require(step.shape == (2,) and np.isfinite(step).all(), kind,
                 f"act returned {dtheta!r}; expected a finite (pan, tilt) step, shape (2,)")
        _require(isinstance(module, str) and bool(module), kind,
                 f"act named its module {module!r}; expected a non-empty string")
    _require(agent.learning_time_steps == result.n_steps, kind,
             f"learning_time_steps = {agent.learning_time_steps} after a first trial of "
             f"{result.n_steps} steps; expected it to count the steps it learned in")

    # 3. the same seed, the same moves and the same cell
    _require(_same_moves(moves, _first_trial(config, condition, ds, kind)[2]), kind,
             "two new agents of the same seed moved differently in the same first trial; "
             "expected each object to draw from its own generator (passed as rng), and nothing "
             "from global state")
    cell = run_cell(config, condition, 0)
    _require(_same_cells(cell, run_cell(config, condition, 0)), kind,
             "two cells of the same seed differ; expected each object to draw from its own "
             "generator (passed as rng), and nothing from global state")

    # 4. the engines it declares
    if options.compiled_refusal() is None:
        compiled = run_cell(_config(options, n_steps, n_objects, seed, "compiled"), condition, 0)
        _require(_same_cells(cell, compiled), kind, "it declares compiled = True, but the "
                 "compiled cell differs from the step-by-step cell")

    # 5. frozen, it learns nothing
    learned = []
    run_cell(config, condition, 0, checkpoints=(n_steps,), on_checkpoint=lambda t, a:
             learned.append(a))
    trained = learned[-1] if learned else agent
    faces, thetas = ds.face[:20], ds.theta_face_rad[:20]
    if hasattr(trained, "learning"):
        frozen = freeze(trained)
        before, steps = _learned_state(frozen, faces, thetas), frozen.learning_time_steps
        rng = np.random.default_rng(seed + 1)
        for _ in range(5):
            trial, face = _scene_trial(config, condition, ds, rng)
            run_trial(trial, frozen, face)
        after = _learned_state(frozen, faces, thetas)
        _require(frozen.learning_time_steps == steps
                 and all(np.array_equal(a, b, equal_nan=True) for a, b in zip(before, after,
                                                                              strict=True)),
                 kind, "with learning = False it still changed what it learned")

    # 6. a model file, if it declares one and this short run may be saved (the developmental
    # model's faces are still blurred before blur_sharp_steps)
    try:
        check_savable(config, condition.name)
    except ConfigError:
        return
    with tempfile.TemporaryDirectory() as folder:
        path = save_model(trained, Path(folder) / "model.npz", config=config,
                          condition=condition.name)
        loaded = load_model(path)
    _require(np.array_equal(loaded.agent.lm_commands(faces, thetas),
                            trained.lm_commands(faces, thetas)), kind,
             "its model file loads to other commands than the agent saved")
