"""The environments' arguments and copies: configuration, actions, reset options, pickling."""

from __future__ import annotations

import dataclasses
import math
import numbers
from pathlib import Path
from typing import ClassVar

import numpy as np
from gymnasium.utils import EzPickle

from .._arrays import floats
from .._checks import MAX_INT, check_int, short_repr
from ..config import Config, load_config
from ..errors import ArgumentError, ConfigError
from ..world.options import FAST_CAMERA

__all__ = ["RENDER_QUALITIES", "EpisodePickle", "check_action", "check_seed", "env_config",
           "first_seed", "refuse_options", "vector_seeds"]


def check_action(action, shape: tuple[int, ...] = (2,), name: str = "action") -> np.ndarray:
    """``action`` as finite floats of ``shape`` (pan, tilt last), else one error naming it."""
    if (type(action) is np.ndarray and action.shape == shape == (2,)
            and action.dtype.kind == "f" and math.isfinite(action[0])
            and math.isfinite(action[1])):
        return action.astype(float)  # an RL library's action: checked at little cost
    # not booleans: True/False are no head turn, and NumPy would take them as 1/0 radians
    return floats(name, action, shape, what="numbers (pan, tilt)", kinds="iuf")


def check_seed(seed, name: str = "seed", hi: int = MAX_INT) -> int | None:
    """A reset's seed: None or an integer in [0, ``hi``], else one ArgumentError naming it."""
    return None if seed is None else check_int(name, seed, 0, hi, ArgumentError)


def vector_seeds(seed, n: int) -> list[int | None]:
    """The seeds of ``n`` sub-environments from a vector reset's ``seed``, as SyncVectorEnv's.

    None: none; an integer s: s + i for sub-environment i (so s + n - 1 must fit the
    engine's integers); a list: one seed (an integer or None) per sub-environment.
    """
    if isinstance(seed, (list, tuple)):
        if len(seed) != n:
            raise ArgumentError(f"seed={short_repr(seed)}: {len(seed)} seeds for {n} "
                                f"sub-environments; expected a list of {n} (an integer or None "
                                "each), an integer or None")
        return [check_seed(s, f"seed[{i}]") for i, s in enumerate(seed)]
    first = first_seed(seed, n, f"a list of {n} seeds or None")
    return [None] * n if first is None else [first + i for i in range(n)]


def first_seed(seed, n: int, others: str = "or None") -> int | None:
    """The seed ``s`` of ``n`` sub-environments that take s + i: None or an integer that fits.

    Else one ArgumentError naming the range; ``others`` says what else is taken.
    """
    if seed is None:
        return None
    hi = MAX_INT - (n - 1)
    if isinstance(seed, bool) or not isinstance(seed, numbers.Integral) or not 0 <= seed <= hi:
        raise ArgumentError(f"seed={short_repr(seed)}: expected an integer in [0, {hi}] "
                            f"(sub-environment i takes seed + i), {others}")
    return int(seed)


def refuse_options(options: dict | None) -> None:
    """Reset options: none are taken."""
    if options:
        raise ArgumentError(f"options={short_repr(options)}: expected None; this environment "
                            "takes no reset options")


RENDER_QUALITIES = ("full", "fast")  # "fast": world.options.FAST_CAMERA (docs/gymnasium.md)


def env_config(config, obs_mode, width, height, render_quality="full") -> Config:
    """The environment's configuration: ``config`` with its image size and render quality."""
    if not isinstance(config, (Config, str, Path, type(None))):
        raise ConfigError(f"config={short_repr(config)}: expected a Config, a preset name, "
                          "a TOML file or None")
    cfg = config if isinstance(config, Config) else load_config(config)
    if (width is not None or height is not None) and obs_mode != "image":
        raise ConfigError(f"width/height: the image size of obs_mode='image'; expected None "
                          f"with obs_mode={obs_mode!r}")
    if not isinstance(render_quality, str) or render_quality not in RENDER_QUALITIES:
        raise ConfigError(f"render_quality={short_repr(render_quality)}: expected one of "
                          f"{', '.join(map(repr, RENDER_QUALITIES))}")
    if render_quality != "full" and obs_mode != "image":
        raise ConfigError(f"render_quality: how obs_mode='image' renders; expected 'full' "
                          f"with obs_mode={obs_mode!r}")
    camera = cfg.world.camera
    camera = dataclasses.replace(
        camera, width_px=camera.width_px if width is None else check_int("width", width, 16, 4096),
        height_px=camera.height_px if height is None else check_int("height", height, 16, 4096),
        **(FAST_CAMERA if render_quality == "fast" else {}))
    return dataclasses.replace(cfg, world=dataclasses.replace(cfg.world, camera=camera))


class EpisodePickle(EzPickle):
    """Pickling and deep copies that continue the episode.

    As Gymnasium's MuJoCo environments, a copy is built anew from the constructor's
    arguments (a renderer does not pickle); then the episode is put back: the generator, the
    trial (the scene, the head angle, the step count) and, with images, the room's scene.
    The copy and the original then give the same observations for the same actions.
    """

    _episode: ClassVar[tuple[str, ...]] = ("_np_random", "_np_random_seed", "_trial", "_face",
                                           "_caregiver", "_poses", "_scene_state")

    def __getstate__(self) -> dict:
        return {**super().__getstate__(),
                "episode": {k: getattr(self, k) for k in self._episode if hasattr(self, k)}}

    def __setstate__(self, state: dict) -> None:
        super().__setstate__(state)
        self.__dict__.update(state.get("episode", {}))
        world, scene = getattr(self, "_world", None), getattr(self, "_scene_state", None)
        if world is not None and scene is not None:
            world.set_scene(scene)
