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

Calls between kernels go to a twin compiled without the wrapper that converts Python objects
(``no_cpython_wrapper``): most kernels are only ever called by other kernels, and building their
wrappers was a tenth of a first run's compile (``jointattention bench``: 10.5-10.7 s to
9.0-9.2 s). Neither builds the wrapper for C callers (``no_cfunc_wrapper``), which nothing uses.
The twin compiles one machine code for a constant argument and a variable one, where numba
would compile a version for each constant (``0``, ``False``) that a caller passes (9.0-9.2 s
to 7.6-7.8 s; the compiled cells' rates did not move beyond the machine's noise).

``@jit(inline=True)`` puts a kernel's body into each kernel that calls it (numba's
``inline="always"``, before typing) instead of calling it. numba counts every array a compiled
function is handed in and out (``NRT_incref``, ``NRT_decref``), and its pass that removes such
pairs left nine in the compiled loops' look at every step, around its call of the fast
detector, and nine in each call of the network's command. With the two inlined, 8 paper cells
took 2.34-2.41 s against 2.63-2.66 s (ablation-paper's v0.2-n5-sigmoid; v0.2-n10-const0.9
3.95-4.03 against 4.34-4.37; runs alternated, one after the other). Only small kernels with
few callers: each caller compiles the body again (the first compile did not move with these
two; with the hidden layer's sums and the forward pass inlined too, 10.2-10.4 s against
8.0-9.0).

:func:`specialise` compiles a copy of a kernel whose globals name other kernels: the compiled
engine's loop, once for each set of kernels a model hands it. numba can take kernels as
arguments too, but a function that does misses the cache in every new process (numba tells
two dispatcher types apart by the object, not by the function), and a tuple of kernels is
numba's experimental first-class function type; a copy named for its kernels is cached like
any kernel.
"""

from __future__ import annotations

import functools
import hashlib
import marshal
import os
import sys
import types
from functools import cache
from pathlib import Path

__all__ = ["cache_dir", "jit", "specialise"]

_TOP = __name__.rpartition(".")[0]
_loaded = False  # whether numba is imported and the waiting kernels compiled
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


def _dispatcher(function, wrapped: bool, inline: bool = False):
    """Numba's dispatcher of ``function``, cached in :func:`cache_dir`.

    ``wrapped=False`` compiles machine code without the wrapper that converts Python objects,
    for calls from other kernels only: its cache is a folder of its own, as numba's index does
    not tell the two apart. ``inline``: kernels calling it take in its body.
    """
    import numba

    folder = cache_dir() if wrapped else cache_dir() / "called"
    previous = numba.config.CACHE_DIR
    numba.config.CACHE_DIR = str(folder)  # read when the cache is attached, right here
    try:
        return numba.njit(function, cache=True, error_model="numpy", no_cfunc_wrapper=True,
                          no_cpython_wrapper=not wrapped, inline="always" if inline else "never")
    finally:
        numba.config.CACHE_DIR = previous


def _compile(function, inline: bool = False):
    """A dispatcher for Python's calls whose calls from other kernels go to a wrapperless twin.

    numba types a global by its ``_numba_type_``: here, as the twin. It inlines a kernel
    marked ``inline`` from the global itself, before typing: no twin is made for it.
    """
    python = _dispatcher(function, wrapped=True, inline=inline)
    python.__class__ = _subclasses(type(python))[0]
    return python


@cache
def _subclasses(base: type) -> tuple[type, type]:
    """``base`` for Python's calls, and for its twin's calls from kernels."""
    from numba.core import types

    class PythonDispatcher(base):
        _called = None  # the twin, made when a kernel calling this one is first compiled

        @property
        def _numba_type_(self):
            if self._called is None:
                self._called = _dispatcher(self.py_func, wrapped=False)
                self._called.__class__ = CalledDispatcher
            return types.Dispatcher(self._called)

    class CalledDispatcher(base):
        def get_call_template(self, args, kws):
            """One machine code for constant and variable arguments (``0``, ``i``) alike."""
            return super().get_call_template(
                tuple(types.unliteral(a) for a in args),
                {k: types.unliteral(v) for k, v in kws.items()})

    return PythonDispatcher, CalledDispatcher


def _load_numba() -> None:
    """Import numba and give every waiting kernel its dispatcher, in every module holding it.

    A kernel calls another through its module's globals, which numba reads when it compiles
    the caller (at its first call): they must hold dispatchers by then, not :class:`_Kernel`.
    """
    global _loaded
    if _loaded:
        return
    _loaded = True
    for kernel in _waiting:
        kernel._dispatcher = _compile(kernel.__wrapped__, kernel.inline)
    _waiting.clear()
    for name, module in list(sys.modules.items()):
        if name == _TOP or name.startswith(f"{_TOP}."):
            for attr, value in list(vars(module).items()):
                if isinstance(value, _Kernel):
                    setattr(module, attr, value._dispatcher)


class _Kernel:
    """A kernel defined before numba was imported: the first use of any kernel imports it."""

    _dispatcher = None

    def __init__(self, function, inline: bool = False):
        functools.update_wrapper(self, function)
        self.inline = inline

    def __call__(self, *args, **kwargs):
        _load_numba()
        return self._dispatcher(*args, **kwargs)

    def __getattr__(self, name):  # numba's attributes (stats, py_func, signatures)
        _load_numba()
        return getattr(self._dispatcher, name)


def jit(function=None, *, inline: bool = False):
    """``function`` compiled in nopython mode, cached in :func:`cache_dir`.

    ``@jit`` or ``@jit(inline=True)`` (the kernels calling it take in its body). numba is
    imported at the first call of any kernel, not when a module defines one, so that loading a
    configuration (whose option classes sit beside their kernels) imports no numba.
    """
    if function is None:
        return functools.partial(jit, inline=inline)
    if _loaded:
        return _compile(function, inline)
    kernel = _Kernel(function, inline)
    _waiting.append(kernel)
    return kernel


def _source_bytes(function) -> bytes:
    """The bytes of ``function``'s file, or of its code if it has none (``python -c``)."""
    try:
        return Path(function.__code__.co_filename).read_bytes()
    except OSError:
        return marshal.dumps(function.__code__)


