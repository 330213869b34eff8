"""The modes without images' episodes in arrays, each step one compiled call.

:class:`FastSteps` holds what the kernels (:mod:`._vector_kernels`) need of an environment
without images, starts :class:`Episodes` and makes the arrays a step fills; the native vector
environment keeps ``num_envs`` episodes, and the single environment's trial, :class:`FastTrial`,
one, each step one call of :func:`~._vector_kernels.step_all`. They are the
episodes of a :class:`~jointattention.experiment.trial.SceneTrial` over the runner's
``random_scene``: the same draws, moves, looks, ends, observations and ``info``
(``tests/test_env_modes.py``). Python's share of a step is the few arrays it hands out.
"""

from __future__ import annotations

import numpy as np

from ..errors import ConfigError
from ..experiment.cells import trial_geometries
from ..experiment.trial import END_FIRED, RUNNING
from ..world.mjcf import HEAD_RADII_M
from ..world.placement import region_of
from ._observation import (
    _SCALED_ROW_BOUNDS,
    DETECTION_COLUMNS,
    MAX_DETECTIONS,
    _row_bounds,
    info_dict,
)
from ._vector_kernels import CAM, FLAGS, STATE, STEP, start_all, step_all

__all__ = ["Episodes", "FastSteps", "FastTrial"]

_N_STEPS, _END, _TARGET = (STATE.index(name) for name in ("n_steps", "end", "target"))


class Episodes:
    """The arrays of ``k`` episodes of ``n`` objects: one row per sub-environment.

    ``theta`` the head angles; ``pos``, ``radius``, ``edge`` the scenes; ``state`` the
    counters (:data:`~._vector_kernels.STATE`); ``looks`` the last look's detections.
    """

    def __init__(self, k: int, n: int):
        self.theta, self.pos = np.zeros((k, 2)), np.zeros((k, n, 3))
        self.radius, self.edge = np.zeros((k, n)), np.zeros((k, n))
        self.state = np.zeros((k, len(STATE)), np.int64)
        self.state[:, _END] = RUNNING
        self.looks = np.zeros((k, n, 4))


class FastSteps:
    """What the kernels need of an environment without images, and the arrays a step hands out.

    ``env``: a :class:`~.joint_attention.JointAttentionEnv`; ``faces``: every data set's face
    as the observation shows it (v2: scaled, float32).
    """

    def __init__(self, env):
        kin, cfg, ds = env.kinematics, env.config, env._datasets
        limits = env.joint_limits_rad
        mid, half = limits.mean(axis=1), (limits[:, 1] - limits[:, 0]) / 2  # as _observation.scaled
        self.n, self.max_steps = env.n_objects, env.max_steps
        self.scaled, self.with_rows = env.scaled_obs, env.obs_mode == "detections"
        self.cam = np.array([kin.pan_limits_rad[0], kin.tilt_limits_rad[0],
                             kin.pan_limits_rad[1], kin.tilt_limits_rad[1], *kin.offset_m,
                             kin.focal_px, kin.width_px, kin.height_px,
                             cfg.agent.d_th_px(kin.width_px), *mid, *half], float)
        assert len(self.cam) == len(CAM)
        self.bounds = np.array([*_row_bounds((kin.height_px, kin.width_px)),
                                *_SCALED_ROW_BOUNDS], np.float32)
        self.targets_m, self.faces_m = trial_geometries(ds, kin, cfg.world.caregiver.distance_m)
        self.region = region_of(cfg.world)
        self.theta_face_rad = ds.theta_face_rad
        # as _observation.scaled scales one face: the same float32 operations, once per data set
        self.faces = np.ascontiguousarray(  # the kernel copies them as rows of pixels
            (ds.face / np.float32(255) - np.float32(0.5)).astype(np.float32) if self.scaled
            else ds.face)
        self.no_faces = np.zeros((0, *ds.face.shape[1:]), self.faces.dtype)
        self.no_rows = np.zeros((0, MAX_DETECTIONS, len(DETECTION_COLUMNS)), np.float32)
        self._shapes: dict[tuple[int, int], tuple] = {}  # outputs' shapes by (k, masks)

    def start(self, episodes: Episodes, rngs, starts: np.ndarray) -> None:
        """Start the episodes where ``starts`` (bool) is true, each from its own generator.

        ``rngs``: the generators in numba's list.
        """
        self.check_started(start_all(rngs, starts, *self.start_args(), self.cam, episodes.pos,
                                     episodes.radius, episodes.edge, episodes.state,
                                     episodes.theta))

    def start_args(self) -> tuple:
        """:func:`~._vector_kernels.start_all`'s arguments from ``targets_m`` to the camera."""
        return (self.targets_m, self.faces_m, HEAD_RADII_M[2], *self.region,
                self.theta_face_rad)

    def check_started(self, failed: int) -> None:
        """One error if a start could not place its objects (``failed`` >= 0: which one)."""
        if failed >= 0:
            raise ConfigError(
                f"objects: could not place {self.n} objects apart within the object region; "
                "expected fewer objects, a wider region or smaller gaps")

    def kernel_args(self, episodes: Episodes, faces: bool = True) -> tuple:
        """The arguments of :func:`~._vector_kernels.step_all` that a step does not change.

        Those after ``starts``, ``then`` and ``dtheta``, up to the outputs (:meth:`outputs`);
        ``faces``: whether it writes the faces too.
        """
        return (self.cam, self.max_steps, episodes.pos, episodes.radius, episodes.edge,
                episodes.state, episodes.theta, episodes.looks,
                self.faces if faces else self.no_faces, self.bounds, self.scaled,
                self.with_rows)

    def outputs(self, k: int, masks: int = 0) -> tuple:
        """New arrays for one step of ``k`` episodes (those handed out are never reused).

        :func:`~._vector_kernels.step_all`'s last arguments: head, face, rows, centre, det,
        ints, flags, floats. ``masks``: rows after the flags, which the step sets True:
        Gymnasium's ``_key`` masks.
        """
        shapes = self._shapes.get((k, masks))
        if shapes is None:  # worked out once: a step of 64 sub-environments is short
            shapes = self._shapes[k, masks] = (
                (k, 2), (k, *self.faces.shape[1:]), (k, MAX_DETECTIONS, len(DETECTION_COLUMNS)),
                (k, MAX_DETECTIONS, 2), (3, k, MAX_DETECTIONS), (4, k), (len(FLAGS) + masks, k),
                (3, k))
        (h, f, r, c, d, i, g, x), empty = shapes, np.empty
        return (empty(h, np.float32), empty(f, self.faces.dtype),
                empty(r, np.float32) if self.with_rows else self.no_rows, empty(c), empty(d),
                empty(i, np.int64), empty(g, bool), empty(x))


