"""MuJoCo and its OpenGL backend, which the user chooses with ``MUJOCO_GL``.

MuJoCo picks its OpenGL backend from ``MUJOCO_GL`` when it is first imported, and a headless
machine needs EGL or OSMesa. The library reads the variable and never writes it: a renderer
asked for while it is unset is one :class:`~jointattention.errors.RenderingUnavailable` line
that says what to set (:func:`backend`). The command line, a program rather than a library,
sets it for its own process when the user did not (:func:`suggested_backend`).
"""

from __future__ import annotations

import ctypes.util
import os
import sys
from types import ModuleType

from ..errors import RenderingUnavailable

__all__ = ["backend", "mujoco", "renderer", "suggested_backend"]

_started_in_pid: int | None = None  # the process that started an OpenGL context


def suggested_backend() -> str:
    """The off-screen backend this machine has: EGL if its library is found, else OSMesa."""
    if ctypes.util.find_library("EGL") or not ctypes.util.find_library("OSMesa"):
        return "egl"  # neither found by name: EGL gives the clearer error later
    return "osmesa"


def backend() -> str:
    """The backend ``MUJOCO_GL`` names; unset, one error line that says what to set."""
    chosen = os.environ.get("MUJOCO_GL", "").strip()
    if not chosen:
        name = suggested_backend()
        raise RenderingUnavailable(
            f"MUJOCO_GL is not set; expected MUJOCO_GL={name} (off-screen: egl needs libegl1, "
            f"osmesa libosmesa6; glfw draws in a window) set before Python starts, e.g. "
            f"`MUJOCO_GL={name} python script.py`; the fast world needs no OpenGL")
    return chosen


def mujoco() -> ModuleType:
    """The ``mujoco`` module (its backend is ``MUJOCO_GL``'s, or none if unset).

    MuJoCo loads its OpenGL backend when imported: a backend that cannot load (OSMesa not
    installed, an unknown ``MUJOCO_GL``) is one :class:`~..errors.RenderingUnavailable` line.
    """
    try:
        import mujoco as module
    except Exception as err:  # the GL stack raises many kinds (AttributeError, RuntimeError...)
        for name in [m for m in sys.modules if m.split(".")[0] in ("mujoco", "OpenGL")]:
            del sys.modules[name]  # half-imported: the next attempt starts again
        raise RenderingUnavailable(
            f"cannot import MuJoCo with MUJOCO_GL={os.environ.get('MUJOCO_GL')!r} "
            f"({type(err).__name__}: {' '.join(str(err).split())}); expected egl (libegl1) or "
            "osmesa (libosmesa6) installed; the fast world needs no OpenGL") from None
    return module


def renderer(model, height_px: int, width_px: int):
    """A MuJoCo renderer; refused in a process forked after its parent started OpenGL.

    EGL and OSMesa do not survive ``fork``: the child's first context hangs (e.g. Gymnasium's
    async vector environment under the default start method).
    """
    global _started_in_pid
    backend()
    if _started_in_pid is not None and _started_in_pid != os.getpid():
        raise RenderingUnavailable(
            "cannot render in a process forked after its parent rendered (OpenGL does not "
            "survive fork); expected processes started with spawn or forkserver, e.g. "
            "gymnasium.make_vec(..., vectorization_mode='async', "
            "vector_kwargs={'context': 'spawn'})")
    made = mujoco().Renderer(model, height_px, width_px)
    _started_in_pid = os.getpid()
    return made