def specialise(kernel, **bound):
    """A copy of ``kernel`` whose global names ``bound`` are the given kernels, compiled.

    Each name is a global of ``kernel``'s module (None there: the kernel prunes the branches
    that call it). The copy is cached under a name of its own, made of the bound kernels'
    modules and names and, for a kernel outside this package (whose sources
    :func:`cache_dir` does not hash), the bytes of its file: a changed kernel of a user's
    model gets a fresh loop too.
    """
    _load_numba()
    # a kernel defined before numba was loaded (held in a tuple, say) is its dispatcher now:
    # bound as one, an inline kernel is inlined
    bound = {name: value._dispatcher if isinstance(value, _Kernel) else value
             for name, value in bound.items()}
    function = kernel.py_func
    digest = hashlib.sha256()
    for name, value in sorted(bound.items()):
        inner = value.py_func
        digest.update(f"{name}={inner.__module__}.{inner.__qualname__};".encode())
        if not inner.__module__.startswith(f"{_TOP}."):
            digest.update(_source_bytes(inner))
    namespace = dict(function.__globals__)
    for name, value in bound.items():
        if name not in namespace:
            raise TypeError(f"{function.__qualname__} has no global {name!r} to bind")
        namespace[name] = value
    copy = types.FunctionType(function.__code__, namespace, function.__name__,
                              function.__defaults__, function.__closure__)
    copy.__qualname__ = f"{function.__qualname__}_{digest.hexdigest()[:12]}"
    copy.__module__, copy.__doc__ = function.__module__, function.__doc__
    return _compile(copy)
