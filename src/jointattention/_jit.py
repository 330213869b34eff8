"""The one place where functions are compiled (numba): the same options for every kernel.

Kernels are compiled once per machine and kept in a cache (``jit`` is ``numba.njit`` with
``cache=True``). numba checks only the defining file of a cached function, not the kernels
it calls from other modules, so the cache lives in a folder named by a hash of the package's
sources: ``$NUMBA_CACHE_DIR/jointattention-<hash>``, by default under ``~/.cache``. A changed
kernel anywhere gets a fresh cache instead of stale machine code.

``error_model="numpy"`` divides by zero as numpy does (inf or NaN, no exception). No
``fastmath``: the compiled engine and the step-by-step path call the same kernels, and must
round alike.
"""

from __future__ import annotations

import hashlib
import os
from functools import cache
from pathlib import Path

import numba

__all__ = ["cache_dir", "jit"]

_njit = numba.njit(cache=True, error_model="numpy")


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


def jit(function):
    """``function`` compiled in nopython mode, cached in :func:`cache_dir`."""
    previous = numba.config.CACHE_DIR
    numba.config.CACHE_DIR = str(cache_dir())  # read when the cache is attached, right here
    try:
        return _njit(function)
    finally:
        numba.config.CACHE_DIR = previous
