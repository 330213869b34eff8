"""MuJoCo with an off-screen OpenGL backend: chosen when the first world needs MuJoCo.

MuJoCo picks its OpenGL backend from ``MUJOCO_GL`` when it is first imported, and a
headless machine needs EGL or OSMesa. Nothing happens at import of this package: the first
:func:`mujoco` call sets ``MUJOCO_GL`` (EGL if its library is found, else OSMesa) unless the
user set it, then imports MuJoCo.
"""

from __future__ import annotations

import ctypes.util
import os
import sys
from types import ModuleType

from ..errors import RenderingUnavailable

__all__ = ["choose_backend", "mujoco", "renderer"]

_started_in_pid: int | None = None  # the process that started an OpenGL context


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


def mujoco() -> ModuleType:
    """The ``mujoco`` module, imported after choosing its backend if nobody imported it yet.

    MuJoCo starts its OpenGL backend when imported: a backend that cannot start (OSMesa not
    installed, an unknown ``MUJOCO_GL``) is one :class:`~..errors.RenderingUnavailable` line.
    """
    if "mujoco" not in sys.modules:
        choose_backend()
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
    if _started_in_pid is not None and _started_in_pid != os.getpid():
        raise RenderingUnavailable(
            "cannot render in a process forked after its parent rendered (OpenGL does not "
            "survive fork); expected processes started with spawn or forkserver, e.g. "
            "gymnasium.make_vec(..., vectorization_mode='async', "
            "vector_kwargs={'context': 'spawn'})")
    made = mujoco().Renderer(model, height_px, width_px)
    _started_in_pid = os.getpid()
    return made
