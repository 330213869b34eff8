"""Learned models in a file: saved after learning, loaded on a robot, never unpickled.

On-disk format: one NumPy ``.npz`` archive whose members are plain arrays (loading one never
runs code: :func:`~jointattention._readers.read_npz` refuses pickled members). Schema version
1 holds the paper's network; version 2 (``learner = "population"``) adds the population code.

==========================  =======  ============  ==========================================
member                      dtype    shape         meaning
==========================  =======  ============  ==========================================
``schema_version``          int      ()            ``1``, or ``2`` with the population code
``w1``                      float64  (n_hid, n_in) input weights; ``n_in`` = face pixels + 2
``b1``                      float64  (n_hid,)      hidden biases
``w2``                      float64  (n_hid, 2)    output weights
``b2``                      float64  (2,)          output biases
``face_mean``               float64  (n_in - 2,)   per-pixel mean of the faces seen (H x W)
``face_m2``                 float64  (n_in - 2,)   per-pixel sum of squared deviations
``face_n_seen``             int      ()            faces seen (>= 1)
``population_w1``           float64  (h, n_feat)   version 2: its input weights (features)
``population_b1``           float64  (h,)          version 2: its hidden biases
``population_w2``           float64  (bins, h)     version 2: its output weights
``population_b2``           float64  (bins,)       version 2: its output biases
``population_hidden_mean``  float64  (h,)          version 2: the hidden units' running mean
``population_feature_*``    float64  (n_feat - 2,) with ``standardise``: the features'
                                                   ``_mean``, ``_m2``, ``_n_seen`` (int, ())
``meta``                    str      ()            JSON text, below
==========================  =======  ============  ==========================================

``meta`` holds ``robot`` (:class:`Robot`: the body the model was learned on), ``model`` (its
kind, ``bootstrap`` (with the back-propagation or the population learner), ``teacher`` or
``developmental`` (saved once it sees sharp faces), the condition, the learning time),
``config`` (the run's whole configuration as TOML, from which the model's options and the face
standardiser's floor are read), ``datasets_sha256`` (of the data-set file it learned from),
``datasets_scenes_sha256`` (of the scenes in it, :func:`~jointattention.datasets.scenes_sha256`:
the same for the same recording made on another machine), ``caregivers`` (who posed them, as
:func:`~jointattention.world.recording.caregivers_of` gives them: the identities an unseen
caregiver's novelty is measured from; absent for a robot's recording),
``generator`` (the package version) and, if measured, ``held_out`` (its frozen success and
errors on its training sets, new poses and unseen caregivers at the end of learning). Float
members must be finite and within ±1e6 (sums of squares ±1e18). The output is a direction, one
``lm_step_deg`` long (docs/real-head.md).
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from functools import cached_property
from pathlib import Path

import numpy as np

from .._arrays import angles, views
from .._checks import check_path, short_repr
from .._files import save_npz
from .._readers import loads_json, loads_toml, read_npz
from .._version import __version__
from ..agent.protocol import Body, freeze
from ..config import Config, check_config, condition_named, load_config, model_options, to_toml
from ..errors import ArgumentError, ConfigError, FileError
from ..models.bootstrap import BootstrapAgent
from ..models.registry import MODELS, ModelOptions

__all__ = ["SCHEMA_VERSION", "LMTrial", "LearnedModel", "Robot", "check_savable", "load_model",
           "save_model"]

_MAX_WEIGHT_ABS, _MAX_SUM_ABS = 1e6, 1e18  # beyond: not learned, and commands overflow to NaN

SCHEMA_VERSION = 2  # the newest; version 1 files (the paper's network) are still written


@dataclass(frozen=True)
class Robot:
    """The body a model was learned on; a model runs only on the same one.

    Attributes:
        image_size_px: (W, H) of the camera image.
        fov_deg: horizontal field of view.
        pan_limits_deg, tilt_limits_deg: the joint ranges (the head angle is scaled by them).
        face_size_px: (width, height) of the face window.
        lm_step_deg: length of one step of the learning module.
        eye_size_px: (width, height) of the eye window seen through its fovea, or None.
    """

    image_size_px: tuple[int, int]
    fov_deg: float
    pan_limits_deg: tuple[float, float]
    tilt_limits_deg: tuple[float, float]
    face_size_px: tuple[int, int]
    lm_step_deg: float
    eye_size_px: tuple[int, int] | None = None

    @classmethod
    def of(cls, config: Config) -> Robot:
        """The robot of a configuration."""
        w = config.world
        return cls((w.camera.width_px, w.camera.height_px), float(w.camera.fov_deg),
                   tuple(map(float, w.head.pan_limits_deg)),
                   tuple(map(float, w.head.tilt_limits_deg)),
                   (w.face_window.width_px, w.face_window.height_px),
                   float(config.agent.lm_step_deg),
                   w.eye_window.kept_size_px if w.eye_window.enabled
                   else None)

    @property
    def body(self) -> Body:
        """What the agent knows of this body."""
        return Body(self.image_size_px, (tuple(np.deg2rad(self.pan_limits_deg)),
                                         tuple(np.deg2rad(self.tilt_limits_deg))),
                    self.face_size_px, self.eye_size_px)

    def differences(self, other: Robot) -> list[str]:
        """The fields in which ``other`` differs from this robot."""
        mine, theirs = asdict(self), asdict(other)
        return [k for k in mine if (mine[k] is None) != (theirs[k] is None) or (
            mine[k] is not None and not np.allclose(mine[k], theirs[k], rtol=0, atol=1e-9))]


class LMTrial:
    """The learning module through one trial, moving the head as it did when it led in learning.

    A bootstrap agent's module reads the view once, with the head at the face, then each step
    moves toward what it read: the population code along its line from the face, the memory
    toward its recalled place, the paper's network by its command at each head angle. So a
    robot follows a gaze by one look at the face and then steps, not by a new look at every
    frame (that reads the face from a head turned away, which these modules never learned
    from). A model with no such module gives its learning module's command at each step.
    """

    def __init__(self, agent, view: np.ndarray, theta_rad: np.ndarray):
        self._agent, self._view = agent, view
        self._module = getattr(agent, "module", None)
        if self._module is not None:
            self._module.begin(views("view", view, agent.body), theta_rad)

    def step(self, theta_rad, detections=None) -> np.ndarray:
        """(dpan, dtilt) in radians, one step, from the head at ``theta_rad``.

        ``detections``: what the robot's detector reports at this step, for a module that
        looks (the memory's); None: nothing is observed.
        """
        theta = angles("theta_rad", theta_rad)
        if self._module is None:
            return self._agent.lm_command(self._view, theta)
        if detections is not None:
            self._module.observe(detections, theta)
        return self._module.step(theta)


@dataclass(frozen=True)
class LearnedModel:
    """A learned agent (bootstrap or teacher) and the robot, configuration and data it had."""

    agent: BootstrapAgent
    config: Config
    condition: str
    datasets_sha256: str | None = None
    held_out: dict | None = None  # {kind: {measure: value}} at the end of learning, if measured
    scenes_sha256: str | None = None  # of its data sets' scenes (files of before: None)
    # Who posed them, if they say: each identity as written (dataclasses.asdict of the world's
    # Caregiver, which world.identity.caregiver_from_dict reads; the robot's side never does).
    caregivers: tuple[dict, ...] | None = None

    @property
    def robot(self) -> Robot:
        """The robot it was learned on."""
        return Robot.of(self.config)

    def lm_command(self, face_window: np.ndarray, theta_rad) -> np.ndarray:
        """The learning module's (dpan, dtilt) in radians, one step long, for a face window.

        ``face_window``: (H, W) grey levels of the robot's face window size (a robot with an
        eye window: its view, :attr:`~jointattention.agent.protocol.Body.view_size` grey levels
        flat); ``theta_rad``: the head's (pan, tilt) at the face. Anything else is refused
        (ArgumentError) before the compiled kernels, which read the window by the learned size,
        see it.
        """
        return self.agent.lm_command(face_window, angles("theta_rad", theta_rad))

    def lm_trial(self, view: np.ndarray, theta_rad) -> LMTrial:
        """The learning module's trial from ``view``, the head at the face at ``theta_rad``.

        ``view`` as :meth:`lm_command` takes it. Its :meth:`~LMTrial.step` moves the head as
        the module moved it when it led in learning. The model learns nothing from it; one
        trial runs at a time (a new one ends the one before).
        """
        return LMTrial(self._following, view, angles("theta_rad", theta_rad))

    @cached_property
    def _following(self):
        """A frozen copy of the agent whose module runs the trials (:meth:`lm_trial`)."""
        return freeze(self.agent)

    def face_template(self) -> np.ndarray:
        """The mean of the faces it learned from, (H, W) uint8: a template to find them."""
        w, h = self.robot.face_size_px
        mean = self.agent.faces.mean_[: w * h]  # the view's face window (Body.view_size)
        return np.clip(np.rint(mean), 0, 255).astype(np.uint8).reshape(h, w)

    def save(self, path: str | Path) -> Path:
        """Write the model to ``path`` (.npz) atomically (see the module docstring)."""
        return save_model(self.agent, path, config=self.config, condition=self.condition,
                          datasets_sha256=self.datasets_sha256, held_out=self.held_out,
                          scenes_sha256=self.scenes_sha256, caregivers=self.caregivers)


def check_savable(config: Config, condition: str) -> ModelOptions:
    """The options of ``condition``'s model if it can be saved, else one ConfigError line."""
    options = model_options(config, condition_named(config, condition))
    refusal = options.save_refusal()
    if refusal is not None:
        raise ConfigError(f"condition {condition!r}: its model is {options.label}: {refusal}; "
                          "expected the bootstrap model, the teacher or the developmental "
                          "model, with learner = 'backprop' or 'population' (the models saved)")
    n, sharp = config.experiment.n_steps, getattr(options, "blur_sharp_steps", 0)
    if getattr(options, "blur_start_px", 0) > 0 and n < sharp:  # saved: sees sharp faces
        raise ConfigError(f"condition {condition!r}: n_steps = {n} ends while the faces are "
                          f"blurred; expected n_steps >= blur_sharp_steps = {sharp:g}")
    return options


