"""The Gymnasium environment ``JointAttention-v0``, registered when this module is imported.

Needs the ``gym`` extra (``pip install "jointattention[gym]"``).
"""

from __future__ import annotations

from pathlib import Path
from typing import ClassVar

import numpy as np

try:
    import gymnasium as gym
    from gymnasium import spaces
except ImportError:  # pragma: no cover - depends on the installed extras
    raise ImportError('jointattention.env needs Gymnasium; expected it installed: '
                      'pip install "jointattention[gym]"') from None

from .agent.attention import attended_object
from .agent.detections import Detections
from .config import Config, load_config, with_n_objects
from .errors import ConfigError
from .world.fast import FastScene
from .world.recording import capture_face_window
from .world.scene import sample_caregiver, sample_scene, with_new_distractors
from .world.simulator import World

__all__ = ["ENV_ID", "FaceWindowObservation", "JointAttentionEnv"]

ENV_ID = "JointAttention-v0"
REWARDS = ("external", "intrinsic")
DETECTION_FIELDS = ("centre_px", "colour_area_px", "edge", "motion")


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
    H))`` rebuilds it); ``"limit_hit"``,
    ``"fired"``, ``"attended"`` (object id at the centre, -1 if none), ``"target"``
    (the caregiver's target; experimenter's knowledge, not the robot's), and both rewards.

    Args:
        config: a :class:`~jointattention.config.Config`, a preset name or a TOML file
            (default: the built-in defaults); its ``world`` and ``agent`` sections are used.
        n_objects: objects in each scene (default: ``world.objects.n_objects``).
        n_poses: size of the pool of caregiver poses and targets (default: None, a new pose
            every episode).
        reward: ``"external"`` (default) or ``"intrinsic"``.
        max_steps: steps before truncation (default: ``agent.max_steps``).
        render_mode: ``None`` or ``"rgb_array"`` (an overview of the room).

    Version 0: first release.
    """

    metadata: ClassVar[dict] = {"render_modes": ["rgb_array"], "render_fps": 5}

    def __init__(self, config: Config | str | Path | None = None, *, n_objects: int | None = None,
                 n_poses: int | None = None, reward: str = "external",
                 max_steps: int | None = None, render_mode: str | None = None):
        cfg = config if isinstance(config, Config) else load_config(config)
        if reward not in REWARDS:
            raise ConfigError(f"reward={reward!r}: expected one of {', '.join(REWARDS)}")
        if render_mode not in (None, *self.metadata["render_modes"]):
            raise ConfigError(f"render_mode={render_mode!r}: expected None or 'rgb_array'")
        if n_objects is not None:
            if not 1 <= n_objects <= 20:
                raise ConfigError(f"n_objects={n_objects}: expected 1 to 20")
            cfg = with_n_objects(cfg, n_objects)
        if n_poses is not None and n_poses < 1:
            raise ConfigError(f"n_poses={n_poses}: expected at least 1, or None")
        self.n_poses = n_poses
        self.max_steps = cfg.agent.max_steps if max_steps is None else max_steps
        if self.max_steps < 1:
            raise ConfigError(f"max_steps={max_steps}: expected at least 1")
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

    @property
    def max_step_rad(self) -> np.ndarray:
        """The visual controller's largest (pan, tilt) command: Eq. 2 at the image border."""
        kin = self._world.kinematics
        return self.config.agent.vf_gain_rad_per_px * np.array([kin.width_px, kin.height_px]) / 2

    @property
    def d_th_px(self) -> float:
        """The internal evaluator's radius (Eq. 3)."""
        return self.config.agent.d_th_px(self._world.kinematics.width_px)

    def reset(self, *, seed: int | None = None, options: dict | None = None):
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
        self._scene = FastScene(self._world.kinematics, state.object_pos_m,
                                state.object_radius_m, state.target_index,
                                np.zeros(state.n_objects))
        self._theta = self._world.kinematics.clip(self._world.face_angle_rad)
        self._n_steps = 0
        obs, _, info = self._look(limit_hit=False)
        return obs, info

    def step(self, action):
        dtheta = np.clip(np.asarray(action, dtype=float), -self.max_step_rad, self.max_step_rad)
        wanted = self._theta + dtheta
        self._theta = self._world.kinematics.clip(wanted)
        self._n_steps += 1
        obs, fired, info = self._look(limit_hit=not np.array_equal(self._theta, wanted))
        terminated = fired or info["limit_hit"]
        truncated = not terminated and self._n_steps >= self.max_steps
        return obs, info[f"{self.reward}_reward"], terminated, truncated, info

    def _look(self, limit_hit: bool):
        """Turn the head to the current angle, render, detect and evaluate (Eq. 3)."""
        self._world.set_head_angle(self._theta)
        det: Detections = self._scene.observe(self._theta)
        i = attended_object(det, self.d_th_px)
        fired = i is not None
        attended = int(self._scene.visible_ids[i]) if fired else -1
        target = self._scene.target_index
        obs = {"image": self._world.render(),
               "head_angle": self._theta.astype(np.float32)}
        info = {"detections": {f: getattr(det, f) for f in DETECTION_FIELDS}, "fired": fired,
                "attended": attended, "target": target, "limit_hit": limit_hit,
                "intrinsic_reward": float(fired),
                "external_reward": float(fired and attended == target)}
        return obs, fired, info

    def face_window(self, image: np.ndarray) -> np.ndarray:
        """The grayscale face window (``world.face_window`` size) cropped from ``image``,
        an image taken at the current head angle."""
        return capture_face_window(self._world, image)

    def render(self):
        if self.render_mode == "rgb_array":
            return self._world.render("overview")
        return None

    def close(self):
        self._world.close()


class FaceWindowObservation(gym.ObservationWrapper):
    """Adds ``"face"``: the caregiver's face window (grayscale uint8, 25 x 30 by default), taken
    from the first image of the episode, when the robot looks at the caregiver, and kept for
    the whole episode (as the robot keeps it in the paper's model)."""

    def __init__(self, env: gym.Env):
        super().__init__(env)
        fw = env.unwrapped.config.world.face_window
        self.observation_space = spaces.Dict({
            **env.observation_space.spaces,
            "face": spaces.Box(0, 255, (fw.height_px, fw.width_px), np.uint8),
        })
        self._face: np.ndarray | None = None

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        obs, info = self.env.reset(seed=seed, options=options)
        self._face = self.env.unwrapped.face_window(obs["image"])
        return self.observation(obs), info

    def observation(self, observation):
        return {**observation, "face": self._face.copy()}


gym.register(id=ENV_ID, entry_point="jointattention.env:JointAttentionEnv")
