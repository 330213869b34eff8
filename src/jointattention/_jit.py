"""The one place where functions are compiled (numba): the same options for every kernel.

numba itself is imported at the first use of a kernel (:func:`jit`). Kernels are compiled once
per machine and kept in a cache (``jit`` is ``numba.njit`` with
``cache=True``). numba checks only the defining file of a cached function, not the kernels
it calls from other modules, so the cache lives in a folder named by a hash of the package's
sources: ``$NUMBA_CACHE_DIR/jointattention-<hash>``, by default under ``~/.cache``. A changed
kernel anywhere gets a fresh cache instead of stale machine code.

``error_model="numpy"`` divides by zero as numpy does (inf or NaN, no exception). No
``fastmath``: the compiled engine and the step-by-step path call the same kernels, and must
round alike.
"""

from __future__ import annotations

import functools
import hashlib
import os
import sys
from functools import cache
from pathlib import Path

__all__ = ["cache_dir", "jit"]

_TOP = __name__.rpartition(".")[0]
_njit = None  # numba's decorator, once numba is imported
_waiting: list[_Kernel] = []  # kernels defined before numba was imported


@cache
def cache_dir() -> Path:
    """Where the compiled kernels of this version of the sources are kept."""
    digest = hashlib.sha256()
    package = Path(__file__).parent
    for path in sorted(package.rglob("*.py")):
        digest.update(path.relative_to(package).as_posix().encode())
        digest.update(path.read_bytes())
    base = os.environ.get("NUMBA_CACHE_DIR") or Path(
        os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "numba"
    return Path(base) / f"jointattention-{digest.hexdigest()[:16]}"


def _compile(function):
    """Numba's dispatcher of ``function``, cached in :func:`cache_dir`."""
    import numba

    previous = numba.config.CACHE_DIR
    numba.config.CACHE_DIR = str(cache_dir())  # read when the cache is attached, right here
    try:
        return _njit(function)
    finally:
        numba.config.CACHE_DIR = previous


def _load_numba() -> None:
    """Import numba and give every waiting kernel its dispatcher, in every module holding it.

    A kernel calls another through its module's globals, which numba reads when it compiles
    the caller (at its first call): they must hold dispatchers by then, not :class:`_Kernel`.
    """
    global _njit
    if _njit is not None:
        return
    import numba

    _njit = numba.njit(cache=True, error_model="numpy")
    for kernel in _waiting:
        kernel._dispatcher = _compile(kernel.__wrapped__)
    _waiting.clear()
    for name, module in list(sys.modules.items()):
        if name == _TOP or name.startswith(f"{_TOP}."):
            for attr, value in list(vars(module).items()):
                if isinstance(value, _Kernel):
                    setattr(module, attr, value._dispatcher)


class _Kernel:
    """A kernel defined before numba was imported: the first use of any kernel imports it."""

    _dispatcher = None

    def __init__(self, function):
        functools.update_wrapper(self, function)

    def __call__(self, *args, **kwargs):
        _load_numba()
        return self._dispatcher(*args, **kwargs)

    def __getattr__(self, name):  # numba's attributes (stats, py_func, signatures)
        _load_numba()
        return getattr(self._dispatcher, name)


def jit(function):
    """``function`` compiled in nopython mode, cached in :func:`cache_dir`.

    numba is imported at the first call of any kernel, not when a module defines one, so that
    loading a configuration (whose option classes sit beside their kernels) imports no numba.
    """
    if _njit is not None:
        return _compile(function)
    kernel = _Kernel(function)
    _waiting.append(kernel)
    return kernel