def save_model(agent: BootstrapAgent, path: str | Path, *, config: Config, condition: str,
               datasets_sha256: str | None = None, held_out: dict | None = None,
               scenes_sha256: str | None = None,
               caregivers: Sequence[dict] | None = None) -> Path:
    """Write a learned agent of ``config``'s condition ``condition`` to ``path`` (.npz).

    ``held_out``: its held-out measures, kept in ``meta`` as they are (JSON);
    ``datasets_sha256`` and ``scenes_sha256``: of the data sets it learned from (their file,
    their scenes), ``caregivers`` who posed them.
    """
    path, config = Path(check_path(path, "path")), check_config(config)
    if not isinstance(agent, BootstrapAgent):  # the teacher and developmental agents are ones
        raise ArgumentError(f"agent {short_repr(agent)}: expected a learned agent of the "
                            "bootstrap, teacher or developmental model")
    if path.suffix != ".npz":
        raise FileError(f"{path}: expected a model file name ending in .npz")
    options = check_savable(config, condition)
    if agent.faces.n_seen_ < 1:
        raise ConfigError(f"{path}: the agent has seen no face; expected a learned agent")
    if getattr(agent, "blur_px", lambda: 0.0)() > 0:  # a saved model sees sharp faces
        raise ConfigError(f"{path}: the developmental agent still sees the face blurred (s.d. "
                          f"{agent.blur_px():.2f} px at learning time "
                          f"{agent.learning_time_steps}); expected a learning time of at least "
                          f"blur_sharp_steps = {agent.options.blur_sharp_steps:g}")
    meta = {"robot": asdict(Robot.of(config)),
            "model": {"kind": MODELS.name_of(options), "condition": condition,
                      "learning_time_steps": int(agent.learning_time_steps)},
            "config": to_toml(config), "datasets_sha256": datasets_sha256,
            **({} if scenes_sha256 is None else {"datasets_scenes_sha256": scenes_sha256}),
            **({} if caregivers is None else {"caregivers": list(caregivers)}),
            "generator": f"jointattention {__version__}",
            **({} if held_out is None else {"held_out": held_out})}
    version = 1 if options.learner == "backprop" else 2  # version 1 files stay as they were
    return save_npz(path, {"schema_version": np.array(version), **agent.saved_arrays(),
                           "meta": np.array(json.dumps(meta))})


