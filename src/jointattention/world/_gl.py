"""Choosing an off-screen OpenGL backend for MuJoCo before it is imported."""

from __future__ import annotations

import ctypes.util
import os

__all__ = ["choose_backend"]


def choose_backend() -> str:
    """Set ``MUJOCO_GL`` to EGL, else OSMesa, unless the user set it; return the choice."""
    if os.environ.get("MUJOCO_GL"):
        return os.environ["MUJOCO_GL"]
    choice = "egl" if ctypes.util.find_library("EGL") else "osmesa"
    if choice == "osmesa" and not ctypes.util.find_library("OSMesa"):
        choice = "egl"  # neither found by name; EGL gives the clearer error later
    os.environ["MUJOCO_GL"] = choice
    # PyOpenGL reads its own platform variable; keep the two in step.
    os.environ.setdefault("PYOPENGL_PLATFORM", choice)
    return choice


choose_backend()
