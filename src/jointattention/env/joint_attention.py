"""The Gymnasium environment ``JointAttention-v0``: one trial per episode.

Its docstring is its manual. Needs the ``gym`` extra (``pip install "jointattention[gym]"``).
"""

from __future__ import annotations

from pathlib import Path
from typing import ClassVar

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from .._checks import check_int, short_repr
from ..config import Config, load_config, with_n_objects
from ..errors import ArgumentError, ConfigError
from ..experiment.cells import evaluator
from ..experiment.trial import END_STEPS, SceneTrial
from ..world.recording import capture_face_window
from ..world.scene import sample_caregiver, sample_scene, with_new_distractors
from ..world.simulator import World

__all__ = ["JointAttentionEnv"]

REWARDS = ("external", "intrinsic")
DETECTION_FIELDS = ("centre_px", "colour_area_px", "edge", "motion")


def _action(action) -> np.ndarray:
    """``action`` as 2 finite floats (pan, tilt), else one error naming it."""
    try:
        a = None if np.iscomplexobj(action) else np.asarray(action, dtype=float)
    except (TypeError, ValueError):
        a = None
    if a is None or a.shape != (2,) or not np.all(np.isfinite(a)):
        raise ArgumentError(f"action={short_repr(action)}: expected 2 finite numbers (pan, tilt) "
                            "in radians")
    return a