def _field(where: str, key: str, expected: str, got) -> FileError:
    return FileError(f"{where}: field '{key}': expected {expected}, got {got}")


def _array(archive: dict, where: str, key: str, shape: tuple, kind: str = "f") -> np.ndarray:
    a = archive[key]
    if a.dtype.kind not in kind or a.shape != shape:
        raise _field(where, key, f"{'a float' if kind == 'f' else 'an integer'} array of shape "
                     f"{shape}", f"{a.dtype} array of shape {a.shape}")
    if kind == "f" and not np.all(np.isfinite(a)):
        raise _field(where, key, "finite values", f"{np.count_nonzero(~np.isfinite(a))} "
                     "non-finite")
    bound = _MAX_SUM_ABS if key.endswith("m2") else _MAX_WEIGHT_ABS
    if kind == "f" and a.size and np.abs(a).max() > bound:
        raise _field(where, key, f"values within ±{bound:.0e}", f"{np.abs(a).max():.3g}")
    return a


def _meta(archive: dict, where: str) -> dict:
    try:
        meta = loads_json(str(archive["meta"]))
    except ValueError:
        meta = None
    if archive["meta"].shape != () or not isinstance(meta, dict):
        raise _field(where, "meta", "JSON text of an object", repr(str(archive["meta"]))[:60])
    for key, kind in (("robot", dict), ("model", dict), ("config", str)):
        if not isinstance(meta.get(key), kind):
            raise _field(where, f"meta.{key}", f"a {kind.__name__}", repr(meta.get(key))[:60])
    model = meta["model"]
    if not isinstance(model.get("condition"), str):
        raise _field(where, "meta.model.condition", "a condition name",
                     repr(model.get("condition"))[:60])
    steps = model.get("learning_time_steps")
    if type(steps) is not int or steps < 0:
        raise _field(where, "meta.model.learning_time_steps", "an integer >= 0", repr(steps)[:60])
    return meta


