"""``render_mode="human"``: frames in a pygame window, or one error line naming the extra."""

from __future__ import annotations

import sys
import warnings

import gymnasium as gym
import numpy as np
import pytest

import jointattention.env  # noqa: F401  (registers the environments)
from jointattention.env import JointAttentionEnv
from jointattention.errors import ConfigError


def test_human_mode_without_pygame_is_one_error_naming_the_extra(monkeypatch):
    """Without pygame, render_mode='human' is one ConfigError saying to install the extra."""
    monkeypatch.setitem(sys.modules, "pygame", None)  # the importer finds no pygame
    for make in (lambda: JointAttentionEnv(obs_mode="face", render_mode="human"),
                 lambda: gym.make("JointAttentionFace-N3-v2", render_mode="human")):
        with pytest.raises(ConfigError) as err:
            make()
        line = str(err.value)
        assert line.startswith("render_mode='human'") and "\n" not in line
        assert 'pip install "jointattention[human]"' in line


def test_human_mode_shows_each_frame_in_a_window(monkeypatch):
    """With pygame, reset and step show the frame; render() returns None; close shuts it."""
    pygame = pytest.importorskip("pygame", reason="needs the human extra")
    monkeypatch.setenv("SDL_VIDEODRIVER", "dummy")  # a window without a screen
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # gym.make wraps nothing: the env shows frames itself
        env = gym.make("JointAttentionFace-N3-v2", render_mode="human")
    env.reset(seed=0)
    assert env.unwrapped._window is not None  # reset shows the first frame
    for _ in range(3):
        env.step(np.zeros(2, np.float32))
    assert env.render() is None
    window = env.unwrapped._window
    assert window.get_size() == (300, 250)  # the 30 x 25 face window, enlarged 10 times
    assert np.ptp(pygame.surfarray.array3d(window)) > 0
    env.close()
    assert env.unwrapped._window is None


def test_the_native_vector_env_refuses_human_mode():
    """make_vec(..., render_mode='human') on the native env: one error naming render_mode."""
    with pytest.raises(ConfigError, match="render_mode='human'"):
        gym.make_vec("JointAttentionFace-v2", num_envs=2, vectorization_mode="vector_entry_point",
                     render_mode="human")


def test_human_mode_without_a_screen_opens_no_window(monkeypatch):
    """No DISPLAY, WAYLAND_DISPLAY or SDL_VIDEODRIVER: reset and step open no window."""
    pytest.importorskip("pygame", reason="needs the human extra")
    for name in ("DISPLAY", "WAYLAND_DISPLAY", "SDL_VIDEODRIVER"):
        monkeypatch.delenv(name, raising=False)
    env = gym.make("JointAttentionFace-N3-v2", render_mode="human")
    env.reset(seed=0)
    env.step(np.zeros(2, np.float32))
    assert env.unwrapped._window is None
    env.close()