class JointAttentionEnv(gym.Env):
    """One trial of the joint-attention task per episode, seen through the robot's camera.

    A caregiver sits in front of the robot and looks at one of ``n_objects`` bright objects
    (its target). Each episode is a new scene; the robot's head starts looking at the
    caregiver's face and the agent turns the head step by step. The scene is rendered with
    MuJoCo; the caregiver's identity (head size, colours) is drawn at each seeded reset and
    kept until the next one. With ``n_poses``, the caregiver's pose and target come from a
    pool of that many drawn at the seeded reset (the paper's robot learned from 125 recorded
    data sets); the other objects are drawn anew each episode.

    **Observation** (``Dict``):
      - ``"image"``: the robot's camera image, ``Box(0, 255, (H, W, 3), uint8)`` (H, W from
        ``world.camera``; 240 x 320 by default).
      - ``"head_angle"``: (pan, tilt) in radians, ``Box(joint limits, (2,), float32)``.

    **Action**: the head angle change (pan, tilt) in radians,
    ``Box(-max_step_rad, max_step_rad, (2,), float32)``, where ``max_step_rad`` = the visual
    controller's largest command (paper Eq. 2: gain x half the image width / height). Actions
    outside the box are clipped to it; the head stops at its joint limits.

    **Episode end**:
      - terminated when the internal evaluator fires (paper Eq. 3: an object within
        ``d_th = W x d_th_fraction`` of the image centre) or when a step hits a joint limit;
      - truncated after ``max_steps`` steps (``agent.max_steps``, 40 by default).
      Objects are kept clear of the face, so the evaluator never fires at reset.

    **Reward** (``reward=``), given at the step that ends the episode, else 0:
      - ``"external"``: 1 if joint attention was achieved, i.e. the object at the image centre
        is the caregiver's target;
      - ``"intrinsic"``: 1 if the internal evaluator fired, whichever object it was.
      The other one is in ``info["external_reward"]`` / ``info["intrinsic_reward"]``.

    **Info**: ``"detections"``: what the salient feature detector reports for the current
    image (computed by projection), as a dict of the arrays of
    :class:`~jointattention.agent.detections.Detections` (``Detections(**d, image_size_px=(W,
    H))`` rebuilds it); ``"seen"``, the index in them of the detection the evaluator fired
    on (-1 if none); ``"limit_hit"``, ``"fired"``, ``"attended"`` (object id at the centre,
    -1 if none), ``"target"`` (the caregiver's target; experimenter's knowledge, not the
    robot's), and both rewards.

    The episode's step is the trial loop's step function
    (:class:`~jointattention.experiment.trial.SceneTrial`); an agent written for the trial
    loop runs through the environment with :class:`~jointattention.env.EnvTrial`.

    Args:
        config: a :class:`~jointattention.config.Config`, a preset name or a TOML file
            (default: the built-in defaults); its ``world`` and ``agent`` sections are used.
        n_objects: objects in each scene (default: ``world.objects.n_objects``).
        n_poses: size of the pool of caregiver poses and targets (default: None, a new pose
            every episode).
        reward: ``"external"`` (default) or ``"intrinsic"``.
        max_steps: steps before truncation, 1 to 100,000 (default: ``agent.max_steps``).

    Arguments of the wrong type or out of range raise
    :class:`~jointattention.errors.ConfigError` naming the argument; a malformed action
    (not 2 finite numbers) or reset options raise :class:`~jointattention.errors.ArgumentError`.
        render_mode: ``None`` or ``"rgb_array"`` (an overview of the room).

    Version 0: first release.
    """

    metadata: ClassVar[dict] = {"render_modes": ["rgb_array"], "render_fps": 5}

    def __init__(self, config: Config | str | Path | None = None, *, n_objects: int | None = None,
                 n_poses: int | None = None, reward: str = "external",
                 max_steps: int | None = None, render_mode: str | None = None, **unknown):
        if unknown:
            raise ConfigError(f"{sorted(unknown)[0]}=...: unknown argument; expected config, "
                              "n_objects, n_poses, reward, max_steps, render_mode")
        if not isinstance(config, (Config, str, Path, type(None))):
            raise ConfigError(f"config={config!r}: expected a Config, a preset name, a TOML "
                              "file or None")
        cfg = config if isinstance(config, Config) else load_config(config)
        if not isinstance(reward, str) or reward not in REWARDS:
            raise ConfigError(f"reward={reward!r}: expected one of {', '.join(REWARDS)}")
        if render_mode not in (None, *self.metadata["render_modes"]):
            raise ConfigError(f"render_mode={render_mode!r}: expected None or 'rgb_array'")
        if n_objects is not None:
            cfg = with_n_objects(cfg, check_int("n_objects", n_objects, 1, 20))
        self.n_poses = None if n_poses is None else check_int("n_poses", n_poses, 1, 100_000)
        self.max_steps = (cfg.agent.max_steps if max_steps is None
                          else check_int("max_steps", max_steps, 1, 100_000))
        self.config, self.reward, self.render_mode = cfg, reward, render_mode
        self._world = World(cfg.world)
        kin = self._world.kinematics
        limits = np.array([kin.pan_limits_rad, kin.tilt_limits_rad], dtype=np.float32)
        self.observation_space = spaces.Dict({
            "image": spaces.Box(0, 255, (kin.height_px, kin.width_px, 3), np.uint8),
            "head_angle": spaces.Box(limits[:, 0], limits[:, 1], (2,), np.float32),
        })
        high = self.max_step_rad.astype(np.float32)
        self.action_space = spaces.Box(-high, high, (2,), np.float32)
        self._caregiver = None
        self._poses: list = []
        self._trial: SceneTrial | None = None
        self._evaluate = evaluator(cfg)

    @property
    def max_step_rad(self) -> np.ndarray:
        """The visual controller's largest (pan, tilt) command: Eq. 2 at the image border."""
        kin = self._world.kinematics
        return self.config.agent.vf_gain_rad_per_px * np.array([kin.width_px, kin.height_px]) / 2

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        """Start an episode: a new scene, the head looking at the caregiver's face.

        ``seed``: None or an integer >= 0. ``options``: none are taken (None or {}).
        """
        if seed is not None:
            check_int("seed", seed, 0, 2**63 - 1, ArgumentError)
        if options:
            raise ArgumentError(f"options={options!r}: expected None; this environment takes "
                                "no reset options")
        super().reset(seed=seed)
        world, rng = self.config.world, self.np_random
        if seed is not None or self._caregiver is None:
            self._caregiver = sample_caregiver(world, rng)
            self._poses = [sample_scene(world, rng, self._caregiver)
                           for _ in range(self.n_poses or 0)]
        if self._poses:
            pose = self._poses[rng.integers(len(self._poses))]
            state = with_new_distractors(pose, world, rng)
        else:
            state = sample_scene(world, rng, self._caregiver)
        self._world.set_scene(state)
        kin = self._world.kinematics
        self._trial = SceneTrial(self._world.fast_scene(), kin.clip(self._world.face_angle_rad),
                                 kinematics=kin, max_steps=self.max_steps,
                                 evaluate=self._evaluate)
        return self._look()

    def step(self, action):
        """Turn the head by ``action`` (clipped to the action space), look, evaluate."""
        trial = self._trial
        if trial is None or trial.end is not None:
            raise gym.error.ResetNeeded("no episode is running; expected reset() before step()")
        high = self.max_step_rad
        trial.step(np.clip(_action(action), -high, high))
        obs, info = self._look()
        terminated = trial.end is not None and trial.end != END_STEPS
        truncated = trial.end == END_STEPS
        return obs, info[f"{self.reward}_reward"], terminated, truncated, info

    def _look(self):
        """The observation and info at the trial's current head angle (rendered)."""
        trial = self._trial
        self._world.set_head_angle(trial.theta_rad)
        det, fired = trial.detections, trial.seen is not None
        obs = {"image": self._world.render(),
               "head_angle": trial.theta_rad.astype(np.float32)}
        info = {"detections": {f: getattr(det, f) for f in DETECTION_FIELDS}, "fired": fired,
                "seen": -1 if trial.seen is None else trial.seen,
                "attended": trial.attended, "target": trial.target, "limit_hit": trial.limit_hit,
                "intrinsic_reward": float(fired),
                "external_reward": float(fired and trial.attended == trial.target)}
        return obs, info

    def face_window(self, image: np.ndarray) -> np.ndarray:
        """The grayscale face window (``world.face_window`` size) cut from ``image``.

        ``image`` must be taken at the current head angle.
        """
        return capture_face_window(self._world, image)

    def render(self):
        """With ``render_mode="rgb_array"``, the room from the experimenter's camera."""
        if self.render_mode == "rgb_array":
            return self._world.render("overview")
        return None

    def close(self):
        """Free the renderer."""
        self._world.close()