def _robot(meta: dict, config: Config, where: str) -> Robot:
    """The file's robot, checked against the one its configuration describes."""
    robot = Robot.of(config)
    saved = meta["robot"]
    for key, value in asdict(robot).items():
        got = saved.get(key)
        if value is None or got is None:  # an optional part (eye_size_px; absent before it)
            if got is not value:
                raise _field(where, f"meta.robot.{key}", f"{value} (the robot of the file's "
                             "configuration)", repr(got)[:60])
            continue
        numbers = got if isinstance(got, list) else [got]
        if (not all(type(v) in (int, float) and math.isfinite(v) for v in numbers)
                or np.shape(got) != np.shape(value)
                or not np.allclose(got, value, rtol=0, atol=1e-9)):
            raise _field(where, f"meta.robot.{key}", f"{value} (the robot of the file's "
                         "configuration)", repr(got)[:60])
    return robot


def load_model(path: str | Path, *, robot: Robot | None = None) -> LearnedModel:
    """Read and check a saved model; any problem is one :class:`FileError` naming the field.

    ``robot``: the body it will run on; a model learned on another is refused.
    """
    where = str(check_path(path, "path"))
    if robot is not None and not isinstance(robot, Robot):
        raise ArgumentError(f"robot {short_repr(robot)}: expected a Robot (Robot.of(config)) "
                            "or None")
    archive = read_npz(path, "a model .npz file (jointattention train --out)")
    missing = [k for k in ("schema_version", "meta") if k not in archive]
    if missing:
        raise FileError(f"{where}: field '{missing[0]}' is missing; expected a model file "
                        "(jointattention train --out)")
    version = int(_array(archive, where, "schema_version", (), "iu"))
    if version not in (1, 2):
        raise _field(where, "schema_version", "1 or 2", version)
    meta = _meta(archive, where)
    try:
        config = load_config(loads_toml(meta["config"]))
        options = check_savable(config, meta["model"]["condition"])
    except ValueError as err:  # TOMLDecodeError, too deep, ConfigError
        raise FileError(f"{where}: field 'meta.config': {err}") from None
    kind = MODELS.name_of(options)
    if meta["model"].get("kind") != kind:
        raise _field(where, "meta.model.kind", f"{kind!r} (the model of its configuration)",
                     repr(meta["model"].get("kind"))[:60])
    saved = _robot(meta, config, where)
    if robot is not None and saved.differences(robot):
        key = saved.differences(robot)[0]
        raise _field(where, f"meta.robot.{key}", f"{getattr(robot, key)} (this robot's)",
                     getattr(saved, key))
    if version != (1 if options.learner == "backprop" else 2):
        raise _field(where, "schema_version", f"{2 - (options.learner == 'backprop')} (the "
                     f"version of learner {options.learner!r})", version)
    agent = options.build(config.agent, saved.body, np.random.default_rng(0))
    shapes = agent.saved_shapes()
    missing = [k for k in shapes if k not in archive]
    if missing:
        raise FileError(f"{where}: field '{missing[0]}' is missing; expected a model file "
                        "(jointattention train --out)")
    unknown = sorted(set(archive) - {"schema_version", *shapes, "meta"})
    if unknown:
        raise FileError(f"{where}: field '{unknown[0]}' is not part of model schema version "
                        f"{version}")
    arrays = {k: _array(archive, where, k, shape, "iu" if k.endswith("n_seen") else "f")
              for k, shape in shapes.items()}
    if np.any(arrays["face_m2"] < 0):
        raise _field(where, "face_m2", "sums of squares >= 0", "a negative value")
    if not 1 <= int(arrays["face_n_seen"]) <= 2**62:
        raise _field(where, "face_n_seen", "an integer >= 1", int(arrays["face_n_seen"]))
    agent.load_arrays(arrays)
    agent.learning_time_steps = meta["model"]["learning_time_steps"]
    held_out, scenes = meta.get("held_out"), meta.get("datasets_scenes_sha256")
    return LearnedModel(agent, config, meta["model"]["condition"], meta.get("datasets_sha256"),
                        held_out if isinstance(held_out, dict) else None,
                        scenes if isinstance(scenes, str) else None, _caregivers(meta, where))


def _caregivers(meta: dict, where: str) -> tuple[dict, ...] | None:
    """``meta["caregivers"]`` (None if absent); one FileError if not a list of tables."""
    people = meta.get("caregivers")
    if people is None:
        return None
    if not isinstance(people, list) or not people:
        raise _field(where, "meta.caregivers", "a list of identities", repr(people)[:60])
    for i, person in enumerate(people):
        if not isinstance(person, dict):
            raise _field(where, f"meta.caregivers[{i}]", "a table of an identity's fields",
                         repr(person)[:60])
    return tuple(people)
