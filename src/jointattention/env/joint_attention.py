"""The Gymnasium environment ``JointAttention-v2`` (and v1): one trial per episode.

Its docstring is its manual. Needs the ``gym`` extra (``pip install "jointattention[gym]"``).
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import ClassVar

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from .._checks import check_int, short_repr
from ..config import Config, load_config
from ..datasets import CaregiverDatasets
from ..errors import ArgumentError, ConfigError, DatasetError
from ..experiment.cells import datasets_of, evaluator, random_scene
from ..experiment.trial import END_STEPS, SceneTrial
from ..world.fast import FastScene
from ..world.kinematics import HeadKinematics
from ..world.options import N_OBJECTS
from ._args import EpisodePickle, check_action, check_seed, env_config, refuse_options
from ._fast_trial import FastSteps, FastTrial
from ._observation import OBS_MODES, detection_rows, info_of, observation_space, scaled

__all__ = ["CAREGIVERS", "JointAttentionEnv", "split_datasets"]

REWARDS = ("external", "intrinsic")
# the splits of caregivers=..., and the held-out kinds (experiment.held_out.KINDS) they serve
CAREGIVERS = ("training", "new-poses", "unseen")
_KINDS = {"new-poses": "new poses", "unseen": "unseen caregivers"}
RENDER_MODES = (None, "rgb_array", "human")
_ARGS = ("config", "obs_mode", "n_objects", "n_poses", "reward", "max_steps", "width",
         "height", "render_quality", "normalize_actions", "scaled_obs", "render_mode",
         "caregivers")


def needs_pygame() -> None:
    """``render_mode="human"`` shows its frames with pygame: one ConfigError if it is missing."""
    import importlib.util

    if importlib.util.find_spec("pygame") is None:  # found, not imported: no banner yet
        raise ConfigError('render_mode=\'human\': needs pygame, which is not installed; '
                          'expected the human extra: pip install "jointattention[human]"')


def check_caregivers(caregivers) -> str:
    """``caregivers`` if it names a split (:data:`CAREGIVERS`), else one ArgumentError."""
    if not isinstance(caregivers, str) or caregivers not in CAREGIVERS:
        raise ArgumentError(f"caregivers={short_repr(caregivers)}: expected one of "
                            f"{', '.join(map(repr, CAREGIVERS))}")
    return caregivers


def split_datasets(config: Config, caregivers: str) -> CaregiverDatasets:
    """The data sets of split ``caregivers`` (:data:`CAREGIVERS`) of ``config``'s run.

    ``"training"``: the run's training sets (:func:`~jointattention.experiment.cells.datasets_of`);
    ``"new-poses"`` and ``"unseen"``: its held-out sets of new poses of the training caregivers
    and of caregivers no training set holds
    (:func:`~jointattention.experiment.held_out.held_out_sets`: the shipped ones for the
    shipped training sets, else the configuration's files or a recording of the world's
    held-out stream). Training sets a robot recorded have held-out sets only as files: without
    them, one ConfigError.
    """
    if check_caregivers(caregivers) == "training":
        return datasets_of(config)
    from ..experiment.held_out import held_out_sets  # only the held-out splits need it

    kind = _KINDS[caregivers]
    sets = held_out_sets(config)
    if kind not in sets:
        field = "poses" if caregivers == "new-poses" else "caregivers"
        raise ConfigError(f"caregivers={caregivers!r}: the training sets name no simulated "
                          f"caregiver, so no {kind} can be recorded; expected a data-set file "
                          f"in experiment.held_out.{field}")
    return sets[kind]


class JointAttentionEnv(gym.Env, EpisodePickle):
    """One trial of the joint-attention task per episode, seen by the robot.

    A caregiver sits in front of the robot and looks at one of ``n_objects`` bright objects
    (its target). Each episode is a new scene; the robot's head starts looking at the
    caregiver's face and the agent turns the head step by step.

    **Observation modes** (``obs_mode``), each a ``Dict`` with ``"head_angle"``, (pan, tilt)
    in radians, ``Box(joint limits, (2,), float32)``:
      - ``"image"``: ``"image"``, the robot's camera image rendered with MuJoCo,
        ``Box(0, 255, (height, width, 3), uint8)`` (240 x 320 by default). The room's
        caregiver identity is drawn at each seeded reset; with ``n_poses`` the poses and
        targets come from a pool of that many drawn then, else a new one every episode.
        Rendering needs ``MUJOCO_GL`` set (``egl`` or ``osmesa``) before Python starts.
      - ``"face"``: ``"face"``, the caregiver's grayscale face window,
        ``Box(0, 255, (25, 30), uint8)``; nothing is rendered. Each episode is one of the
        caregiver data sets (``config.datasets``, by default the 125 shipped) with random
        distractors: the fast world in which ``jointattention reproduce`` learns.
      - ``"detections"``: as ``"face"``, plus ``"detections"``, what the salient feature
        detector reports: ``Box(low, high, (20, 6), float32)``, a row per object in view
        (columns ``present, centre_x_px, centre_y_px, colour_area_px, edge, motion``; image
        pixels, x right, y down), zero rows after them. Bounds per column: ``present`` 0 or
        1, centres within the image (-0.5 to W - 0.5, -0.5 to H - 0.5), areas 0 to 4 images
        (clipped there), ``edge`` and ``motion`` 0 to 1.

    With ``scaled_obs=True`` (the v2 ids) every entry is near [-1, 1], which RL libraries'
    default networks need (PPO with Stable-Baselines3's defaults learns v2, not v1): the
    face is ``float32`` grey levels / 255 - 0.5, ``Box(-0.5, 0.5)``; the head angle is scaled
    by the joint ranges, ``Box(-1, 1)``; the detections' centres are offsets from the image
    centre in half image sizes, ``[-1, 1]``, and their areas are in images, ``[0, 4]``. The
    ``"image"`` stays uint8 (the libraries scale images themselves).

    **Action**: the head angle change (pan, tilt) in radians,
    ``Box(-max_step_rad, max_step_rad, (2,), float32)``, where ``max_step_rad`` is the visual
    controller's largest command (paper Eq. 2: gain x half the image width / height); with
    ``normalize_actions=True``, ``Box(-1, 1)`` in units of ``max_step_rad``. Actions outside
    the box are clipped to it; the head stops at its joint limits.

    **Episode end**:
      - terminated when the internal evaluator fires (paper Eq. 3: an object within
        ``d_th = W x d_th_fraction`` of the image centre) or when a step hits a joint limit;
      - truncated after ``max_steps`` steps (40 by default, the registration's
        ``max_episode_steps``). Objects are kept clear of the face, so the evaluator never
        fires at reset.

    **Reward** (``reward=``), given at the step that ends the episode, else 0:
      - ``"external"``: 1 if joint attention was achieved, i.e. the object at the image centre
        is the caregiver's target;
      - ``"intrinsic"``: 1 if the internal evaluator fired, whichever object it was.
      The other one is in ``info["external_reward"]`` / ``info["intrinsic_reward"]``.
      An episode's return is therefore 0 or 1, and the mean return is the success rate.
      Each v2 and v3 id's ``spec.reward_threshold`` says when it is solved: 0.9 times the
      oracle gaze-line follower's mean return at the id's object count (5 where the id names
      none) and reward, in the fast world of the default configuration
      (:data:`~jointattention.env.REWARD_THRESHOLDS`; the intrinsic reward's oracle fires
      every time, so those ids are solved at 0.9).

    **Caregivers** (``caregivers=``), the split of a held-out evaluation:
      - ``"training"`` (default): the training caregivers, as always: in the modes without
        images the run's training sets (``config.datasets``, by default the 125 shipped); in
        ``"image"`` mode a caregiver identity drawn at each seeded reset.
      - ``"new-poses"``: new poses of the training caregivers; ``"unseen"``: caregivers that no
        training set holds, drawn from the world's held-out stream. In the modes without
        images, each episode is one of the run's held-out sets of that kind
        (:func:`~jointattention.experiment.held_out.held_out_sets`: for the shipped training
        sets the shipped ``held_out_poses.npz`` (250 sets) and ``held_out_caregivers.npz``
        (400 sets, 16 caregivers); for other training sets the files of
        ``[experiment.held_out]`` or a recording of the world's held-out stream, made once).
        In ``"image"`` mode, each scene (or each pose of the ``n_poses`` pool) is posed by
        one of the people who posed those sets, in a new pose.
      The split changes nothing else: the same spaces, distractors, steps and rewards.

    **Info**, the same keys and shapes at every step: ``"detections"``, the detector's report
    as a dict of the arrays of :class:`~jointattention.agent.detections.Detections` padded to
    20 rows, and ``"n_detections"``, how many rows are objects
    (:func:`jointattention.env.detections_of` rebuilds it); ``"seen"``, the row the evaluator
    fired on (-1 if none); ``"limit_hit"``, ``"fired"``, ``"attended"`` (object id at the
    centre, -1 if none), ``"target"`` (the caregiver's target: the experimenter's knowledge,
    not the robot's), both rewards, and ``"caregiver_error_rad"``, how far from her target the
    robot looked as she sees it (the angle at the head between the attended object and her
    target; -1 until the evaluator fires), which the developmental model's caregiver grades.

    The episode's step is the trial loop's step function
    (:class:`~jointattention.experiment.trial.SceneTrial`); an agent written for the trial
    loop runs through the environment with :class:`~jointattention.env.EnvTrial`.

    Args:
        config: a :class:`~jointattention.config.Config`, a preset name or a TOML file
            (default: the built-in defaults); its ``world``, ``agent`` and ``datasets``.
        obs_mode: ``"image"`` (default), ``"face"`` or ``"detections"``.
        n_objects: objects in each scene, 1 to 20 (default 5).
        n_poses: ``"image"`` mode: the size of the pool of caregiver poses (default: None, a
            new pose every episode).
        reward: ``"external"`` (default) or ``"intrinsic"``.
        max_steps: steps before truncation, 1 to 100,000 (default: ``agent.max_steps``, 40).
        width, height: ``"image"`` mode: the image size in pixels, 16 to 4096 (default:
            ``world.camera``, 320 x 240).
        render_quality: ``"image"`` mode: ``"full"`` (default), as ``world.camera`` says
            (the look of the shipped data sets' faces), or ``"fast"``, about 2.5x the steps on
            a CPU: no multisampling and 16 x 8 facets per sphere
            (``world.options.FAST_CAMERA``).
        normalize_actions: actions in [-1, 1] (default: False, radians).
        scaled_obs: observations scaled near [-1, 1] (default: False, raw; see above).
        render_mode: ``None``, ``"rgb_array"`` (``"image"`` mode: an overview of the room;
            the other modes: the face window, as RGB) or ``"human"``: the same frames in a
            window, shown at every reset and step (``render_fps`` 5), which needs pygame: the
            ``human`` extra (``pip install "jointattention[human]"``). Without a screen (none
            of ``DISPLAY``, ``WAYLAND_DISPLAY``, ``SDL_VIDEODRIVER`` set) nothing is shown.
        caregivers: which caregivers the episodes show (see **Caregivers** above):
            ``"training"`` (default), ``"new-poses"`` or ``"unseen"``.

    Arguments of the wrong type or out of range raise
    :class:`~jointattention.errors.ConfigError` naming the argument; a malformed action (not 2
    finite numbers), seed or reset options raise
    :class:`~jointattention.errors.ArgumentError`. The environment pickles and deep-copies at
    any time, and a copy continues the episode: the same actions give it the same
    observations, rewards and ends as the original (:class:`~._args.EpisodePickle`).

    Versions: v0, first release (``info["detections"]`` had one row per object in view, so
    vector environments could not stack it). v1: observation modes, ``info`` of fixed shape,
    ``width``/``height``, ``normalize_actions``, ``max_episode_steps`` registered, variants,
    the native vector environment (:mod:`jointattention.env.vector`), argument errors, reset
    options refused, pickling. v2: ``scaled_obs=True``; v1 is kept as it was. v3 (the
    image ids alone): v2 with ``render_quality="fast"``.
    """

    metadata: ClassVar[dict] = {"render_modes": ["rgb_array", "human"], "render_fps": 5}

    def __init__(self, config: Config | str | Path | None = None, *, obs_mode: str = "image",
                 n_objects: int | None = None, n_poses: int | None = None,
                 reward: str = "external", max_steps: int | None = None,
                 width: int | None = None, height: int | None = None,
                 render_quality: str = "full", normalize_actions: bool = False,
                 scaled_obs: bool = False, render_mode: str | None = None,
                 caregivers: str = "training", **unknown):
        if unknown:
            raise ConfigError(f"{sorted(unknown)[0]}=...: unknown argument; expected one of "
                              f"{', '.join(_ARGS)}")
        check_caregivers(caregivers)
        EpisodePickle.__init__(self, config, obs_mode=obs_mode, n_objects=n_objects,
                               n_poses=n_poses, reward=reward, max_steps=max_steps, width=width,
                               height=height, render_quality=render_quality,
                               normalize_actions=normalize_actions,
                               scaled_obs=scaled_obs, render_mode=render_mode,
                               caregivers=caregivers)
        cfg = env_config(config, obs_mode, width, height, render_quality)
        self.n_objects = N_OBJECTS if n_objects is None else check_int("n_objects", n_objects,
                                                                       1, 20)
        for name, value, choices in (("obs_mode", obs_mode, OBS_MODES),
                                     ("reward", reward, REWARDS),
                                     ("render_mode", render_mode, RENDER_MODES)):
            if not isinstance(value, (str, type(None))) or value not in choices:
                raise ConfigError(f"{name}={value!r}: expected one of "
                                  f"{', '.join(map(repr, choices))}")
        if render_mode == "human":
            needs_pygame()
        for name, value in (("normalize_actions", normalize_actions),
                            ("scaled_obs", scaled_obs)):
            if not isinstance(value, bool):
                raise ConfigError(f"{name}={value!r}: expected True or False")
        if obs_mode != "image" and n_poses is not None:
            raise ConfigError(f"obs_mode={obs_mode!r}: draws its poses from the data sets; "
                              "expected n_poses=None")
        self.n_poses = None if n_poses is None else check_int("n_poses", n_poses, 1, 100_000)
        self.max_steps = (cfg.agent.max_steps if max_steps is None
                          else check_int("max_steps", max_steps, 1, 100_000))
        self.config, self.obs_mode, self.reward = cfg, obs_mode, reward
        self.render_mode, self.normalize_actions = render_mode, normalize_actions
        self.scaled_obs, self.caregivers = scaled_obs, caregivers
        self.kinematics = HeadKinematics.from_config(cfg.world)
        kin = self.kinematics
        self._world = self._datasets = self._people = None
        if obs_mode == "image":
            from ..world.simulator import World  # MuJoCo only where it renders

            if caregivers != "training":  # the split's people, from the sets of the config
                self._people = _people_of(config if isinstance(config, Config)
                                          else load_config(config), caregivers)
            self._world = World(cfg.world, n_objects=self.n_objects)
        else:
            self._datasets = split_datasets(cfg, caregivers)
        face_hw = (cfg.world.face_window.height_px, cfg.world.face_window.width_px)
        if self._datasets is not None:
            face_hw = self._datasets.face.shape[1:]
        self.joint_limits_rad = np.array([kin.pan_limits_rad, kin.tilt_limits_rad])
        self.observation_space = observation_space(obs_mode, (kin.height_px, kin.width_px),
                                                   face_hw, self.joint_limits_rad, scaled_obs)
        high = np.ones(2) if normalize_actions else self.max_step_rad
        self.action_space = spaces.Box(-high.astype(np.float32), high.astype(np.float32), (2,),
                                       np.float32)
        self._caregiver, self._poses, self._face, self._scene_state = None, [], None, None
        self._window = None  # render_mode="human": pygame's window, opened at the first frame
        self._trial: SceneTrial | FastTrial | None = None
        self._evaluate = evaluator(cfg)
        # a step's clip and scale as Python numbers: numpy's calls cost more than the step
        self._moves = (*self.action_space.low.tolist(), *self.action_space.high.tolist(),
                       *(self.max_step_rad.tolist() if normalize_actions else (1.0, 1.0)))
        # the modes without images step in one compiled call (._fast_trial); their generator
        # goes to it in numba's list, made again when the generator changes
        self._fast = None if self._datasets is None else FastSteps(self)
        self._rng_list = (None, None)

    @property
    def max_step_rad(self) -> np.ndarray:
        """The visual controller's largest (pan, tilt) command: Eq. 2 at the image border."""
        kin = self.kinematics
        return self.config.agent.vf_gain_rad_per_px * np.array([kin.width_px, kin.height_px]) / 2

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        """Start an episode: a new scene, the head looking at the caregiver's face.

        ``seed``: None or an integer >= 0. ``options``: none are taken (None or {}).
        """
        check_seed(seed)
        refuse_options(options)
        super().reset(seed=seed)
        if self._fast is not None:  # one kernel draws the scene as _fast_episode does
            self._trial = FastTrial(self._fast, self._rngs())
            self._face = self._datasets.face[self._trial.face_k]
        else:
            if self._world is None:  # the reference (tests): the runner's draw
                k, scene = self._fast_episode(self.np_random)
                self._face, start = self._datasets.face[k], self._datasets.theta_face_rad[k]
            else:
                start = self._new_scene(seeded=seed is not None)
                scene = self._world.fast_scene()
            self._trial = SceneTrial(scene, self.kinematics.clip(start),
                                     kinematics=self.kinematics, max_steps=self.max_steps,
                                     evaluate=self._evaluate)
        out = self._look()
        if self.render_mode == "human":
            self._show()
        return out

    def _rngs(self):
        """The generator in numba's list (sharing its state), as the start kernel takes it."""
        if self._rng_list[0] is not self.np_random:
            from numba.typed import List

            rng = self.np_random
            self._rng_list = rng, List([rng])
        return self._rng_list[1]

    def _fast_episode(self, rng: np.random.Generator) -> tuple[int, FastScene]:
        """The modes without images: a data set's index and its scene with random distractors.

        The runner's own draw (:func:`~jointattention.experiment.cells.random_scene`), which
        :class:`~._fast_trial.FastTrial` draws in one kernel; kept as the reference the tests
        compare the kernels with.
        """
        k, scene, _ = random_scene(self.config, self._datasets, self.kinematics, self.n_objects,
                                   rng)
        return k, scene

    def _new_scene(self, seeded: bool) -> np.ndarray:
        """``"image"`` mode: show a new scene in the room; returns the start head angle.

        ``"training"``: one caregiver per seeded reset poses every scene. A held-out split:
        each pose (each episode's, or each of the ``n_poses`` pool's) draws its caregiver from
        the split's people, so that one seed's episodes show all of them.
        """
        from ..world.scene import sample_caregiver, sample_scene, with_new_distractors

        world, rng, people = self.config.world, self.np_random, self._people

        def poser():
            return self._caregiver if people is None else people[rng.integers(len(people))]

        if seeded or self._caregiver is None:
            if people is None:
                self._caregiver = sample_caregiver(world, rng)
            self._poses = [sample_scene(world, rng, poser(), self.n_objects)
                           for _ in range(self.n_poses or 0)]
        if self._poses:
            state = with_new_distractors(self._poses[rng.integers(len(self._poses))], world, rng)
        else:
            state = sample_scene(world, rng, poser(), self.n_objects)
        self._world.set_scene(state)
        self._scene_state, self._caregiver = state, state.caregiver
        return self._world.face_angle_rad

    def step(self, action):
        """Turn the head by ``action`` (clipped to the action space), look, evaluate."""
        trial = self._trial
        if trial is None or trial.end is not None:
            raise gym.error.ResetNeeded("no episode is running; expected reset() before step()")
        trial.step(self._dtheta_rad(action))
        obs, info = self._look()
        terminated = trial.end is not None and trial.end != END_STEPS
        truncated = trial.end == END_STEPS
        if self.render_mode == "human":
            self._show()
        return obs, info[f"{self.reward}_reward"], terminated, truncated, info

    def _dtheta_rad(self, action) -> tuple[float, float]:
        """The head's move (pan, tilt) in radians for ``action``: checked, clipped, scaled.

        As ``np.clip(action, low, high) * max_step_rad`` in float64, on Python numbers.
        """
        if type(action) is np.ndarray and action.shape == (2,) and action.dtype.char in "fd":
            pan, tilt = action.tolist()  # an RL library's action: checked at little cost
        else:
            pan, tilt = check_action(action).tolist()
        if not (math.isfinite(pan) and math.isfinite(tilt)):
            check_action(action)  # one error naming it
        lo_pan, lo_tilt, hi_pan, hi_tilt, scale_pan, scale_tilt = self._moves
        return (min(max(pan, lo_pan), hi_pan) * scale_pan,
                min(max(tilt, lo_tilt), hi_tilt) * scale_tilt)

    def _look(self):
        """The observation and info at the trial's current head angle."""
        trial = self._trial
        if self._fast is not None:
            return trial.looks()
        obs = {"head_angle": trial.theta_rad.astype(np.float32)}
        if self._world is not None:
            self._world.set_head_angle(trial.theta_rad)
            obs["image"] = self._world.render()
        else:
            obs["face"] = self._face.copy()
        if self.obs_mode == "detections":
            obs["detections"] = detection_rows(trial.detections)
        if self.scaled_obs:
            obs = scaled(obs, self.joint_limits_rad, (self.kinematics.height_px,
                                                      self.kinematics.width_px))
        return obs, info_of(trial)

    def face_window(self, image: np.ndarray) -> np.ndarray:
        """``"image"`` mode: the grayscale face window cut from ``image``.

        ``image`` must be taken at the current head angle.
        """
        from ..world.recording import capture_face_window

        return capture_face_window(self._world, image)

    def render(self):
        """With ``render_mode="rgb_array"``: the room, or the face window (modes without images).

        The room is seen from the experimenter's camera; the face window is shown as RGB. With
        ``"human"`` the frames are shown at every reset and step, and this returns None.
        """
        if self.render_mode != "rgb_array":
            return None
        return self._frame()

    def _show(self) -> None:
        """``render_mode="human"``: show the frame in pygame's window, at ``render_fps``."""
        if not any(os.environ.get(k) for k in ("DISPLAY", "WAYLAND_DISPLAY", "SDL_VIDEODRIVER")):
            # No screen to show it on: SDL would pick its EGL "offscreen" driver, whose exit
            # ends the EGL display MuJoCo renders with (and check_env makes every mode).
            return
        import pygame

        frame = self._frame()
        # a face window is 30 x 25 pixels: enlarged whole pixels to about 300 wide
        zoom = max(1, 300 // frame.shape[1])
        frame = np.repeat(np.repeat(frame, zoom, axis=0), zoom, axis=1)
        if self._window is None:
            pygame.display.init()  # the display alone: pygame.init() opens the sound too
            self._window = pygame.display.set_mode((frame.shape[1], frame.shape[0]))
            self._clock = pygame.time.Clock()
        self._window.blit(pygame.surfarray.make_surface(frame.swapaxes(0, 1)), (0, 0))
        pygame.event.pump()
        self._clock.tick(self.metadata["render_fps"])
        pygame.display.flip()

    def _frame(self) -> np.ndarray:
        """The frame ``render`` shows: the room's overview, or the face window as RGB."""
        if self._world is not None:
            return self._world.render("overview")
        face = self._face if self._face is not None else np.zeros(
            self.observation_space["face"].shape, np.uint8)
        return np.repeat(face[..., None], 3, axis=2)

    def close(self):
        """Free the renderer, and close the window of ``render_mode="human"``."""
        if self._world is not None:
            self._world.close()
        if self._window is not None:
            import pygame

            pygame.display.quit()
            self._window = None


def _people_of(config: Config, caregivers: str) -> list:
    """``"image"`` mode: the caregivers who posed split ``caregivers``'s data sets.

    The new poses' people are the training caregivers; the unseen ones, people drawn from the
    world's held-out stream (:data:`~jointattention.world.recording.HELD_OUT`).
    """
    from ..world.recording import caregivers_of

    try:
        return caregivers_of(split_datasets(config, caregivers), config.world)
    except DatasetError as err:
        raise ConfigError(f"caregivers={caregivers!r}: {err}") from None
