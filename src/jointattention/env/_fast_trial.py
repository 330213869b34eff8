"""The modes without images' episodes in arrays, each step one compiled call.

:class:`FastSteps` holds what the kernels (:mod:`._vector_kernels`) need of an environment
without images, and starts and steps :class:`Episodes`; the native vector environment keeps
``num_envs`` of them, and the single environment's trial, :class:`FastTrial`, one. They are the
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
from ._looks import _SCALED_ROW_BOUNDS, DETECTION_COLUMNS, MAX_DETECTIONS, _row_bounds
from ._vector_kernels import CAM, LOOK, STATE, STEP, start_all, step_all

__all__ = ["Episodes", "FastSteps", "FastTrial"]

_END = STATE.index("end")


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
        mid, half = limits.mean(axis=1), (limits[:, 1] - limits[:, 0]) / 2  # as _looks.scaled
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
        # as _looks.scaled scales one face: the same float32 operations, once per data set
        self.faces = (ds.face / np.float32(255) - np.float32(0.5)).astype(np.float32) \
            if self.scaled else ds.face
        self.no_faces = np.zeros((0, *ds.face.shape[1:]), self.faces.dtype)
        self.no_rows = np.zeros((0, MAX_DETECTIONS, len(DETECTION_COLUMNS)), np.float32)

    def start(self, episodes: Episodes, rngs, which: np.ndarray) -> None:
        """Start the episodes of ``which``, each from its own generator (numba's list)."""
        failed = start_all(rngs, which, self.targets_m, self.faces_m, HEAD_RADII_M[2],
                           *self.region, self.theta_face_rad, self.cam, episodes.pos,
                           episodes.radius, episodes.edge, episodes.state, episodes.theta)
        if failed >= 0:
            raise ConfigError(
                f"objects: could not place {self.n} objects apart within the object region; "
                "expected fewer objects, a wider region or smaller gaps")

    def step(self, episodes: Episodes, mode: np.ndarray, dtheta: np.ndarray, out: dict,
             faces: bool = True) -> float:
        """Step each episode as ``mode`` says (:func:`~._vector_kernels.step_all`) into ``out``.

        ``out``: :meth:`outputs`'s arrays (or the single trial's); ``faces``: whether to write
        the faces too. Returns the first episode's caregiver error.
        """
        return step_all(mode, dtheta, self.cam, self.max_steps, episodes.pos, episodes.radius,
                        episodes.edge, episodes.state, episodes.theta, episodes.looks,
                        self.faces if faces else self.no_faces, self.bounds, self.scaled,
                        self.with_rows, out["head"], out["face"], out["rows"], out["centre"],
                        out["det"], out["ints"], out["flags"], out["floats"])

    def outputs(self, k: int, faces: bool = True) -> dict:
        """New arrays for one step of ``k`` episodes (those handed out are never reused)."""
        face = self.faces.shape[1:]
        return {"head": np.empty((k, 2), np.float32),
                "face": np.empty((k, *face), self.faces.dtype) if faces else self.no_faces,
                "rows": (np.empty((k, MAX_DETECTIONS, len(DETECTION_COLUMNS)), np.float32)
                         if self.with_rows else self.no_rows),
                "centre": np.empty((k, MAX_DETECTIONS, 2)),
                "det": np.empty((3, k, MAX_DETECTIONS)), "ints": np.empty((4, k), np.int64),
                "flags": np.empty((4, k), bool), "floats": np.empty((3, k))}


class FastTrial:
    """The single environment's episode without images: a vector of one for the kernels.

    What the environment's ``step`` and ``_look`` ask of a trial: ``end`` (None while it
    runs), ``step(dtheta_rad)`` and the observation and ``info`` of the last look
    (:meth:`looks`). ``face`` is the episode's face as the observation shows it.
    """

    _LOOK, _STEP = np.array([LOOK], np.int64), np.array([STEP], np.int64)

    def __init__(self, steps: FastSteps, rngs):
        self.steps, self.episodes = steps, Episodes(1, steps.n)
        steps.start(self.episodes, rngs, np.zeros(1, np.int64))
        self.face_k = int(self.episodes.state[0, -1])
        self.face = steps.faces[self.face_k]
        self._dtheta = np.zeros((1, 2))
        # the outputs the environment reads as Python numbers: kept, not handed out
        self._scratch = {"ints": np.empty((4, 1), np.int64), "flags": np.empty((4, 1), bool),
                         "floats": np.empty((3, 1)), "face": steps.no_faces}
        self._look(self._LOOK)

    def _look(self, mode: np.ndarray) -> None:
        steps = self.steps
        out = {"head": np.empty((1, 2), np.float32),
               "rows": (np.empty((1, MAX_DETECTIONS, len(DETECTION_COLUMNS)), np.float32)
                        if steps.with_rows else steps.no_rows),
               "centre": np.empty((1, MAX_DETECTIONS, 2)), "det": np.empty((3, 1, MAX_DETECTIONS)),
               **self._scratch}
        self._error = steps.step(self.episodes, mode, self._dtheta, out, faces=False)
        self._out = out
        self._state = self.episodes.state[0].tolist()
        end = self._state[_END]
        self.end = None if end == RUNNING else end

    def step(self, dtheta_rad) -> None:
        """Move the head by ``dtheta_rad`` (stopping at the joint limits), look, evaluate."""
        if self.end is not None:
            raise RuntimeError("the trial has ended; expected a new trial")
        self._dtheta[0, 0], self._dtheta[0, 1] = dtheta_rad[0], dtheta_rad[1]
        self._look(self._STEP)

    @property
    def theta_rad(self) -> np.ndarray:
        """The head angle now."""
        return self.episodes.theta[0].copy()

    def looks(self) -> tuple[dict, dict]:
        """The observation and ``info`` of the last look (new arrays each time)."""
        out = self._out
        obs = {"head_angle": out["head"][0], "face": self.face.copy()}
        if self.steps.with_rows:
            obs["detections"] = out["rows"][0]
        _, end, limit_hit, attended, seen, n_det, target, _ = self._state
        fired = end == END_FIRED
        det = out["det"]
        info = {"detections": {"centre_px": out["centre"][0], "colour_area_px": det[0, 0],
                               "edge": det[1, 0], "motion": det[2, 0]},
                "n_detections": n_det, "fired": fired, "seen": seen if fired else -1,
                "attended": attended, "target": target, "limit_hit": limit_hit != 0,
                "intrinsic_reward": float(fired),
                "external_reward": float(fired and attended == target),
                "caregiver_error_rad": self._error}
        return obs, info

    def __getstate__(self) -> dict:
        """All but the environment's :class:`FastSteps` (its data sets' faces).

        A copy of the environment gives its trial its own (``JointAttentionEnv.__setstate__``).
        """
        return {**self.__dict__, "steps": None}