class FastTrial:
    """The single environment's episode without images: a vector of one for the kernels.

    What the environment's ``step`` and ``_look`` ask of a trial: ``end`` (None while it
    runs), ``step(dtheta_rad)`` and the observation and ``info`` of the last look
    (:meth:`looks`). ``face`` is the episode's face as the observation shows it.
    """

    _START, _GOES_ON = np.ones(1, bool), np.zeros(1, bool)

    def __init__(self, steps: FastSteps, rngs):
        self.episodes = Episodes(1, steps.n)
        steps.start(self.episodes, rngs, self._START)
        self.face_k = int(self.episodes.state[0, -1])
        self.face = steps.faces[self.face_k]
        self._with_rows, self._no_faces, self._no_rows = (steps.with_rows, steps.no_faces,
                                                          steps.no_rows)
        self._fixed = steps.kernel_args(self.episodes, faces=False)
        self._dtheta = np.zeros((1, 2))
        # the outputs the environment reads as Python numbers: kept, not handed out
        self._scratch = (np.empty((4, 1), np.int64), np.empty((len(FLAGS), 1), bool),
                         np.empty((3, 1)))
        self._look(self._START)

    def _look(self, starts: np.ndarray) -> None:
        head, centre = np.empty((1, 2), np.float32), np.empty((1, MAX_DETECTIONS, 2))
        det = np.empty((3, 1, MAX_DETECTIONS))
        rows = (np.empty((1, MAX_DETECTIONS, len(DETECTION_COLUMNS)), np.float32)
                if self._with_rows else self._no_rows)
        self._error = step_all(starts, STEP, self._dtheta, *self._fixed, head, self._no_faces,
                               rows, centre, det, *self._scratch)
        self._out = head, rows, centre, det
        self._state = self.episodes.state[0].tolist()
        end = self._state[_END]
        self.end = None if end == RUNNING else end

    def step(self, dtheta_rad) -> None:
        """Move the head by ``dtheta_rad`` (stopping at the joint limits), look, evaluate."""
        if self.end is not None:
            raise RuntimeError("the trial has ended; expected a new trial")
        self._dtheta[0, 0], self._dtheta[0, 1] = dtheta_rad[0], dtheta_rad[1]
        self._look(self._GOES_ON)

    @property
    def theta_rad(self) -> np.ndarray:
        """The head angle now."""
        return self.episodes.theta[0].copy()

    @property
    def target_pos_m(self) -> np.ndarray:
        """Where the caregiver's target is, in the robot's frame (m)."""
        return self.episodes.pos[0, self.episodes.state[0, _TARGET]].copy()

    @property
    def n_steps(self) -> int:
        """The steps taken so far (as :class:`~jointattention.experiment.trial.SceneTrial`)."""
        return int(self.episodes.state[0, _N_STEPS])

    def looks(self) -> tuple[dict, dict]:
        """The observation and ``info`` of the last look (new arrays each time)."""
        head, rows, centre, det = self._out
        obs = {"head_angle": head[0], "face": self.face.copy()}
        if self._with_rows:
            obs["detections"] = rows[0]
        _, end, limit_hit, attended, seen, n_det, target, _ = self._state
        fired = end == END_FIRED
        info = info_dict((centre[0], det[0, 0], det[1, 0], det[2, 0]), (
            n_det, fired, seen if fired else -1, attended, target, limit_hit != 0,
            float(fired), float(fired and attended == target), self._error))
        return obs, info
